#pragma once
// The one exception type of the simpli core. Messages name what is wrong: the op, file,
// field and value, so that a filter can forward them to vtkErrorMacro and the CLI can print
// them as a one-line error.
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace simpli {

class Error : public std::runtime_error {
public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

namespace detail {
inline void appendAll(std::ostringstream&) {}
template <typename T, typename... Rest>
void appendAll(std::ostringstream& os, T&& first, Rest&&... rest) {
  os << std::forward<T>(first);
  appendAll(os, std::forward<Rest>(rest)...);
}
} // namespace detail

/// Builds a message from streamable parts: fail("conv2d: input ", shape, " has ", c, " channels").
template <typename... Parts> [[noreturn]] void fail(Parts&&... parts) {
  std::ostringstream os;
  detail::appendAll(os, std::forward<Parts>(parts)...);
  throw Error(os.str());
}

} // namespace simpli

#pragma once
// Warnings: input that is valid but will give a poor result (an extreme depth range, an
// implausible focal length, frames without images). Invalid input is an Error (simpli/error.h);
// a warning lets the work go on and says why its result will be poor, naming the file, the
// field and the value as an error does. Every warning goes through one handler: by default it
// prints "simpli: warning: <message>" on stderr; a program (or a test) may replace it.
#include <functional>
#include <sstream>
#include <string>
#include <utility>

namespace simpli {

using WarningHandler = std::function<void(const std::string& message)>;

/// Installs `handler` for every later warning (all threads) and returns the previous one; an
/// empty handler restores the default (stderr).
WarningHandler setWarningHandler(WarningHandler handler);

/// Sends one warning (one line, no prefix) to the current handler.
void emitWarning(const std::string& message);

/// Builds a message from streamable parts, as fail() does, and emits it.
template <typename... Parts> void warn(Parts&&... parts) {
  std::ostringstream os;
  (os << ... << std::forward<Parts>(parts));
  emitWarning(os.str());
}

} // namespace simpli

#pragma once
// Text quoted from a file in an error message: one line, short, nothing a terminal would act
// on. A mutated or hostile file can hold newlines, escape sequences and megabytes in one field.
#include <string>

namespace simpli::io {

/// `text` with control characters (bytes below 0x20, and 0x7F) shown as '?', cut to
/// `maxLength` characters ("..." marks the cut).
inline std::string excerpt(const std::string& text, std::size_t maxLength = 80) {
  std::string s = text.size() > maxLength ? text.substr(0, maxLength - 3) + "..." : text;
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F)
      c = '?';
  return s;
}

} // namespace simpli::io

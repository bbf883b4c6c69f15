#include "simpli/model/io/image_size.h"

#include "simpli/error.h"

#include <regex>

namespace simpli::io {

namespace {

/// A side's value; more than nine digits is beyond every limit (and beyond an int).
long long sideValue(const std::string& digits) {
  const bool negative = !digits.empty() && digits[0] == '-';
  if (digits.size() - (negative ? 1 : 0) > 9)
    return negative ? -1000000000LL : 1000000000LL;
  return std::stoll(digits);
}

} // namespace

ImageSize parseImageSize(const std::string& text, const std::string& what,
                         const ImageSizeLimits& limits) {
  static const std::regex pattern("^\\s*(-?[0-9]+)\\s*[xX]\\s*(-?[0-9]+)\\s*$");
  std::smatch m;
  if (!std::regex_match(text, m, pattern))
    fail(what, " '", text, "': expected WIDTHxHEIGHT in pixels, e.g. 192x128");
  const long long w = sideValue(m[1].str()), h = sideValue(m[2].str());
  const auto inside = [&](long long v) {
    return v >= limits.minSide && v <= limits.maxSide && v % limits.multiple == 0;
  };
  if (!inside(w) || !inside(h)) {
    if (limits.multiple > 1)
      fail(what, " '", text, "': width and height must be multiples of ", limits.multiple, " in ",
           limits.minSide, "..", limits.maxSide);
    fail(what, " '", text, "': width and height must be in ", limits.minSide, "..", limits.maxSide);
  }
  return {int(w), int(h)};
}

} // namespace simpli::io

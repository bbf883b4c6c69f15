#pragma once
// Line-oriented text parsing for the camera files (COLMAP, RealEstate10K): whitespace-separated
// fields, numbers parsed locale-independently, errors naming file, line, field and value.
#include "io/excerpt.h"
#include "simpli/error.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace simpli::scene {

inline std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream is(line);
  std::string f;
  while (is >> f)
    fields.push_back(f);
  return fields;
}

/// A line or field for an error message (io/excerpt.h): cut to 80 characters, control
/// characters shown as '?'.
inline std::string lineExcerpt(const std::string& line) {
  return io::excerpt(line, 80);
}

/// All lines of a text file (CR stripped), or an error naming the file.
inline std::vector<std::string> readLines(const std::string& path, const char* what) {
  std::ifstream in(path);
  if (!in)
    fail("cannot open ", what, " '", path, "'");
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    lines.push_back(line);
  }
  if (in.bad())
    fail("cannot read ", what, " '", path, "'");
  return lines;
}

/// A finite number; `field` names it in the error ("TX", "fx", ...). Line numbers are 1-based.
inline double parseFinite(const std::string& token, const std::string& path, size_t line,
                          const char* field) {
  double value = 0;
  const char* begin = token.data();
  const char* end = begin + token.size();
  if (begin != end && *begin == '+')
    ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr != end)
    fail(path, " line ", line, ": field ", field, " = '", lineExcerpt(token), "' is not a number");
  if (!std::isfinite(value))
    fail(path, " line ", line, ": field ", field, " = ", token, " is not finite");
  return value;
}

inline long long parseInteger(const std::string& token, const std::string& path, size_t line,
                              const char* field) {
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || ptr != token.data() + token.size())
    fail(path, " line ", line, ": field ", field, " = '", lineExcerpt(token),
         "' is not an integer");
  return value;
}

/// The rest of `line` after its first `n` whitespace-separated fields, without surrounding
/// blanks (for trailing fields that may contain spaces, such as COLMAP image names).
inline std::string restAfterFields(const std::string& line, size_t n) {
  size_t pos = 0;
  for (size_t k = 0; k < n; ++k) {
    pos = line.find_first_not_of(" \t", pos);
    if (pos == std::string::npos)
      return {};
    pos = line.find_first_of(" \t", pos);
    if (pos == std::string::npos)
      return {};
  }
  const size_t first = line.find_first_not_of(" \t", pos);
  if (first == std::string::npos)
    return {};
  const size_t last = line.find_last_not_of(" \t");
  return line.substr(first, last - first + 1);
}

/// True when `token` is a whole number (from_chars syntax, optional leading '+'), no error.
inline bool isNumberToken(const std::string& token) {
  double value = 0;
  const char* begin = token.data();
  const char* end = begin + token.size();
  if (begin != end && *begin == '+')
    ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  return ec == std::errc() && ptr == end && begin != end;
}

/// True when `token` is a whole integer, no error.
inline bool isIntegerToken(const std::string& token) {
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && ptr == token.data() + token.size() && !token.empty();
}

inline bool isCommentOrBlank(const std::string& line) {
  const size_t first = line.find_first_not_of(" \t");
  return first == std::string::npos || line[first] == '#';
}

} // namespace simpli::scene

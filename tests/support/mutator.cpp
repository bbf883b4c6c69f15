// Seeded mutants of valid files (support/mutator.h).
#include "support/mutator.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <exception>
#include <new>
#include <sstream>

namespace simpli::test {

namespace {

// Length fields a parser must not trust: huge, the largest of each width, zero.
const uint64_t kLengths[] = {0,      1,          0x7F,       0xFF,       0x7FFF,
                             0xFFFF, 0x7FFFFFFF, 0xFFFFFFFF, 1ull << 40, 0x7FFFFFFFFFFFFFFF,
                             ~0ull,  1000000,    1u << 20,   65535,      65536};

// What a number token becomes.
const char* const kNumbers[] = {"1e308",
                                "-1e308",
                                "1e-308",
                                "1e-300",
                                "1e300",
                                "nan",
                                "-nan",
                                "inf",
                                "-inf",
                                "0",
                                "-0",
                                "-1",
                                "-2",
                                "0.5",
                                "1e30",
                                "1e-30",
                                "65535",
                                "65536",
                                "2147483647",
                                "2147483648",
                                "-2147483649",
                                "9223372036854775807",
                                "18446744073709551616",
                                "1e9",
                                "abc",
                                "",
                                "1.5.2",
                                "+-1",
                                "0x10"};

bool isNumberChar(char c) {
  return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+' ||
         c == 'e' || c == 'E';
}

// [begin, end) of every maximal run of number characters that holds a digit.
std::vector<std::pair<std::size_t, std::size_t>> numberSpans(const std::string& s) {
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  for (std::size_t i = 0; i < s.size();) {
    if (!isNumberChar(s[i])) {
      ++i;
      continue;
    }
    std::size_t j = i;
    bool digit = false;
    for (; j < s.size() && isNumberChar(s[j]); ++j)
      digit = digit || std::isdigit(static_cast<unsigned char>(s[j]));
    if (digit)
      spans.emplace_back(i, j);
    i = j;
  }
  return spans;
}

std::vector<std::string> splitLines(const std::string& s) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= s.size()) {
    const std::size_t end = s.find('\n', start);
    if (end == std::string::npos) {
      lines.push_back(s.substr(start));
      break;
    }
    lines.push_back(s.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

std::string joinLines(const std::vector<std::string>& lines) {
  std::string s;
  for (std::size_t i = 0; i < lines.size(); ++i)
    s += (i ? "\n" : "") + lines[i];
  return s;
}

// Every value of a document (depth first), for picking one to replace.
void collectValues(nlohmann::json& v, std::vector<nlohmann::json*>& out) {
  out.push_back(&v);
  if (v.is_array() || v.is_object())
    for (auto& child : v)
      collectValues(child, out);
}

} // namespace

uint64_t Mutator::next() {
  uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

std::size_t Mutator::below(std::size_t n) {
  return static_cast<std::size_t>(next() % n);
}

std::string Mutator::mutateBytes(std::string s) {
  const std::size_t n = s.size();
  std::ostringstream kind;
  switch (below(n == 0 ? 1 : 9)) {
  case 0: { // insert bytes (also the only mutation of an empty file)
    const std::size_t at = below(n + 1), count = 1 + below(8);
    std::string bytes;
    for (std::size_t k = 0; k < count; ++k)
      bytes.push_back(static_cast<char>(next()));
    s.insert(at, bytes);
    kind << "insert " << count << " bytes at " << at;
    break;
  }
  case 1: { // truncate
    const std::size_t at = below(n);
    s.resize(at);
    kind << "truncate at " << at << " of " << n;
    break;
  }
  case 2: { // flip bits
    const int flips = 1 + static_cast<int>(below(4));
    for (int k = 0; k < flips; ++k) {
      const std::size_t at = below(n);
      s[at] = static_cast<char>(s[at] ^ (1 << below(8)));
    }
    kind << "flip " << flips << " bits";
    break;
  }
  case 3: { // overwrite with a length field
    const uint64_t value = kLengths[below(sizeof kLengths / sizeof kLengths[0])];
    const int width = below(2) ? 4 : 8;
    const bool big = below(2);
    const std::size_t at = below(n);
    for (int k = 0; k < width && at + k < n; ++k) {
      const int shift = 8 * (big ? width - 1 - k : k);
      s[at + k] = static_cast<char>(value >> shift);
    }
    kind << "length " << value << " (" << width * 8 << "-bit " << (big ? "BE" : "LE") << ") at "
         << at;
    break;
  }
  case 4: { // delete a run
    const std::size_t at = below(n), count = 1 + below(std::min<std::size_t>(n - at, 16));
    s.erase(at, count);
    kind << "delete " << count << " bytes at " << at;
    break;
  }
  case 5: { // duplicate a chunk
    const std::size_t at = below(n), count = 1 + below(std::min<std::size_t>(n - at, 64));
    s.insert(at, s.substr(at, count));
    kind << "duplicate " << count << " bytes at " << at;
    break;
  }
  case 6: { // a random run
    const std::size_t at = below(n), count = 1 + below(std::min<std::size_t>(n - at, 16));
    for (std::size_t k = 0; k < count; ++k)
      s[at + k] = static_cast<char>(next());
    kind << "randomise " << count << " bytes at " << at;
    break;
  }
  case 7: { // set one byte to an extreme
    const std::size_t at = below(n);
    const char values[] = {0, '\x7f', '\x80', '\xff'};
    s[at] = values[below(4)];
    kind << "extreme byte at " << at;
    break;
  }
  default: { // cut in the last quarter (where end markers and trailing tables live)
    const std::size_t at = n - 1 - below(std::max<std::size_t>(1, n / 4));
    s.resize(at);
    kind << "truncate near the end at " << at << " of " << n;
    break;
  }
  }
  kind_ = kind.str();
  return s;
}

std::string Mutator::mutateTokens(const std::string& s) {
  std::vector<std::string> lines = splitLines(s);
  const auto spans = numberSpans(s);
  std::ostringstream kind;
  switch (below(8)) {
  case 0:
  case 1:
  case 2: { // a number replaced (the most telling mutation of a text format)
    if (spans.empty())
      return mutateBytes(s);
    const auto [b, e] = spans[below(spans.size())];
    const char* value = kNumbers[below(sizeof kNumbers / sizeof kNumbers[0])];
    kind << "number '" << s.substr(b, e - b) << "' at " << b << " -> '" << value << "'";
    kind_ = kind.str();
    return s.substr(0, b) + value + s.substr(e);
  }
  case 3: { // a line dropped
    const std::size_t at = below(lines.size());
    lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(at));
    kind << "drop line " << at + 1;
    break;
  }
  case 4: { // a line repeated
    const std::size_t at = below(lines.size());
    lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(at), lines[at]);
    kind << "repeat line " << at + 1;
    break;
  }
  case 5: { // two lines swapped
    const std::size_t a = below(lines.size()), b = below(lines.size());
    std::swap(lines[a], lines[b]);
    kind << "swap lines " << a + 1 << " and " << b + 1;
    break;
  }
  case 6: { // a line emptied or cut in the middle
    const std::size_t at = below(lines.size());
    lines[at] = lines[at].substr(0, below(lines[at].size() + 1));
    kind << "cut line " << at + 1;
    break;
  }
  default: { // a field added to or dropped from a line
    const std::size_t at = below(lines.size());
    std::string& line = lines[at];
    if (below(2) || line.find(' ') == std::string::npos) {
      line += " 1";
      kind << "extra field on line " << at + 1;
    } else {
      line.erase(line.rfind(' '));
      kind << "drop last field of line " << at + 1;
    }
    break;
  }
  }
  kind_ = kind.str();
  return joinLines(lines);
}

std::string Mutator::mutateJsonValue(const std::string& s) {
  nlohmann::json doc = nlohmann::json::parse(s, nullptr, false);
  if (doc.is_discarded())
    return mutateTokens(s);
  std::vector<nlohmann::json*> values;
  collectValues(doc, values);
  nlohmann::json& v = *values[below(values.size())];
  std::ostringstream kind;
  const std::string before = v.dump().substr(0, 40);
  switch (below(12)) {
  case 0:
    v = nullptr;
    break;
  case 1:
    v = below(2) == 0;
    break;
  case 2:
    v = "x";
    break;
  case 3:
    v = nlohmann::json::array({1, 2, 3});
    break;
  case 4:
    v = nlohmann::json::object({{"a", 1}});
    break;
  case 5: {
    const double numbers[] = {1e308, -1e308, 1e-308, -1, 0, 0.5, 2147483648.0, 1e19, -0.0};
    v = numbers[below(sizeof numbers / sizeof numbers[0])];
    break;
  }
  case 6: {
    const int64_t integers[] = {-1,        0,        1, 2, 65535, 65536, 2147483647, -2147483648LL,
                                INT64_MAX, INT64_MIN};
    v = integers[below(sizeof integers / sizeof integers[0])];
    break;
  }
  case 7:
    v = ~0ull; // an unsigned integer above INT64_MAX
    break;
  case 8: { // deep nesting
    nlohmann::json deep = 1;
    for (int k = 0; k < 100; ++k)
      deep = nlohmann::json::array({deep});
    v = deep;
    break;
  }
  case 9: { // a long array
    v = nlohmann::json::array();
    for (int k = 0; k < 10000; ++k)
      v.push_back(k);
    break;
  }
  default: { // a key dropped, renamed or added
    std::vector<nlohmann::json*> objects;
    for (nlohmann::json* p : values)
      if (p->is_object() && !p->empty())
        objects.push_back(p);
    if (objects.empty()) {
      v = "x";
      break;
    }
    nlohmann::json& o = *objects[below(objects.size())];
    auto it = o.begin();
    std::advance(it, static_cast<std::ptrdiff_t>(below(o.size())));
    const std::string key = it.key();
    const int what = static_cast<int>(below(3));
    if (what == 0) {
      o.erase(key);
      kind << "drop key \"" << key << "\"";
    } else if (what == 1) {
      nlohmann::json value = *it;
      o.erase(key);
      o[key + "_x"] = value;
      kind << "rename key \"" << key << "\"";
    } else {
      o["unexpected_key"] = 1;
      kind << "add key";
    }
    kind_ = kind.str();
    return doc.dump();
  }
  }
  kind << "value " << before << " -> " << v.dump().substr(0, 40);
  kind_ = kind.str();
  return doc.dump(below(2) ? -1 : 2);
}

std::string Mutator::binary(const std::string& original) {
  return mutateBytes(original);
}

std::string Mutator::text(const std::string& original) {
  return below(3) == 0 ? mutateBytes(original) : mutateTokens(original);
}

std::string Mutator::json(const std::string& original) {
  switch (below(4)) {
  case 0:
    return mutateBytes(original);
  case 1:
    return mutateTokens(original);
  default:
    return mutateJsonValue(original);
  }
}

MutationCounts runMutants(const std::string& what, uint64_t seed, int count, MutantKind kind,
                          const std::vector<std::string>& corpus,
                          const std::function<void(const std::string& mutant)>& parse) {
  MutationCounts counts;
  Mutator m(seed);
  int failures = 0;
  for (int i = 0; i < count && failures < 5; ++i) {
    const std::string& original = corpus[static_cast<std::size_t>(i) % corpus.size()];
    const std::string mutant = kind == MutantKind::Binary ? m.binary(original)
                               : kind == MutantKind::Text ? m.text(original)
                                                          : m.json(original);
    const std::string name = what + " mutant " + std::to_string(i) + " (seed " +
                             std::to_string(seed) + ", corpus file " +
                             std::to_string(static_cast<std::size_t>(i) % corpus.size()) + ", " +
                             m.lastKind() + ")";
    SCOPED_TRACE(name); // names the mutant in the failures of parse's own assertions
    try {
      parse(mutant);
      ++counts.parsed;
    } catch (const Error& e) {
      const std::string msg = e.what();
      if (msg.empty() || msg.find('\n') != std::string::npos) {
        ADD_FAILURE() << name << ": error message is empty or not one line: " << msg;
        ++failures;
      }
      ++counts.rejected;
    } catch (const std::bad_alloc&) {
      ADD_FAILURE() << name << ": std::bad_alloc instead of a named error";
      ++failures;
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << ": not a simpli::Error: " << e.what();
      ++failures;
    } catch (...) {
      ADD_FAILURE() << name << ": threw something that is not an exception";
      ++failures;
    }
  }
  std::printf("%s: %d mutants, %d parsed, %d rejected with a named error\n", what.c_str(),
              counts.parsed + counts.rejected, counts.parsed, counts.rejected);
  return counts;
}

} // namespace simpli::test

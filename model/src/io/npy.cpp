#include "simpli/model/io/npy.h"

#include "io/excerpt.h"
#include "simpli/error.h"
#include "simpli/model/io/files.h"

#include <cctype>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>

namespace simpli::io {

namespace {

// The header is a Python dict literal such as
//   {'descr': '<f8', 'fortran_order': False, 'shape': (3, 17), }
// This parser accepts exactly the value kinds numpy writes there: strings, True/False and tuples
// of non-negative integers (Python 2 files may suffix them with L).
class HeaderParser {
public:
  HeaderParser(const std::string& text, const std::string& path) : s_(text), path_(path) {}

  void parse() {
    expect('{');
    skipSpace();
    while (peek() != '}') {
      const std::string key = parseString("key");
      expect(':');
      skipSpace();
      if (key == "descr") {
        descr = parseString("'descr'");
      } else if (key == "fortran_order") {
        fortranOrder = parseBool();
      } else if (key == "shape") {
        shape = parseTuple();
      } else {
        fail(path_, ": .npy header has unexpected key '", excerpt(key), "' (header: ", excerpt(s_),
             ")");
      }
      skipSpace();
      if (peek() == ',') {
        ++i_;
        skipSpace();
      } else if (peek() != '}') {
        bad("',' or '}'");
      }
    }
    ++i_;
    skipSpace();
    if (i_ != s_.size())
      bad("end of header");
    if (!descr)
      fail(path_, ": .npy header has no 'descr' (header: ", excerpt(s_), ")");
    if (!fortranOrder)
      fail(path_, ": .npy header has no 'fortran_order' (header: ", excerpt(s_), ")");
    if (!shape)
      fail(path_, ": .npy header has no 'shape' (header: ", excerpt(s_), ")");
  }

  std::optional<std::string> descr;
  std::optional<bool> fortranOrder;
  std::optional<std::vector<size_t>> shape;

private:
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  void skipSpace() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_])))
      ++i_;
  }
  [[noreturn]] void bad(const char* expected) const {
    fail(path_, ": malformed .npy header: expected ", expected, " at character ", i_,
         " (header: ", excerpt(s_), ")");
  }
  void expect(char c) {
    skipSpace();
    if (peek() != c) {
      const char what[] = {'\'', c, '\'', '\0'};
      bad(what);
    }
    ++i_;
  }
  std::string parseString(const char* what) {
    skipSpace();
    const char quote = peek();
    if (quote != '\'' && quote != '"')
      bad(what);
    const size_t end = s_.find(quote, i_ + 1);
    if (end == std::string::npos)
      bad("closing quote");
    std::string value = s_.substr(i_ + 1, end - i_ - 1);
    i_ = end + 1;
    return value;
  }
  bool parseBool() {
    if (s_.compare(i_, 4, "True") == 0) {
      i_ += 4;
      return true;
    }
    if (s_.compare(i_, 5, "False") == 0) {
      i_ += 5;
      return false;
    }
    bad("True or False for 'fortran_order'");
  }
  std::vector<size_t> parseTuple() {
    expect('(');
    std::vector<size_t> dims;
    skipSpace();
    while (peek() != ')') {
      if (!std::isdigit(static_cast<unsigned char>(peek())))
        bad("a non-negative integer in 'shape'");
      size_t value = 0;
      while (std::isdigit(static_cast<unsigned char>(peek()))) {
        const size_t digit = size_t(peek() - '0');
        if (value > (std::numeric_limits<size_t>::max() - digit) / 10)
          fail(path_, ": .npy header 'shape' has a dimension too large (header: ", excerpt(s_),
               ")");
        value = value * 10 + digit;
        ++i_;
      }
      if (peek() == 'L') // Python 2 long
        ++i_;
      dims.push_back(value);
      skipSpace();
      if (peek() == ',') {
        ++i_;
        skipSpace();
      } else if (peek() != ')') {
        bad("',' or ')' in 'shape'");
      }
    }
    ++i_;
    return dims;
  }

  const std::string& s_;
  const std::string& path_;
  size_t i_ = 0;
};

uint64_t readLittleEndian(const unsigned char* p, int bytes) {
  uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i)
    v = (v << 8) | p[i];
  return v;
}

std::string shapeString(const std::vector<size_t>& shape) {
  std::ostringstream os;
  os << '(';
  for (size_t i = 0; i < shape.size(); ++i)
    os << (i ? ", " : "") << shape[i];
  os << (shape.size() == 1 ? ",)" : ")");
  return os.str();
}

} // namespace

NpyArray parseNpy(const unsigned char* bytes, size_t size, const std::string& path) {
  static const unsigned char magic[6] = {0x93, 'N', 'U', 'M', 'P', 'Y'};
  if (size < 10 || std::memcmp(bytes, magic, 6) != 0)
    fail(path, ": not a .npy file (missing the \\x93NUMPY magic)");
  const int major = bytes[6], minor = bytes[7];
  size_t headerStart = 0, headerLength = 0;
  if (major == 1 && minor == 0) {
    headerStart = 10;
    headerLength = size_t(readLittleEndian(bytes + 8, 2));
  } else if ((major == 2 || major == 3) && minor == 0) {
    if (size < 12)
      fail(path, ": .npy header is truncated (file has ", size, " bytes)");
    headerStart = 12;
    headerLength = size_t(readLittleEndian(bytes + 8, 4));
  } else {
    fail(path, ": unsupported .npy format version ", major, ".", minor,
         " (supported: 1.0, 2.0, 3.0)");
  }
  if (headerLength > size - headerStart)
    fail(path, ": .npy header is truncated (header length ", headerLength, " but only ",
         size - headerStart, " bytes follow)");
  std::string header(reinterpret_cast<const char*>(bytes + headerStart), headerLength);
  // numpy pads the header with spaces and ends it with '\n'; keep messages on one line.
  const size_t last = header.find_last_not_of(std::string(" \t\r\n\0", 5));
  header.erase(last == std::string::npos ? 0 : last + 1);

  HeaderParser parser(header, path);
  parser.parse();

  NpyArray array;
  array.descr = *parser.descr;
  array.shape = *parser.shape;
  size_t itemSize = 0;
  if (array.descr == "<f8")
    itemSize = 8;
  else if (array.descr == "<f4")
    itemSize = 4;
  else
    fail(path, ": .npy 'descr' is '", excerpt(array.descr),
         "'; only little-endian float64 ('<f8') and float32 ('<f4') are supported");

  const size_t dataStart = headerStart + headerLength;
  const size_t available = size - dataStart;
  size_t count = 1;
  for (size_t d : array.shape) {
    if (d != 0 && count > std::numeric_limits<size_t>::max() / itemSize / d)
      fail(path, ": .npy data is truncated: 'shape' ", shapeString(array.shape),
           " is larger than any file");
    count *= d;
  }
  if (count * itemSize > available)
    fail(path, ": .npy data is truncated: 'shape' ", shapeString(array.shape), " of '", array.descr,
         "' needs ", count * itemSize, " bytes, file has ", available);

  // Values in file order, then reordered to C order if the file is Fortran-ordered.
  std::vector<double> values(count);
  const unsigned char* p = bytes + dataStart;
  for (size_t i = 0; i < count; ++i) {
    if (itemSize == 8) {
      const uint64_t bits = readLittleEndian(p + 8 * i, 8);
      double v;
      std::memcpy(&v, &bits, 8);
      values[i] = v;
    } else {
      const uint32_t bits = uint32_t(readLittleEndian(p + 4 * i, 4));
      float v;
      std::memcpy(&v, &bits, 4);
      values[i] = v;
    }
  }
  if (*parser.fortranOrder && array.shape.size() > 1) {
    const size_t nd = array.shape.size();
    // Fortran strides: the first index varies fastest.
    std::vector<size_t> fstride(nd, 1);
    for (size_t d = 1; d < nd; ++d)
      fstride[d] = fstride[d - 1] * array.shape[d - 1];
    array.data.resize(count);
    std::vector<size_t> index(nd, 0);
    for (size_t c = 0; c < count; ++c) { // c enumerates C order (last index fastest)
      size_t f = 0;
      for (size_t d = 0; d < nd; ++d)
        f += index[d] * fstride[d];
      array.data[c] = values[f];
      for (size_t d = nd; d-- > 0;) {
        if (++index[d] < array.shape[d])
          break;
        index[d] = 0;
      }
    }
  } else {
    array.data = std::move(values);
  }
  return array;
}

NpyArray readNpy(const std::string& path) {
  const std::vector<unsigned char> bytes = readFileBytes(path, ".npy file");
  return parseNpy(bytes.data(), bytes.size(), path);
}

void writeNpy(const std::string& path, const std::vector<double>& data,
              const std::vector<size_t>& shape) {
  size_t count = 1;
  for (size_t d : shape)
    count *= d;
  if (count != data.size())
    fail("writeNpy '", path, "': shape ", shapeString(shape), " has ", count,
         " elements, data has ", data.size());
  std::string header =
      "{'descr': '<f8', 'fortran_order': False, 'shape': " + shapeString(shape) + ", }";
  // Pad with spaces so that magic + version + length + header + '\n' is a multiple of 64.
  const size_t unpadded = 10 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header.push_back('\n');
  if (header.size() > 65535)
    fail("writeNpy '", path, "': header too long for format 1.0");
  std::vector<unsigned char> bytes = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
  bytes.push_back(static_cast<unsigned char>(header.size() & 0xff));
  bytes.push_back(static_cast<unsigned char>(header.size() >> 8));
  bytes.insert(bytes.end(), header.begin(), header.end());
  for (double v : data) {
    uint64_t bits;
    std::memcpy(&bits, &v, 8);
    for (int i = 0; i < 8; ++i)
      bytes.push_back(static_cast<unsigned char>(bits >> (8 * i)));
  }
  writeFileAtomically(path, bytes.data(), bytes.size());
}

} // namespace simpli::io

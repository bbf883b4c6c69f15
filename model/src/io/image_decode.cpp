// Image files checked and decoded (io/image_decode.h).
#include "io/image_decode.h"

#include "simpli/error.h"
#include "simpli/model/io/files.h"
#include "simpli/model/io/image_header.h"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace simpli::io {

namespace {

uint32_t be32(const unsigned char* p) {
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3];
}

// Chunks (length, type, data, CRC) from the signature to IEND. deflate compresses at most
// 1032:1, so IDAT data much smaller than the declared rows cannot hold them: a corrupt IHDR (or
// a cut file padded with an IEND) is refused before a huge image is allocated for it.
std::string pngTruncation(const unsigned char* b, std::size_t n) {
  constexpr uint64_t kMaxDeflateRatio = 1100; // 1032, with a margin for interlacing
  uint64_t rowBytes = 0, height = 0, idat = 0;
  std::size_t pos = 8;
  while (pos + 8 <= n) {
    const std::size_t length = be32(b + pos);
    const std::string type(reinterpret_cast<const char*>(b + pos + 4), 4);
    const bool letters = std::all_of(type.begin(), type.end(), [](char c) {
      return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
    });
    if (length > 0x7FFFFFFFu || !letters)
      return {}; // not a chunk PNG allows: corrupt, not cut; let the decoder judge the file
    if (n - pos < 12 + length)
      return "PNG chunk '" + type + "' at byte " + std::to_string(pos) + " needs " +
             std::to_string(12 + length) + " bytes, the file ends after " + std::to_string(n - pos);
    if (type == "IHDR" && length >= 13) {
      const unsigned char depth = b[pos + 16], colour = b[pos + 17];
      const int channels = colour == 2 ? 3 : colour == 4 ? 2 : colour == 6 ? 4 : 1;
      rowBytes = 1 + (uint64_t(be32(b + pos + 8)) * channels * depth + 7) / 8;
      height = be32(b + pos + 12);
    }
    if (type == "IDAT")
      idat += length;
    if (type == "IEND") {
      if (idat * kMaxDeflateRatio < rowBytes * height)
        return "PNG declares " + std::to_string(rowBytes * height) + " bytes of rows but holds " +
               std::to_string(idat) + " bytes of image data, more than deflate can compress " +
               "(its header is corrupt or its data cut)";
      return {};
    }
    pos += 12 + length;
  }
  return "PNG data ends at byte " + std::to_string(n) + " before the IEND chunk";
}

// The marker structure up to the end-of-image marker (FFD9); bytes after it are allowed (some
// cameras append data there). A Huffman-coded JPEG spends at least one bit on the DC value of
// every 8x8 block of its first component, so scan data below that cannot hold the declared
// size: the header is corrupt or the data was cut (libjpeg would only warn and decode grey).
std::string jpegTruncation(const unsigned char* b, std::size_t n) {
  const std::string cut =
      "JPEG data ends at byte " + std::to_string(n) + " before the end-of-image marker";
  uint64_t width = 0, height = 0, scanBytes = 0;
  bool arithmetic = false;
  std::size_t pos = 2;
  while (true) {
    if (pos >= n)
      return cut;
    if (b[pos] != 0xFF)
      return {};                      // unexpected structure: let the decoder decide
    while (pos < n && b[pos] == 0xFF) // fill bytes
      ++pos;
    if (pos >= n)
      return cut;
    const unsigned char marker = b[pos++];
    if (marker == 0xD9) { // end of image
      if (!arithmetic && scanBytes * 8 < (width / 8) * (height / 8))
        return "JPEG declares " + std::to_string(width) + " x " + std::to_string(height) +
               " pixels but holds " + std::to_string(scanBytes) +
               " bytes of image data, less than one bit per 8x8 block (its header is corrupt or "
               "its data cut)";
      return {};
    }
    if ((marker >= 0xD0 && marker <= 0xD7) || marker == 0x01)
      continue; // markers without a length
    if (pos + 2 > n)
      return cut;
    const std::size_t length = std::size_t(b[pos]) << 8 | b[pos + 1];
    if (length < 2)
      return {};
    if (pos + length > n)
      return cut;
    const bool sof =
        marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof && length >= 7 && width == 0) {
      height = std::size_t(b[pos + 3]) << 8 | b[pos + 4];
      width = std::size_t(b[pos + 5]) << 8 | b[pos + 6];
      arithmetic = marker >= 0xC9;
    }
    pos += length;
    if (marker == 0xDA) { // start of scan: entropy-coded data up to the next real marker
      const std::size_t scanStart = pos;
      while (true) {
        if (pos + 1 >= n)
          return cut;
        if (b[pos] == 0xFF && b[pos + 1] != 0x00 && !(b[pos + 1] >= 0xD0 && b[pos + 1] <= 0xD7) &&
            b[pos + 1] != 0xFF)
          break;
        ++pos;
      }
      scanBytes += pos - scanStart;
    }
  }
}

// The first IFD's strips (StripOffsets 273, StripByteCounts 279) or tiles (TileOffsets 324,
// TileByteCounts 325) must lie inside the file; that is what a cut TIFF loses.
class TiffLayout {
public:
  TiffLayout(const unsigned char* b, std::size_t n) : b_(b), n_(n), little_(b[0] == 'I') {}

  std::string truncation() const {
    if (n_ < 8 || u16(2) != 42)
      return {}; // BigTIFF or not TIFF: the decoder judges it
    const std::size_t ifd = u32(4);
    if (ifd > n_ || n_ - ifd < 2)
      return "TIFF directory at byte " + std::to_string(ifd) + " lies past the end of the " +
             std::to_string(n_) + "-byte file";
    const std::size_t entries = u16(ifd);
    if (n_ - ifd - 2 < 12 * entries)
      return "TIFF directory at byte " + std::to_string(ifd) + " has " + std::to_string(entries) +
             " entries, the file ends inside them";
    Array offsets, counts;
    for (std::size_t e = 0; e < entries; ++e) {
      const std::size_t p = ifd + 2 + 12 * e;
      const uint32_t tag = u16(p);
      // Values that do not fit in the entry live elsewhere in the file; a cut file loses them.
      const uint64_t bytes = uint64_t(u32(p + 4)) * typeSize(u16(p + 2));
      if (bytes > 4 && (u32(p + 8) > n_ || bytes > n_ - u32(p + 8)))
        return "TIFF tag " + std::to_string(tag) + " has " + std::to_string(bytes) +
               " bytes of values at byte " + std::to_string(u32(p + 8)) + ", past the end of the " +
               std::to_string(n_) + "-byte file";
      if (tag == 273 || tag == 324)
        offsets = array(p);
      else if (tag == 279 || tag == 325)
        counts = array(p);
    }
    if (!offsets.valid || !counts.valid || offsets.count != counts.count)
      return {}; // malformed in another way: the decoder judges it
    if (!offsets.inside || !counts.inside)
      return "TIFF strip or tile table lies past the end of the " + std::to_string(n_) +
             "-byte file";
    for (std::size_t i = 0; i < offsets.count; ++i) {
      const uint64_t begin = offsets.at(*this, i), size = counts.at(*this, i);
      if (begin > n_ || size > n_ - begin)
        return "TIFF strip/tile " + std::to_string(i) + " (bytes " + std::to_string(begin) + " + " +
               std::to_string(size) + ") reaches past the end of the " + std::to_string(n_) +
               "-byte file";
    }
    return {};
  }

private:
  struct Array {
    bool valid = false, inside = false;
    uint32_t type = 0;
    std::size_t count = 0, offset = 0; // where the values are
    uint64_t at(const TiffLayout& t, std::size_t i) const {
      return type == 3 ? t.u16(offset + 2 * i) : t.u32(offset + 4 * i);
    }
  };

  // Bytes per value of a TIFF field type (0 for types this check does not know).
  static uint64_t typeSize(uint32_t type) {
    switch (type) {
    case 1:
    case 2:
    case 6:
    case 7:
      return 1;
    case 3:
    case 8:
      return 2;
    case 4:
    case 9:
    case 11:
    case 13:
      return 4;
    case 5:
    case 10:
    case 12:
      return 8;
    default:
      return 0;
    }
  }

  // A SHORT (3) or LONG (4) array entry: inline when it fits in 4 bytes, else at an offset.
  Array array(std::size_t p) const {
    Array a;
    a.type = u16(p + 2);
    if (a.type != 3 && a.type != 4)
      return a;
    a.valid = true;
    a.count = u32(p + 4);
    const std::size_t bytes = a.count * (a.type == 3 ? 2 : 4);
    a.offset = bytes <= 4 ? p + 8 : u32(p + 8);
    a.inside = a.count <= n_ && a.offset <= n_ && bytes <= n_ - a.offset;
    return a;
  }

  uint32_t u16(std::size_t p) const {
    return little_ ? uint32_t(b_[p]) | uint32_t(b_[p + 1]) << 8 : uint32_t(b_[p]) << 8 | b_[p + 1];
  }
  uint32_t u32(std::size_t p) const {
    return little_ ? uint32_t(b_[p]) | uint32_t(b_[p + 1]) << 8 | uint32_t(b_[p + 2]) << 16 |
                         uint32_t(b_[p + 3]) << 24
                   : be32(b_ + p);
  }

  const unsigned char* b_;
  std::size_t n_;
  bool little_;
};

// OpenCV's messages span lines; an error is one line.
std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r')
      c = ' ';
  const std::size_t last = s.find_last_not_of(' ');
  return s.substr(0, last == std::string::npos ? 0 : last + 1);
}

} // namespace

std::string imageTruncation(const unsigned char* data, std::size_t size) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (!data || size < 4)
    return {};
  if (size >= 8 && std::memcmp(data, kPng, 8) == 0)
    return pngTruncation(data, size);
  if (data[0] == 0xFF && data[1] == 0xD8)
    return jpegTruncation(data, size);
  if ((data[0] == 'I' && data[1] == 'I') || (data[0] == 'M' && data[1] == 'M'))
    return TiffLayout(data, size).truncation();
  return {};
}

cv::Mat decodeImageFile(const std::string& path, int imreadFlags, const std::string& what) {
  const std::vector<unsigned char> bytes = readFileBytes(path, what);
  if (bytes.empty())
    fail(what, " '", path, "' is empty");
  // The declared size before anything is decoded (io/image_header.h).
  if (const auto header = parseImageHeader(bytes.data(), bytes.size());
      header && header->width * header->height > kMaxImagePixels)
    fail(what, " '", path, "': its ", header->format, " header declares ", header->width, " x ",
         header->height, " pixels, more than the limit of ", kMaxImagePixels,
         " (8192 x 8192) that keeps a corrupt header from exhausting memory");
  if (const std::string cut = imageTruncation(bytes.data(), bytes.size()); !cut.empty())
    fail(what, " '", path, "' is truncated (", cut, ")");
  cv::Mat image;
  try {
    image = cv::imdecode(bytes, imreadFlags);
  } catch (const cv::Exception& e) {
    fail(what, " '", path, "': cannot decode it (", oneLine(e.what()), ")");
  }
  if (image.empty())
    fail(what, " '", path,
         "': cannot decode it: not a readable image (corrupt, or not a PNG, "
         "JPEG or TIFF file)");
  return image;
}

} // namespace simpli::io

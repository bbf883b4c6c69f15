// Image sizes from file headers, without decoding (io/image_header.h).
#include "simpli/model/io/image_header.h"

#include "simpli/error.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

namespace simpli::io {

namespace {

uint32_t be16(const unsigned char* p) {
  return uint32_t(p[0]) << 8 | p[1];
}
uint32_t be32(const unsigned char* p) {
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3];
}

std::optional<ImageHeader> png(const unsigned char* d, std::size_t n) {
  // Signature, then the IHDR chunk: length 13, "IHDR", width, height (big-endian).
  if (n < 24 || std::memcmp(d + 12, "IHDR", 4) != 0)
    return std::nullopt;
  return ImageHeader{"PNG", be32(d + 16), be32(d + 20)};
}

std::optional<ImageHeader> jpeg(const unsigned char* d, std::size_t n) {
  std::size_t p = 2;
  while (p + 4 <= n) {
    if (d[p] != 0xFF)
      return std::nullopt;
    const unsigned char marker = d[p + 1];
    if (marker == 0xFF) { // fill byte
      ++p;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) { // no length
      p += 2;
      continue;
    }
    if (marker == 0xD9 || marker == 0xDA) // end of image, start of scan: no frame header before
      return std::nullopt;
    const std::size_t length = be16(d + p + 2);
    if (length < 2)
      return std::nullopt;
    const bool sof =
        marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof) {
      if (p + 9 > n || length < 7)
        return std::nullopt;
      return ImageHeader{"JPEG", be16(d + p + 7), be16(d + p + 5)};
    }
    p += 2 + length;
  }
  return std::nullopt;
}

std::optional<ImageHeader> tiff(const unsigned char* d, std::size_t n) {
  const bool little = d[0] == 'I';
  auto u16 = [&](std::size_t p) {
    return little ? uint32_t(d[p]) | uint32_t(d[p + 1]) << 8 : be16(d + p);
  };
  auto u32 = [&](std::size_t p) {
    return little ? uint32_t(d[p]) | uint32_t(d[p + 1]) << 8 | uint32_t(d[p + 2]) << 16 |
                        uint32_t(d[p + 3]) << 24
                  : be32(d + p);
  };
  if (n < 8 || u16(2) != 42)
    return std::nullopt;
  const std::size_t ifd = u32(4);
  if (ifd > n || n - ifd < 2)
    return std::nullopt;
  const std::size_t entries = u16(ifd);
  long long width = -1, height = -1;
  for (std::size_t e = 0; e < entries; ++e) {
    const std::size_t p = ifd + 2 + 12 * e;
    if (p + 12 > n)
      break; // the tags are sorted: width and height come first
    const uint32_t tag = u16(p), type = u16(p + 2);
    if (tag != 256 && tag != 257)
      continue;
    const long long value = type == 3 ? u16(p + 8) : type == 4 ? u32(p + 8) : -1;
    if (value < 0)
      return std::nullopt;
    (tag == 256 ? width : height) = value;
  }
  if (width < 0 || height < 0)
    return std::nullopt;
  return ImageHeader{"TIFF", width, height};
}

} // namespace

std::optional<ImageHeader> parseImageHeader(const unsigned char* data, std::size_t size) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (!data || size < 4)
    return std::nullopt;
  if (size >= 8 && std::memcmp(data, kPng, 8) == 0)
    return png(data, size);
  if (data[0] == 0xFF && data[1] == 0xD8)
    return jpeg(data, size);
  if ((data[0] == 'I' && data[1] == 'I') || (data[0] == 'M' && data[1] == 'M'))
    return tiff(data, size);
  return std::nullopt;
}

std::optional<ImageHeader> readImageHeader(const std::string& path) {
  // Enough for PNG's IHDR, JPEG's SOF after EXIF / ICC segments (up to 64 KiB each) and the
  // first TIFF IFD in the files simpli and common tools write.
  constexpr std::size_t kHeaderBytes = 1 << 20;
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return std::nullopt;
  std::vector<unsigned char> bytes(kHeaderBytes);
  in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  const std::size_t n = std::size_t(in.gcount());
  std::optional<ImageHeader> header = parseImageHeader(bytes.data(), n);
  if (header || n < 8 || !(bytes[0] == bytes[1] && (bytes[0] == 'I' || bytes[0] == 'M')))
    return header;
  // libtiff writes the IFD after the pixel data: read it where the header points, behind a copy
  // of the header that points right after itself.
  const bool little = bytes[0] == 'I';
  const uint32_t offset = little ? uint32_t(bytes[4]) | uint32_t(bytes[5]) << 8 |
                                       uint32_t(bytes[6]) << 16 | uint32_t(bytes[7]) << 24
                                 : be32(&bytes[4]);
  std::vector<unsigned char> ifd(8 + 2 + 12 * 64);
  std::memcpy(ifd.data(), bytes.data(), 4);
  ifd[4] = little ? 8 : 0;
  ifd[5] = ifd[6] = 0;
  ifd[7] = little ? 0 : 8;
  in.clear();
  in.seekg(std::streamoff(offset));
  in.read(reinterpret_cast<char*>(ifd.data() + 8), std::streamsize(ifd.size() - 8));
  return parseImageHeader(ifd.data(), 8 + std::size_t(in.gcount()));
}

void checkImageHeader(const std::string& path, const std::string& what, long long expectWidth,
                      long long expectHeight) {
  const std::optional<ImageHeader> h = readImageHeader(path);
  if (!h)
    return;
  if (h->width * h->height > kMaxImagePixels)
    fail(what, " '", path, "': its ", h->format, " header declares ", h->width, " x ", h->height,
         " pixels, more than the limit of ", kMaxImagePixels,
         " (8192 x 8192) that keeps a corrupt header from exhausting memory");
  if (expectWidth > 0 && (h->width != expectWidth || h->height != expectHeight))
    fail(what, " '", path, "': its ", h->format, " header declares ", h->width, " x ", h->height,
         " (W x H), expected ", expectWidth, " x ", expectHeight);
}

} // namespace simpli::io

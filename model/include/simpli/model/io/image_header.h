#pragma once
// The size an image file declares, read from its header without decoding it: PNG (IHDR), JPEG
// (the first SOFn frame header) and TIFF (ImageWidth / ImageLength of the first IFD). Readers
// compare it with what they expect and with kMaxImagePixels before OpenCV decodes the pixels,
// so that a small file declaring a huge image is refused instead of allocated.
#include <cstddef>
#include <optional>
#include <string>

namespace simpli::io {

/// The largest image (width x height) any reader decodes: 8192 x 8192. Far above the network's
/// sizes (the paper's are at most 1008 x 756) and a camera's; it bounds one decoded float image
/// to 768 MiB, so a corrupt header cannot exhaust memory.
inline constexpr long long kMaxImagePixels = 8192LL * 8192LL;

struct ImageHeader {
  std::string format; ///< "PNG", "JPEG" or "TIFF"
  long long width = 0, height = 0;
};

/// The header of the image in `data`, std::nullopt when it is none of the three formats or the
/// header is cut short or malformed (then the decoder gives its own error). Never throws.
std::optional<ImageHeader> parseImageHeader(const unsigned char* data, std::size_t size);

/// parseImageHeader of the start of the file `path` (std::nullopt when it cannot be read).
std::optional<ImageHeader> readImageHeader(const std::string& path);

/// Throws simpli::Error ("<what> '<path>': ...") when the header of `path` declares an image of
/// more than kMaxImagePixels pixels, or (when expectWidth > 0) a size other than expectWidth x
/// expectHeight. Files without a recognised header pass (the decoder checks them).
void checkImageHeader(const std::string& path, const std::string& what, long long expectWidth = 0,
                      long long expectHeight = 0);

} // namespace simpli::io

#pragma once
// RGB images as the network sees them (spec §1.1): float32, planar CHW with
// 3 channels (R, G, B), values in [-1, 1].
//
// Reading (readImage) uses OpenCV with IMREAD_UNCHANGED | IMREAD_IGNORE_ORIENTATION: the pixel
// array is taken as stored and the EXIF orientation tag is ignored, because camera poses from
// SfM tools (COLMAP, LLFF) refer to the stored pixel array, not to the rotated display.
// Accepted: 8-bit and 16-bit PNG / JPEG (and whatever else OpenCV decodes to 8 or 16 bits),
// 1 (grey, replicated to RGB), 2 (grey + alpha), 3 (BGR) or 4 (BGRA) channels; alpha is
// dropped. 8-bit x -> x / 127.5 - 1, 16-bit x -> x / 32767.5 - 1.
//
// Size: the network needs H and W divisible by 16 (§1.5). readImage can resize down to the
// nearest multiple (floor, INTER_AREA). Relative intrinsics need no adjustment for this: they
// are fractions of the image extent, and a resize maps the image extent [0,1]^2 onto itself
// (only the pixel grid changes, even when the aspect ratio changes slightly).
#include <string>
#include <vector>

namespace simpli::io {

struct Image {
  static constexpr int channels = 3;
  int width = 0, height = 0;
  std::vector<float> data; ///< channels x height x width, row-major planes

  Image() = default;
  Image(int width, int height); ///< zero-filled; throws simpli::Error for negative sizes

  bool empty() const { return width == 0 || height == 0; }
  float& at(int c, int y, int x) { return data[(size_t(c) * height + y) * width + x]; }
  float at(int c, int y, int x) const { return data[(size_t(c) * height + y) * width + x]; }
  float* plane(int c) { return data.data() + size_t(c) * height * width; }
  const float* plane(int c) const { return data.data() + size_t(c) * height * width; }
};

/// Width and height of an image file after the optional resize, and before it.
struct ImageSize {
  int width = 0, height = 0;
};

/// Largest multiple of `multiple` not above `size` (multiple <= 1: size unchanged).
int floorToMultiple(int size, int multiple);

/// Reads an image file (see the header comment). With sizeMultiple > 1 the image is resized down
/// to floorToMultiple(W) x floorToMultiple(H) with area interpolation (nothing happens when it
/// already is a multiple). Throws simpli::Error naming the file when it is missing, unreadable,
/// has an unsupported depth or channel count, or is smaller than sizeMultiple.
/// `originalSize`, when given, receives the size stored in the file.
Image readImage(const std::string& path, int sizeMultiple = 1, ImageSize* originalSize = nullptr);

/// Area-interpolated resize (for down-sizing; up-sizing falls back to bilinear).
Image resizeImage(const Image& image, int width, int height);

/// Writes an 8-bit RGB PNG: v -> round((v + 1) * 127.5), clamped to [0, 255]. The file appears
/// atomically (written to a temporary beside it, then renamed). Throws simpli::Error on failure.
void writeImagePng(const Image& image, const std::string& path);

} // namespace simpli::io

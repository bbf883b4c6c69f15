// The reference's MLI export format (spec §10.2; see mli/files.h): 8-bit JPEGs for
// colour, alpha and per-layer linearly quantised depth.
#include <algorithm>
#include <cmath>

#include <opencv2/imgcodecs.hpp>

#include "mli/files_internal.h"
#include "simpli/error.h"

namespace simpli::mli {

namespace {

// PIL's defaults as used by the reference writer: quality 75 with optimised Huffman tables.
// libjpeg's default sampling for a 3-channel image is 2x2 luma, i.e. 4:2:0, as in PIL (OpenCV
// 4.6 has no sampling-factor flag; the tests check the SOF marker).
const std::vector<int> kColourParams = {cv::IMWRITE_JPEG_QUALITY, 75, cv::IMWRITE_JPEG_OPTIMIZE, 1};
// Depth: single channel, quality 100 (all quantisers 1).
const std::vector<int> kDepthParams = {cv::IMWRITE_JPEG_QUALITY, 100, cv::IMWRITE_JPEG_OPTIMIZE, 1};

// Layer maps are used as stored: an EXIF orientation tag must not rotate one map against the
// others or against the depth.
constexpr int kReadColour = cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION;
constexpr int kReadGrey = cv::IMREAD_GRAYSCALE | cv::IMREAD_IGNORE_ORIENTATION;

// trunc(255 x) of a value in [0, 1] (§12 item 21: truncation, not rounding). The float product
// matches the reference's float32 arithmetic.
unsigned char to8bit(float x) {
  const float c = std::min(std::max(x, 0.0f), 1.0f);
  return static_cast<unsigned char>(255.0f * c);
}

// q = clip(floor(256 (D - lo)/(hi - lo)), 0, 255) (note 256 with a clip, as the reference);
// a constant layer (hi == lo) is all q = 0, i.e. decodes to lo exactly, where the reference
// would divide by zero.
unsigned char depthCode(double d, double lo, double hi) {
  if (!(hi > lo))
    return 0;
  const double q = std::floor(256.0 * (d - lo) / (hi - lo));
  return static_cast<unsigned char>(std::min(std::max(q, 0.0), 255.0));
}

} // namespace

void writeJpegLayers(const fs::path& folder, const MLI& mli) {
  const int H = mli.height(), W = mli.width();
  std::vector<std::pair<double, double>> ranges;
  for (int k = 0; k < mli.numLayers(); ++k) {
    const MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
    cv::Mat colour(H, W, CV_8UC3), alpha(H, W, CV_8UC3), depth(H, W, CV_8UC1);
    const auto range = depthRange(layer);
    ranges.push_back(range);
    for (int i = 0; i < H; ++i) {
      auto* c = colour.ptr<unsigned char>(i);
      auto* a = alpha.ptr<unsigned char>(i);
      auto* q = depth.ptr<unsigned char>(i);
      for (int j = 0; j < W; ++j) {
        const std::size_t p = static_cast<std::size_t>(i) * W + j;
        const float* rgba = &layer.rgba[4 * p];
        // OpenCV's channel order is BGR.
        c[3 * j + 0] = to8bit(rgba[2]);
        c[3 * j + 1] = to8bit(rgba[1]);
        c[3 * j + 2] = to8bit(rgba[0]);
        a[3 * j + 0] = a[3 * j + 1] = a[3 * j + 2] = to8bit(rgba[3]);
        q[j] = depthCode(layer.depth[p], range.first, range.second);
      }
    }
    writeLayerImage(folder / layerName("layer_", k, ".jpg"), colour, kColourParams);
    writeLayerImage(folder / layerName("layer_alpha_", k, ".jpg"), alpha, kColourParams);
    writeLayerImage(folder / layerName("layer_depth_", k, ".jpg"), depth, kDepthParams);
  }
  writeMeta(folder, mli, ranges, MLIFormat::Jpeg);
}

MLI readJpegLayers(const fs::path& folder, const Meta& meta, const MLIReadOptions& options) {
  const int H = meta.height, W = meta.width;
  MLI mli = MLI::allocate(meta.camera, static_cast<int>(meta.ranges.size()));
  for (int k = 0; k < mli.numLayers(); ++k) {
    MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
    const cv::Mat colour =
        readLayerImage(folder / layerName("layer_", k, ".jpg"), kReadColour, H, W);
    // The alpha file holds three identical channels; decoding straight to grey yields the luma
    // plane, which for equal channels is the value itself and carries no chroma error.
    const cv::Mat alpha =
        readLayerImage(folder / layerName("layer_alpha_", k, ".jpg"), kReadGrey, H, W);
    const cv::Mat depth =
        readLayerImage(folder / layerName("layer_depth_", k, ".jpg"), kReadGrey, H, W);

    const auto [lo, hi] = meta.ranges[static_cast<std::size_t>(k)];
    const bool viewer = options.depthDecoding == MLIDepthDecoding::Viewer;
    for (int i = 0; i < H; ++i) {
      const auto* c = colour.ptr<unsigned char>(i);
      const auto* a = alpha.ptr<unsigned char>(i);
      const auto* q = depth.ptr<unsigned char>(i);
      for (int j = 0; j < W; ++j) {
        const std::size_t p = static_cast<std::size_t>(i) * W + j;
        float* rgba = &layer.rgba[4 * p];
        rgba[0] = c[3 * j + 2] / 255.0f;
        rgba[1] = c[3 * j + 1] / 255.0f;
        rgba[2] = c[3 * j + 0] / 255.0f;
        rgba[3] = a[j] / 255.0f;
        const double d =
            viewer ? lo + q[j] * (hi - lo) / 255.0 : lo + (q[j] + 0.5) * (hi - lo) / 256.0;
        layer.depth[p] = static_cast<float>(d);
      }
    }
  }
  return mli;
}

} // namespace simpli::mli

// The lossless MLI form (see mli/files.h): 32-bit float TIFFs. Debian 12's OpenCV 4.6 writes
// CV_32FC1 and CV_32FC4 as uncompressed IEEE-float TIFFs and reads them back bit-exactly
// (denormals and -0 included; the tests check it). CV_32FC3 would NOT round-trip: OpenCV stores
// it as lossy SGILOG, which is why colour and alpha travel together as RGBA.
#include <cstring>

#include <opencv2/imgcodecs.hpp>

#include "mli/files_internal.h"
#include "simpli/error.h"

namespace simpli::mli {

namespace {

std::string typeName(const cv::Mat& m) {
  static const char* depths[] = {"8U", "8S", "16U", "16S", "32S", "32F", "64F", "16F"};
  return std::string("CV_") + depths[m.depth()] + "C" + std::to_string(m.channels());
}

cv::Mat readFloatImage(const fs::path& file, int channels, int H, int W) {
  cv::Mat m = readLayerImage(file, cv::IMREAD_UNCHANGED, H, W);
  if (m.type() != CV_MAKETYPE(CV_32F, channels))
    fail(file.string(), ": expected a 32-bit float image with ", channels, " channel",
         channels > 1 ? "s" : "", ", found ", typeName(m));
  return m;
}

} // namespace

void writeLosslessLayers(const fs::path& folder, const MLI& mli) {
  const int H = mli.height(), W = mli.width();
  std::vector<std::pair<double, double>> ranges;
  for (int k = 0; k < mli.numLayers(); ++k) {
    const MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
    ranges.push_back(depthRange(layer));
    // OpenCV swaps the first and third channel between a Mat and a TIFF file; giving it BGRA
    // stores a standard RGBA TIFF that other tools read correctly.
    cv::Mat rgba(H, W, CV_32FC4);
    for (int i = 0; i < H; ++i) {
      float* row = rgba.ptr<float>(i);
      const float* src = &layer.rgba[static_cast<std::size_t>(i) * W * 4];
      for (int j = 0; j < W; ++j) {
        row[4 * j + 0] = src[4 * j + 2];
        row[4 * j + 1] = src[4 * j + 1];
        row[4 * j + 2] = src[4 * j + 0];
        row[4 * j + 3] = src[4 * j + 3];
      }
    }
    // A copy: a Mat header over the const input would need a const_cast.
    cv::Mat depth(H, W, CV_32FC1);
    std::memcpy(depth.ptr<float>(), layer.depth.data(), layer.depth.size() * sizeof(float));
    writeLayerImage(folder / layerName("layer_rgba_", k, ".tiff"), rgba, {});
    writeLayerImage(folder / layerName("layer_depth_", k, ".tiff"), depth, {});
  }
  writeMeta(folder, mli, ranges, MLIFormat::Lossless);
}

MLI readLosslessLayers(const fs::path& folder, const Meta& meta) {
  const int H = meta.height, W = meta.width;
  MLI mli = MLI::allocate(meta.camera, static_cast<int>(meta.ranges.size()));
  for (int k = 0; k < mli.numLayers(); ++k) {
    MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
    const fs::path rgbaFile = folder / layerName("layer_rgba_", k, ".tiff");
    const fs::path depthFile = folder / layerName("layer_depth_", k, ".tiff");
    const cv::Mat rgba = readFloatImage(rgbaFile, 4, H, W);
    const cv::Mat depth = readFloatImage(depthFile, 1, H, W);
    for (int i = 0; i < H; ++i) {
      const float* row = rgba.ptr<float>(i);
      float* dst = &layer.rgba[static_cast<std::size_t>(i) * W * 4];
      for (int j = 0; j < W; ++j) {
        dst[4 * j + 0] = row[4 * j + 2];
        dst[4 * j + 1] = row[4 * j + 1];
        dst[4 * j + 2] = row[4 * j + 0];
        dst[4 * j + 3] = row[4 * j + 3];
      }
      std::memcpy(&layer.depth[static_cast<std::size_t>(i) * W], depth.ptr<float>(i),
                  static_cast<std::size_t>(W) * sizeof(float));
    }
    // The floats are whatever the file holds: check them against the MLI's contract here, so
    // the message names the file.
    validateMLIRgba(layer.rgba, H, W, rgbaFile.string());
    validateMLIDepth(layer.depth, H, W, depthFile.string());
  }
  return mli;
}

} // namespace simpli::mli

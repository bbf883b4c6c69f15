#pragma once
// Private pieces of the MLI reader/writer (mli/files.h): meta.json, file names, image files and
// the file names. Not installed; used by mli/files*.cpp only.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "simpli/model/mli/files.h"
#include "simpli/model/mli/mli.h"

namespace simpli::mli {

namespace fs = std::filesystem;

/// The value of meta.json's "format" for the lossless form (absent in the reference form).
inline constexpr const char* kLosslessFormatTag = "simpli-mli-float";
/// meta.json's mark of an MLI written by simpli: "written_by": "simpli" (both forms).
inline constexpr const char* kWrittenByKey = "written_by";
inline constexpr const char* kWrittenByValue = "simpli";

/// Layer file/key name: layerName("layer_depth_", 3, ".jpg") == "layer_depth_03.jpg". The index
/// has at least two digits, like the reference's "%02d".
std::string layerName(const std::string& prefix, int k, const std::string& suffix = "");

/// Everything meta.json says, checked (see readMeta).
struct Meta {
  MLIFormat format = MLIFormat::Jpeg;
  int height = 0, width = 0;
  scene::Camera camera;                          ///< width/height filled from frame_size
  std::vector<std::pair<double, double>> ranges; ///< per layer [lo, hi]; size() = L
  bool writtenBySimpli = false;                  ///< "written_by": "simpli" present
};

/// Reads and checks `folder`/meta.json: valid JSON object; frame_size = two integers in
/// [2, 65535]; extrinsic_re = 12 numbers forming a rotation and a translation; intrinsics_re =
/// 9 numbers [fx, 0, cx, 0, fy, cy, 0, 0, 1] with fx, fy > 0; layer_depth_00 .. layer_depth_<L-1>
/// present without gaps, each [lo, hi] with 0 < lo <= hi; for the lossless form "format" and a
/// matching "num_layers". Errors name the file, the key and the value.
Meta readMeta(const fs::path& folder);

/// The files of an MLI of `layers` layers in `format`, meta.json included.
std::vector<std::string> mliFileNames(MLIFormat format, int layers);

/// Writes meta.json for `mli` into `folder` (the reference keys, "written_by", plus "format" and
/// "num_layers" for the lossless form). ranges[k] = [lo, hi] of layer k's depth.
void writeMeta(const fs::path& folder, const MLI& mli,
               const std::vector<std::pair<double, double>>& ranges, MLIFormat format);

/// [min, max] of a layer's depth.
std::pair<double, double> depthRange(const MLILayer& layer);

/// Throws simpli::Error naming `file` unless it exists and its header (when recognised) declares
/// W x H (io/image_header.h): checked for every layer file before any layer is allocated.
void checkLayerFile(const fs::path& file, int H, int W);

/// cv::imread with checks: the file exists, decodes, and is H x W; errors name the file.
cv::Mat readLayerImage(const fs::path& file, int imreadFlags, int H, int W);

/// cv::imwrite with checks; errors (including OpenCV exceptions) name the file.
void writeLayerImage(const fs::path& file, const cv::Mat& image, const std::vector<int>& params);

MLI readJpegLayers(const fs::path& folder, const Meta& meta, const MLIReadOptions& options);
void writeJpegLayers(const fs::path& folder, const MLI& mli);
MLI readLosslessLayers(const fs::path& folder, const Meta& meta);
void writeLosslessLayers(const fs::path& folder, const MLI& mli);

} // namespace simpli::mli

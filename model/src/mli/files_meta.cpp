// meta.json of an MLI folder: reading with full checks, writing (see mli/files_internal.h).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include <nlohmann/json.hpp>

#include "io/json_text.h"
#include "mli/files_internal.h"
#include "simpli/error.h"
#include "simpli/model/io/files.h"

namespace simpli::mli {

namespace {

using json = nlohmann::json;

using io::jsonExcerpt;

const json& requireKey(const json& root, const std::string& key, const std::string& file) {
  auto it = root.find(key);
  if (it == root.end())
    fail(file, ": missing key \"", key, "\"");
  return *it;
}

// The array at root[key], which must hold exactly n finite numbers.
std::vector<double> numbers(const json& root, const std::string& key, std::size_t n,
                            const std::string& file) {
  const json& value = requireKey(root, key, file);
  if (!value.is_array())
    fail(file, ": \"", key, "\" is ", jsonExcerpt(value), ", expected an array of ", n, " numbers");
  if (value.size() != n)
    fail(file, ": \"", key, "\" has ", value.size(), " values, expected ", n);
  std::vector<double> out;
  for (std::size_t i = 0; i < n; ++i) {
    const json& e = value[i];
    if (!e.is_number())
      fail(file, ": \"", key, "\"[", i, "] is ", jsonExcerpt(e), ", expected a number");
    const double d = e.get<double>();
    if (!std::isfinite(d))
      fail(file, ": \"", key, "\"[", i, "] = ", d, " is not finite");
    out.push_back(d);
  }
  return out;
}

// An integer-valued JSON number in [lo, hi] (the reference writes Python ints; 752.0 is
// accepted as 752).
int integerIn(const json& e, const std::string& what, double lo, double hi,
              const std::string& file) {
  if (!e.is_number())
    fail(file, ": ", what, " is ", jsonExcerpt(e), ", expected an integer");
  const double d = e.get<double>();
  if (!(d >= lo && d <= hi) || std::floor(d) != d)
    fail(file, ": ", what, " = ", jsonExcerpt(e), ", expected an integer in [", lo, ", ", hi, "]");
  return static_cast<int>(d);
}

// Layer k's index when `key` is exactly layer_depth_<k as %02d>, -1 for other keys.
int layerKeyIndex(const std::string& key, const std::string& file) {
  static const std::string prefix = "layer_depth_";
  if (key.compare(0, prefix.size(), prefix) != 0)
    return -1;
  const std::string digits = key.substr(prefix.size());
  const bool allDigits =
      !digits.empty() && digits.size() <= 6 &&
      std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); });
  const int k = allDigits ? std::stoi(digits) : -1;
  if (k < 0 || layerName(prefix, k) != key)
    fail(file, ": key \"", key, "\" is not of the form layer_depth_XX (XX = 00, 01, ...)");
  return k;
}

} // namespace

std::string layerName(const std::string& prefix, int k, const std::string& suffix) {
  char digits[16];
  std::snprintf(digits, sizeof digits, "%02d", k);
  return prefix + digits + suffix;
}

std::vector<std::string> mliFileNames(MLIFormat format, int layers) {
  std::vector<std::string> names{"meta.json"};
  for (int k = 0; k < layers; ++k) {
    if (format == MLIFormat::Lossless) {
      names.push_back(layerName("layer_rgba_", k, ".tiff"));
      names.push_back(layerName("layer_depth_", k, ".tiff"));
    } else {
      names.push_back(layerName("layer_", k, ".jpg"));
      names.push_back(layerName("layer_alpha_", k, ".jpg"));
      names.push_back(layerName("layer_depth_", k, ".jpg"));
    }
  }
  return names;
}

std::pair<double, double> depthRange(const MLILayer& layer) {
  const auto [lo, hi] = std::minmax_element(layer.depth.begin(), layer.depth.end());
  return {*lo, *hi};
}

Meta readMeta(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec))
    fail("readMLI: folder ", folder.string(), " does not exist");
  if (!fs::is_directory(folder, ec))
    fail("readMLI: ", folder.string(), " is not a folder (an MLI is a folder with meta.json)");
  const fs::path path = folder / "meta.json";
  const std::string file = path.string();
  if (!fs::is_regular_file(path, ec))
    fail(file, ": missing (not an MLI folder)");

  const std::vector<unsigned char> bytes = io::readFileBytes(file, "MLI meta.json");
  const json root = io::parseJson(std::string(bytes.begin(), bytes.end()), file);
  if (!root.is_object())
    fail(file, ": expected a JSON object, found ", jsonExcerpt(root));

  Meta meta;
  if (auto it = root.find(kWrittenByKey); it != root.end())
    meta.writtenBySimpli = it->is_string() && it->get<std::string>() == kWrittenByValue;
  if (auto it = root.find("format"); it != root.end()) {
    if (!it->is_string() || it->get<std::string>() != kLosslessFormatTag)
      fail(file, ": \"format\" is ", jsonExcerpt(*it), ", expected \"", kLosslessFormatTag,
           "\" (or no \"format\" key for the JPEG form)");
    meta.format = MLIFormat::Lossless;
  }

  // frame_size: [H, W]. 65535 is the JPEG limit; it also keeps a corrupt size from turning
  // into a huge allocation.
  const json& size = requireKey(root, "frame_size", file);
  if (!size.is_array() || size.size() != 2)
    fail(file, ": \"frame_size\" is ", jsonExcerpt(size), ", expected [H, W]");
  meta.height = integerIn(size[0], "\"frame_size\"[0] (H)", 2, 65535, file);
  meta.width = integerIn(size[1], "\"frame_size\"[1] (W)", 2, 65535, file);

  const std::vector<double> E = numbers(root, "extrinsic_re", 12, file);
  const std::vector<double> K = numbers(root, "intrinsics_re", 9, file);
  scene::Camera& cam = meta.camera;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      cam.R(r, c) = E[static_cast<std::size_t>(4 * r + c)];
    cam.t(r) = E[static_cast<std::size_t>(4 * r + 3)];
  }
  // Only a plain pinhole K fits the camera model (no skew, relative, last row 0 0 1).
  const int fixedIdx[5] = {1, 3, 6, 7, 8};
  const double fixedVal[5] = {0, 0, 0, 0, 1};
  for (int n = 0; n < 5; ++n)
    if (std::abs(K[static_cast<std::size_t>(fixedIdx[n])] - fixedVal[n]) > 1e-6)
      fail(file, ": \"intrinsics_re\"[", fixedIdx[n], "] = ", K[fixedIdx[n]], ", expected ",
           fixedVal[n], " (K = [fx, 0, cx, 0, fy, cy, 0, 0, 1])");
  cam.fx = K[0];
  cam.cx = K[2];
  cam.fy = K[4];
  cam.cy = K[5];
  cam.width = meta.width;
  cam.height = meta.height;
  validateMLICamera(cam, file + " (extrinsic_re, intrinsics_re)");

  std::map<int, std::pair<double, double>> ranges;
  for (auto it = root.begin(); it != root.end(); ++it) {
    const int k = layerKeyIndex(it.key(), file);
    if (k < 0)
      continue;
    const std::vector<double> r = numbers(root, it.key(), 2, file);
    if (!(r[0] > 0))
      fail(file, ": \"", it.key(), "\" = [", r[0], ", ", r[1],
           "]: lo must be > 0 (depths are "
           "camera z in front of the camera)");
    if (r[0] > r[1])
      fail(file, ": \"", it.key(), "\" = [", r[0], ", ", r[1], "]: lo > hi");
    ranges[k] = {r[0], r[1]};
    if (k >= kMaxMLILayers || static_cast<int>(ranges.size()) > kMaxMLILayers)
      fail(file, ": key \"", it.key(), "\": more than the limit of ", kMaxMLILayers,
           " layers (kMaxMLILayers, which keeps a corrupt meta.json from exhausting memory)");
  }
  if (ranges.empty())
    fail(file, ": no layer_depth_XX keys (an MLI has at least one layer)");
  for (int k = 0; k < static_cast<int>(ranges.size()); ++k)
    if (!ranges.count(k))
      fail(file, ": missing key \"", layerName("layer_depth_", k), "\" (found ", ranges.size(),
           " layer_depth keys, up to ", layerName("layer_depth_", ranges.rbegin()->first),
           "; they must run from 00 without gaps)");
  for (const auto& [k, r] : ranges)
    meta.ranges.push_back(r);
  const long long texels = static_cast<long long>(meta.ranges.size()) * meta.height * meta.width;
  if (texels > kMaxMLITexels)
    fail(file, ": \"frame_size\" [", meta.height, ", ", meta.width, "] with ", meta.ranges.size(),
         " layer(s) is ", texels, " texels, more than the limit of ", kMaxMLITexels,
         " (kMaxMLITexels, 1.25 GiB in memory; it keeps a corrupt size from exhausting memory)");

  if (meta.format == MLIFormat::Lossless) {
    const int L = integerIn(requireKey(root, "num_layers", file), "\"num_layers\"", 1, 1e6, file);
    if (L != static_cast<int>(meta.ranges.size()))
      fail(file, ": \"num_layers\" = ", L, " but there are ", meta.ranges.size(),
           " layer_depth_XX keys");
  }
  return meta;
}

void writeMeta(const fs::path& folder, const MLI& mli,
               const std::vector<std::pair<double, double>>& ranges, MLIFormat format) {
  // ordered_json keeps the reference's key order (layers, frame_size, camera) for readability.
  nlohmann::ordered_json root;
  for (int k = 0; k < mli.numLayers(); ++k) {
    const auto& r = ranges[static_cast<std::size_t>(k)];
    root[layerName("layer_depth_", k)] = {r.first, r.second};
  }
  root["frame_size"] = {mli.height(), mli.width()};
  const scene::Camera& cam = mli.camera;
  nlohmann::ordered_json E = nlohmann::ordered_json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      E.push_back(cam.R(r, c));
    E.push_back(cam.t(r));
  }
  root["extrinsic_re"] = E;
  root["intrinsics_re"] = {cam.fx, 0.0, cam.cx, 0.0, cam.fy, cam.cy, 0.0, 0.0, 1.0};
  if (format == MLIFormat::Lossless) {
    root["format"] = kLosslessFormatTag;
    root["num_layers"] = mli.numLayers();
  }
  root[kWrittenByKey] = kWrittenByValue;

  const fs::path path = folder / "meta.json";
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  // nlohmann writes doubles with enough digits to round-trip them exactly.
  out << root.dump(2) << '\n';
  out.close();
  if (!out)
    fail(path.string(), ": write failed");
}

} // namespace simpli::mli

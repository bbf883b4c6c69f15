// The MLI data type: allocation and validation (see mli/mli.h).
#include "simpli/model/mli/mli.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "simpli/error.h"
#include "simpli/model/scene/camera_checks.h"

namespace simpli::mli {

namespace {

// The reference's averaged rotation comes from a quaternion and is stored as float32 in
// meta.json, so a true rotation carries ~1e-7 errors; 1e-4 still rejects anything that is not
// a rotation (scaled, sheared, transposed-with-a-flip) whose inverse R^T would then be wrong.
constexpr double kRotationTolerance = 1e-4;

std::size_t texelCount(int H, int W) {
  return static_cast<std::size_t>(H < 0 ? 0 : H) * static_cast<std::size_t>(W < 0 ? 0 : W);
}

} // namespace

void validateMLICamera(const scene::Camera& c, const std::string& context) {
  scene::validateCamera(c, context + ": camera", kRotationTolerance);
}

void validateMLIDepth(const std::vector<float>& depth, int H, int W, const std::string& context) {
  const std::size_t n = texelCount(H, W);
  if (depth.size() != n)
    fail(context, ": depth has ", depth.size(), " values, expected H*W = ", n, " (", H, " x ", W,
         ")");
  for (std::size_t p = 0; p < n; ++p) {
    const float d = depth[p];
    // !(d > 0) also catches NaN.
    if (!(d > 0.0f) || !std::isfinite(d))
      fail(context, ": depth at (row ", p / W, ", col ", p % W, ") = ", d,
           ", must be finite and > 0");
  }
}

void validateMLIRgba(const std::vector<float>& rgba, int H, int W, const std::string& context) {
  const std::size_t n = texelCount(H, W);
  if (rgba.size() != 4 * n)
    fail(context, ": rgba has ", rgba.size(), " values, expected 4*H*W = ", 4 * n, " (", H, " x ",
         W, " x 4)");
  static const char* channel[4] = {"R", "G", "B", "A"};
  for (std::size_t e = 0; e < 4 * n; ++e) {
    const float v = rgba[e];
    // Written so that NaN fails too.
    if (!(v >= 0.0f && v <= 1.0f))
      fail(context, ": rgba ", channel[e % 4], " at (row ", (e / 4) / W, ", col ", (e / 4) % W,
           ") = ", v, ", must be in [0, 1]");
  }
}

MLI MLI::allocate(const scene::Camera& camera, int numLayers) {
  if (numLayers < 0)
    fail("MLI::allocate: numLayers = ", numLayers, " is negative");
  if (camera.width < 0 || camera.height < 0)
    fail("MLI::allocate: camera size ", camera.width, "x", camera.height, " is negative");
  MLI mli;
  mli.camera = camera;
  const std::size_t n = mli.texels();
  mli.layers.resize(static_cast<std::size_t>(numLayers));
  for (MLILayer& layer : mli.layers) {
    layer.depth.assign(n, 1.0f);
    layer.rgba.assign(4 * n, 0.0f);
  }
  return mli;
}

void validateMLI(const MLI& mli, const std::string& context) {
  if (mli.layers.empty())
    fail(context, ": MLI has no layers");
  const int H = mli.height(), W = mli.width();
  if (H < 2 || W < 2)
    fail(context, ": layer size H x W = ", H, " x ", W,
         " (camera height x width) must be at least 2 x 2 for the corner-grid mesh");
  validateMLICamera(mli.camera, context);
  for (int k = 0; k < mli.numLayers(); ++k) {
    const MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
    const std::string where = context + ": layer " + std::to_string(k);
    validateMLIDepth(layer.depth, H, W, where);
    validateMLIRgba(layer.rgba, H, W, where);
  }
}

float maxAlpha(const MLILayer& layer) {
  float m = 0.0f;
  for (std::size_t e = 3; e < layer.rgba.size(); e += 4)
    m = std::max(m, layer.rgba[e]);
  return m;
}

std::vector<int> emptyLayers(const MLI& mli, float threshold) {
  std::vector<int> empty;
  for (int k = 0; k < mli.numLayers(); ++k)
    if (maxAlpha(mli.layers[static_cast<std::size_t>(k)]) < threshold)
      empty.push_back(k);
  return empty;
}

} // namespace simpli::mli

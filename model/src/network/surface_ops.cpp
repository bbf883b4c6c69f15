// Parameter-free network steps: plane state, the level-0 tanh quirk, fMPI0 assembly, RGBA
// squashing and the layer depths from group opacities (reference §3, §4.5, §4.9).
#include "simpli/model/network/surface_ops.h"

#include "simpli/error.h"

#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_encoding.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include <cmath>

namespace simpli::network {
namespace {

std::string describe(const ocl::Tensor& t) {
  return t.defined() ? t.describe() : "undefined";
}

ocl::Tensor squashRgb(const ocl::Tensor& x) {
  // The reference clamps after tanh (a no-op in exact arithmetic); kept for identical output.
  return ocl::clamp(ocl::tanh(x), -1.0, 1.0);
}

} // namespace

ocl::Tensor planeState(int planes, int channels, ocl::Dtype dtype) {
  if (planes < 1 || channels < 1)
    fail("planeState: ", planes, " planes, ", channels, " channels");
  std::vector<double> index(static_cast<std::size_t>(planes));
  for (int p = 0; p < planes; ++p)
    index[p] = p;
  return ocl::positionalEncoding(index, channels, dtype);
}

ocl::Tensor nearPlanesTanh(const ocl::Tensor& features, int count) {
  if (!features.defined() || features.dim() < 2)
    fail("nearPlanesTanh: features ", describe(features), " must be [B, P, ...]");
  const int64_t P = features.size(1);
  if (count < 0 || count > P)
    fail("nearPlanesTanh: ", count, " planes of features ", features.describe());
  if (count == 0)
    return features;
  const ocl::Tensor nearest = squashRgb(ocl::slice(features, 1, P - count, P));
  if (count == P)
    return nearest;
  return ocl::concat({ocl::slice(features, 1, 0, P - count), nearest}, 1);
}

ocl::Tensor assembleMpi0(const ocl::Tensor& features, const ocl::Tensor& alphaLogits,
                         int tanhPlanes) {
  if (!features.defined() || features.dim() != 5)
    fail("assembleMpi0: features ", describe(features), " must be [B, P, C, h, w]");
  const ocl::Shape& s = features.shape();
  if (!alphaLogits.defined() || alphaLogits.shape() != ocl::Shape{s[0], s[1], 1, s[3], s[4]})
    fail("assembleMpi0: alpha logits ", describe(alphaLogits), " must be [", s[0], ", ", s[1],
         ", 1, ", s[3], ", ", s[4], "] for features ", features.describe());
  return ocl::concat({nearPlanesTanh(features, tanhPlanes), ocl::sigmoid(alphaLogits)}, 2);
}

ocl::Tensor activateRgba(const ocl::Tensor& raw, int channelAxis) {
  if (!raw.defined() || raw.dim() == 0)
    fail("activateRgba: input ", describe(raw), " has no channel axis");
  const int rank = raw.dim();
  const int axis = channelAxis < 0 ? channelAxis + rank : channelAxis;
  if (axis < 0 || axis >= rank || raw.size(axis) != 4)
    fail("activateRgba: axis ", channelAxis, " of ", raw.describe(), " must have 4 channels");
  return ocl::concat(
      {squashRgb(ocl::slice(raw, axis, 0, 3)), ocl::sigmoid(ocl::slice(raw, axis, 3, 4))}, axis);
}

ocl::Tensor processDepth(const ocl::Tensor& logits, const std::vector<double>& planeDepths,
                         int layers) {
  const int P = static_cast<int>(planeDepths.size());
  if (layers < 1 || P < layers)
    fail("processDepth: ", layers, " layers over ", P, " planes");
  const int G = (P + layers - 1) / layers, stride = P / layers;
  if ((layers - 1) * stride + G != P)
    fail("processDepth: ", P, " planes do not split into ", layers,
         " overlapping groups (need P mod L <= 1)");
  for (double d : planeDepths)
    if (!std::isfinite(d) || d <= 0)
      fail("processDepth: plane depth ", d, " is not finite and positive");
  if (!logits.defined() || logits.dim() != 4 || logits.size(1) != int64_t(layers) * G)
    fail("processDepth: logits ", describe(logits), " must be [B, ", layers * G, ", H, W] (",
         layers, " layers x ", G, " group opacities)");
  const int64_t B = logits.size(0), H = logits.size(2), W = logits.size(3);
  const ocl::Dtype dtype = logits.dtype();
  const ocl::Tensor alpha = ocl::sigmoid(ocl::reshape(logits, {B, layers, G, H, W}));

  // Per-layer constants, [1, L, 1, 1] so they broadcast over [B, L, H, W].
  auto perLayer = [&](auto value) {
    std::vector<double> v(static_cast<std::size_t>(layers));
    for (int k = 0; k < layers; ++k)
      v[k] = value(k);
    return ocl::Tensor::fromHost(v, {1, layers, 1, 1}, dtype);
  };
  auto depthOf = [&](int k, int g) {
    return planeDepths[static_cast<std::size_t>(k * stride + g)];
  };
  const ocl::Tensor nearest = perLayer([&](int k) { return depthOf(k, G - 1); });

  // Back-to-front over-composite of the relative depths c_g = d_g - d_{G-1}, nearest first
  // so that T accumulates prod_{g' > g}; c_{G-1} = 0 contributes nothing.
  ocl::Tensor transmittance, sum;
  for (int g = G - 1; g >= 0; --g) {
    // alpha_{k,0} is replaced by 1: the group's far plane is opaque.
    const ocl::Tensor a =
        g == 0 ? ocl::Tensor() : ocl::reshape(ocl::slice(alpha, 2, g, g + 1), {B, layers, H, W});
    if (g < G - 1) {
      const ocl::Tensor c = perLayer([&](int k) { return depthOf(k, g) - depthOf(k, G - 1); });
      const ocl::Tensor weight = g == 0 ? transmittance : ocl::mul(a, transmittance);
      const ocl::Tensor term = ocl::mul(weight, c);
      sum = sum.defined() ? ocl::add(sum, term) : term;
    }
    if (g > 0) {
      const ocl::Tensor factor = ocl::addScalar(ocl::neg(a), 1.0 + 1e-6);
      transmittance = transmittance.defined() ? ocl::mul(transmittance, factor) : factor;
    }
  }
  if (!sum.defined()) // G == 1: every group is a single plane
    return ocl::expand(nearest, {B, layers, H, W});
  return ocl::add(sum, nearest);
}

} // namespace simpli::network

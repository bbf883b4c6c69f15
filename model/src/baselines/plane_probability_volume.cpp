// The plane-sweep matcher's distribution over planes on the OpenCL device
// (baselines::planeProbabilityVolume): the host version's steps as tensor ops, so the network's
// level-0 photo prior costs no download of the sweep and no host loop per pixel.
#include "simpli/model/baselines/plane_sweep_stereo.h"

#include "simpli/model/geometry/plane_sweep.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_pool.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_reshape.h"
#include "simpli/ocl/ops_shape.h"
#include "simpli/ocl/ops_softmax.h"

namespace simpli::baselines {

namespace {

using ocl::Tensor;

/// Mean of x [P, 1, H, W] over the window x window square around every pixel, counting only
/// pixels inside the image (as the host's summed-area table): the zero-padded sum over rows,
/// then columns (2 x window reads per pixel, not window^2), over the same sums of ones.
Tensor boxMean(const Tensor& x, int window) {
  const int64_t r = window / 2, H = x.size(2), W = x.size(3);
  const auto boxSum = [&](const Tensor& t) {
    const Tensor rows =
        ocl::avgPool2d(ocl::pad(t, {{0, 0}, {0, 0}, {0, 0}, {r, r}}), 1, window, 1, 1);
    return ocl::avgPool2d(ocl::pad(rows, {{0, 0}, {0, 0}, {r, r}, {0, 0}}), window, 1, 1, 1);
  };
  return ocl::div(boxSum(x), boxSum(Tensor::ones({1, 1, H, W}, x.dtype())));
}

} // namespace

Tensor planeProbabilityVolume(const generator::GeneratorInput& in,
                              const std::vector<double>& depths, const PlaneSweepStereoOptions& o,
                              int height, int width) {
  checkOptions(o);
  checkDivides(in, height, width);
  ocl::NoGradGuard noGrad;
  const int H = int(in.images.size(2)), W = int(in.images.size(3));
  const int64_t P = int64_t(depths.size());
  // The weighted variance of the sweep (weights m_v / (n + 1e-7)) summed over RGB.
  const Tensor meanVar =
      geometry::planeSweepMeanVar(in.images, in.reference, in.sources, depths, H, W);
  const Tensor variance = ocl::sum(ocl::slice(meanVar, 1, 3, 6), 1, /*keepdim=*/true);
  // 1 where at least two sources see the point (counts are whole numbers), else 0.
  const Tensor seeing =
      geometry::planeSweepCoverage(in.images, in.reference, in.sources, depths, H, W);
  const Tensor matched = ocl::clamp(ocl::addScalar(seeing, -1.0), 0.0, 1.0);
  const Tensor cost =
      ocl::addScalar(ocl::mul(matched, ocl::addScalar(variance, -kUnmatchedCost)), kUnmatchedCost);
  const Tensor windowed = boxMean(cost, windowPixels(o, W));
  const Tensor probability = ocl::softmax(ocl::mulScalar(windowed, -1.0 / o.temperature), 0);
  const int fy = H / height, fx = W / width;
  return ocl::reshape(ocl::avgPool2d(probability, fy, fx, fy, fx), {P, height, width});
}

} // namespace simpli::baselines

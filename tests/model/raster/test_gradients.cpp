// Gradients of the MLI rasterizer (attributes and layer depths) against central finite
// differences in float64.
#include "raster_test_util.h"

#include "simpli/model/raster/rasterizer.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace simpli::test {
namespace {

using ocl::Dtype;
using ocl::Tensor;

// L = sum of every output times fixed random weights, so every output's gradient is tested.
struct LossWeights {
  std::vector<double> colour, opacity, depth, weights;
  ocl::Shape colourShape, planeShape, weightShape;
};

LossWeights lossWeights(int A, int K, int Ht, int Wt, unsigned seed) {
  const std::size_t plane = std::size_t(Ht) * Wt;
  LossWeights w;
  w.colour = randomValues((A - 1) * plane, -1, 1, seed);
  w.opacity = randomValues(plane, -1, 1, seed + 1);
  w.depth = randomValues(plane, -0.3, 0.3, seed + 2);
  w.weights = randomValues(K * plane, -1, 1, seed + 3);
  w.colourShape = {A - 1, Ht, Wt};
  w.planeShape = {1, Ht, Wt};
  w.weightShape = {K, Ht, Wt};
  return w;
}

double hostLoss(const DeviceImage& img, const LossWeights& w) {
  double sum = 0;
  auto dot = [&](const std::vector<double>& a, const std::vector<double>& b) {
    for (std::size_t i = 0; i < a.size(); ++i)
      sum += a[i] * b[i];
  };
  dot(img.colour, w.colour);
  dot(img.opacity, w.opacity);
  dot(img.depth, w.depth);
  dot(img.weights, w.weights);
  return sum;
}

Tensor deviceLoss(const raster::RenderedLayers& r, const LossWeights& w) {
  using ocl::mul;
  using ocl::sumAll;
  const Dtype dt = Dtype::F64;
  return sumAll(mul(r.colour, Tensor::fromHost(w.colour, w.colourShape, dt))) +
         sumAll(mul(r.opacity, Tensor::fromHost(w.opacity, w.planeShape, dt))) +
         sumAll(mul(r.depth, Tensor::fromHost(w.depth, w.planeShape, dt))) +
         sumAll(mul(r.weights, Tensor::fromHost(w.weights, w.weightShape, dt)));
}

struct GradCase {
  raster::RasterInterpolation mode;
  int K;
};

class RasterGradients : public ::testing::TestWithParam<GradCase> {};

TEST_P(RasterGradients, MatchFiniteDifferences) {
  const GradCase gc = GetParam();
  const int L = 3, H = 5, W = 6, A = 5, Ht = 22, Wt = 26;
  LayerScene s = randomScene(L, H, W, A, 0.3, 1234, 0.1, 0.9);
  const std::size_t texels = std::size_t(H) * W;
  // Exact alpha extremes on some texels (no clamping: the gradient stays defined there).
  s.attrs[(0 * A + A - 1) * texels + 8] = 0.0;
  s.attrs[(std::size_t(1) * A + A - 1) * texels + 14] = 1.0;
  s.attrs[(std::size_t(2) * A + A - 1) * texels + 15] = 0.0;
  s.attrs[(std::size_t(2) * A + A - 1) * texels + 21] = 1.0;
  s.target = makeCamera(1.1, 1.3, 0.5, 0.47, Wt, Ht, smallRotation(6.0, 77) * s.reference.R,
                        s.reference.t + Eigen::Vector3d(0.25, -0.15, 0.3));
  s.settings.interpolation = gc.mode;
  s.settings.maxFragments = gc.K;
  const LossWeights lw = lossWeights(A, gc.K, Ht, Wt, 99);

  Tensor depth = s.depthTensor(Dtype::F64);
  Tensor attrs = s.attrTensor(Dtype::F64);
  depth.setRequiresGrad();
  attrs.setRequiresGrad();
  PoisonScope poison;
  const raster::RasterFragments base =
      raster::rasterizeLayers(depth, s.reference, s.target, s.settings);
  const std::vector<int32_t> baseIds = base.triangleIds();
  int visible = 0;
  for (int32_t id : baseIds)
    visible += id >= 0;
  ASSERT_GT(visible, Ht * Wt); // several layers overlap in the view
  deviceLoss(raster::shadeFragments(base, depth, attrs), lw).backward();
  const std::vector<double> gDepth = depth.grad().toVector();
  const std::vector<double> gAttr = attrs.grad().toVector();
  ASSERT_TRUE(allFinite(gDepth));
  ASSERT_TRUE(allFinite(gAttr));

  ocl::NoGradGuard noGrad;
  // Loss at perturbed inputs; `sameVisibility` reports whether the fragments are unchanged.
  auto evaluate = [&](const std::vector<double>& d, const std::vector<double>& a,
                      bool* sameVisibility) {
    const Tensor dt = Tensor::fromHost(d, {L, H, W}, Dtype::F64);
    const raster::RasterFragments f =
        raster::rasterizeLayers(dt, s.reference, s.target, s.settings);
    if (sameVisibility)
      *sameVisibility = f.triangleIds() == baseIds;
    return hostLoss(
        download(raster::shadeFragments(f, dt, Tensor::fromHost(a, {L, A, H, W}, Dtype::F64))), lw);
  };
  const double h = 1e-6;
  double worst = 0;
  int nonzero = 0;
  // Every fifth attribute (six texels of every channel plane of every layer), every depth.
  for (std::size_t i = 0; i < s.attrs.size(); i += 5) {
    std::vector<double> plus = s.attrs, minus = s.attrs;
    plus[i] += h;
    minus[i] -= h;
    const double fd =
        (evaluate(s.depth, plus, nullptr) - evaluate(s.depth, minus, nullptr)) / (2 * h);
    worst = std::max(worst, std::abs(fd - gAttr[i]) / std::max(1.0, std::abs(fd)));
    nonzero += std::abs(fd) > 1e-3;
  }
  EXPECT_LT(worst, 1e-6) << "attributes";
  EXPECT_GT(nonzero, 30);
  worst = 0;
  nonzero = 0;
  int skipped = 0;
  for (std::size_t i = 0; i < s.depth.size(); ++i) {
    const double step = h * s.depth[i];
    std::vector<double> plus = s.depth, minus = s.depth;
    plus[i] += step;
    minus[i] -= step;
    bool samePlus = false, sameMinus = false;
    const double lp = evaluate(plus, s.attrs, &samePlus);
    const double lm = evaluate(minus, s.attrs, &sameMinus);
    if (!samePlus || !sameMinus) { // a pixel centre crossed an edge: not differentiable here
      ++skipped;
      continue;
    }
    const double fd = (lp - lm) / (2 * step);
    worst = std::max(worst, std::abs(fd - gDepth[i]) / std::max(1.0, std::abs(fd)));
    nonzero += std::abs(fd) > 1e-3;
  }
  EXPECT_LE(skipped, 2);
  EXPECT_LT(worst, 1e-6) << "depths";
  EXPECT_GT(nonzero, 40);
}

INSTANTIATE_TEST_SUITE_P(
    Raster, RasterGradients,
    ::testing::Values(GradCase{raster::RasterInterpolation::ScreenLinear, 16},
                      GradCase{raster::RasterInterpolation::PerspectiveCorrect, 16},
                      GradCase{raster::RasterInterpolation::ScreenLinear, 2}),
    [](const auto& info) {
      return std::string(info.param.mode == raster::RasterInterpolation::ScreenLinear
                             ? "linear"
                             : "perspective") +
             "_K" + std::to_string(info.param.K);
    });

TEST(RasterGradientsFlow, OnlyToInputsThatRequireThem) {
  LayerScene s = randomScene(2, 4, 5, 4, 0.2, 55);
  s.target = cornerGridCamera(s.reference, 5, 4);
  Tensor depth = s.depthTensor(Dtype::F32);
  Tensor attrs = s.attrTensor(Dtype::F32);
  attrs.setRequiresGrad();
  const raster::RenderedLayers r = raster::renderLayers(depth, attrs, s.reference, s.target);
  ocl::sumAll(r.colour).backward();
  EXPECT_FALSE(depth.grad().defined());
  ASSERT_TRUE(attrs.grad().defined());
  // Colour sum: each interior pixel hits its texel with barycentric 1, so d/d rgb of the
  // nearest layer's texel is its weight; alpha gradients exist too; all finite.
  EXPECT_TRUE(allFinite(attrs.grad().toVector()));
  {
    ocl::NoGradGuard noGrad;
    const raster::RenderedLayers q = raster::renderLayers(depth, attrs, s.reference, s.target);
    EXPECT_FALSE(q.colour.requiresGrad());
  }
  Tensor d2 = s.depthTensor(Dtype::F32);
  d2.setRequiresGrad();
  const raster::RenderedLayers r2 =
      raster::renderLayers(d2, s.attrTensor(Dtype::F32), s.reference, s.target);
  ocl::sumAll(r2.depth).backward();
  ASSERT_TRUE(d2.grad().defined());
  EXPECT_TRUE(allFinite(d2.grad().toVector()));
}

} // namespace
} // namespace simpli::test

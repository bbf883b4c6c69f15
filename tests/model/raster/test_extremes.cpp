// Extreme inputs of the MLI rasterizer: alpha 0 / 1, edge-on layers, layers crossing the
// camera plane, 1x1 and 2048x2048 targets, depths from 1e-3 to 1e6, non-finite depths. Nothing
// may produce NaN or Inf, in outputs or gradients.
#include "raster_test_util.h"

#include "simpli/model/raster/rasterizer.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>

namespace simpli::test {
namespace {

using ocl::Dtype;
using ocl::Tensor;

// Renders with gradients on, back-propagates random output weights and checks that every
// output and gradient is finite; returns the rendered image.
DeviceImage renderAndCheckFinite(const LayerScene& s, Dtype dt) {
  Tensor depth = s.depthTensor(dt);
  Tensor attrs = s.attrTensor(dt);
  depth.setRequiresGrad();
  attrs.setRequiresGrad();
  PoisonScope poison;
  const raster::RenderedLayers r =
      raster::renderLayers(depth, attrs, s.reference, s.target, s.settings);
  const DeviceImage img = download(r);
  EXPECT_TRUE(allFinite(img.colour));
  EXPECT_TRUE(allFinite(img.opacity));
  EXPECT_TRUE(allFinite(img.depth));
  EXPECT_TRUE(allFinite(img.weights));
  auto weighted = [&](const Tensor& x, unsigned seed) {
    return ocl::sumAll(
        ocl::mul(x, Tensor::fromHost(randomValues(x.numel(), -1, 1, seed), x.shape(), dt)));
  };
  (weighted(r.colour, 1) + weighted(r.opacity, 2) + weighted(r.depth, 3) + weighted(r.weights, 4))
      .backward();
  EXPECT_TRUE(allFinite(depth.grad().toVector())) << "depth gradient";
  EXPECT_TRUE(allFinite(attrs.grad().toVector())) << "attribute gradient";
  return img;
}

scene::Camera movedTarget(const scene::Camera& ref, const Eigen::Vector3d& centreInRef, int W,
                          int H, const Eigen::Matrix3d& turn = Eigen::Matrix3d::Identity()) {
  scene::Camera c = ref;
  c.R = turn * ref.R;
  // Xt = turn (Xr - centre) with Xr = R Xw + t.
  c.t = turn * (ref.t - centreInRef);
  c.width = W;
  c.height = H;
  return c;
}

TEST(RasterExtremes, AlphaExactlyZeroAndOne) {
  for (double alpha : {0.0, 1.0}) {
    LayerScene s = randomScene(3, 7, 8, 4, 0.2, 31, alpha, alpha);
    s.target = movedTarget(s.reference, {0.2, -0.1, 0.3}, 33, 29, smallRotation(4, 2));
    const DeviceImage img = renderAndCheckFinite(s, Dtype::F32);
    const ReferenceImage want = referenceRender(s);
    EXPECT_LT(maxRelativeError(img, want), 1e-5) << "alpha " << alpha;
    const std::size_t plane = 33 * 29;
    for (std::size_t p = 0; p < plane; ++p) {
      if (want.ambiguous[p] || want.ids[p] < 0)
        continue;
      // alpha 1: the nearest fragment takes weight 1 and leaves 1e-6 transmittance (the
      // reference's epsilon); alpha 0: every weight is 0 but the farthest (opaque) one.
      int n = 0;
      while (n < 16 && want.ids[n * plane + p] >= 0)
        ++n;
      for (int k = 0; k < n; ++k) {
        const double w = img.weights[k * plane + p];
        if (alpha == 1.0)
          ASSERT_TRUE(k == 0 ? std::abs(w - 1.0) < 1e-6 : w <= 1.5e-6) << k << " " << w;
        else
          ASSERT_TRUE(k < n - 1 ? w == 0.0 : std::abs(w - 1.0) < 1e-5) << k << " " << w;
      }
    }
  }
}

TEST(RasterExtremes, EdgeOnLayer) {
  // Layer 1 lies on the plane x + z = 0.5 (reference-camera coordinates), which contains the
  // target's centre (0.5, 0, 0): the target sees it exactly edge-on. Layer 0 is a normal plane
  // behind it.
  const int H = 9, W = 11;
  LayerScene s = flatScene({6.0, 1.0}, H, W, 4, 41);
  const scene::Camera& ref = s.reference;
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      const double rx = (double(j) / (W - 1) - ref.cx) / ref.fx;
      s.depth[std::size_t(H) * W + std::size_t(i) * W + j] = 0.5 / (rx + 1.0);
    }
  s.target = movedTarget(ref, {0.5, 0.0, 0.0}, 48, 40);
  const DeviceImage img = renderAndCheckFinite(s, Dtype::F32);
  const ReferenceImage want = referenceRender(s);
  EXPECT_LT(maxRelativeError(img, want), 1e-5);
  EXPECT_LT(want.ambiguousCount(), 48 * 40 / 4);
  const std::vector<double> layer =
      raster::rasterizeLayers(s.depthTensor(Dtype::F32), s.reference, s.target)
          .layerIndex()
          .toVector();
  int edgeOn = 0;
  for (double l : layer)
    edgeOn += l == 1.0;
  EXPECT_LE(edgeOn, 2 * 48) << "an edge-on layer covers at most a line of pixels";
  renderAndCheckFinite(s, Dtype::F64);
}

TEST(RasterExtremes, LayerCrossingTheCameraPlane) {
  // The target stands at reference z = 4 inside the stack; layer 1 is tilted from z = 3 to 5
  // across the image, so some of its triangles have vertices behind or at the camera plane and
  // are skipped; the near plane is set at 0.01 (default).
  const int H = 10, W = 12;
  LayerScene s = randomScene(3, H, W, 4, 0.1, 51);
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j)
      s.depth[std::size_t(H) * W + std::size_t(i) * W + j] = 3.0 + 2.0 * j / (W - 1);
  s.target = makeCamera(0.4, 0.5, 0.5, 0.5, 50, 40); // wide field of view
  s.target = movedTarget(s.reference, {0.0, 0.0, 4.0}, 50, 40);
  s.target.fx = 0.4;
  s.target.fy = 0.5;
  for (Dtype dt : {Dtype::F32, Dtype::F64}) {
    const DeviceImage img = renderAndCheckFinite(s, dt);
    const ReferenceImage want = referenceRender(s);
    EXPECT_LT(want.ambiguousCount(), 50 * 40 / 5);
    EXPECT_LT(maxRelativeError(img, want), dt == Dtype::F32 ? 1e-5 : 1e-10);
  }
  // Vertices at exactly the near plane distance: skipped, still finite.
  s.settings.nearZ = 1.0; // layer 1 has target z from -1 to 1
  renderAndCheckFinite(s, Dtype::F32);
}

TEST(RasterExtremes, OneByOneTarget) {
  LayerScene s = randomScene(3, 6, 7, 4, 0.3, 61);
  for (int variant = 0; variant < 3; ++variant) {
    s.target = movedTarget(s.reference, {0.05 * variant, -0.03 * variant, 0.1}, 1, 1,
                           smallRotation(2.0 * variant, 5));
    const DeviceImage img = renderAndCheckFinite(s, Dtype::F64);
    EXPECT_LT(maxRelativeError(img, referenceRender(s)), 1e-10) << "variant " << variant;
    EXPECT_GT(img.opacity[0], 0.5) << "the centre pixel sees the layers";
  }
}

// Labelled "slow" in ctest (suite RasterSlow).
TEST(RasterSlow, Target2048x2048) {
  LayerScene s = randomScene(3, 9, 12, 4, 0.3, 71);
  s.target = movedTarget(s.reference, {0.1, 0.05, -0.2}, 2048, 2048, smallRotation(3.0, 8));
  s.settings.maxFragments = 4;
  const Tensor depth = s.depthTensor(Dtype::F32);
  const Tensor attrs = s.attrTensor(Dtype::F32);
  auto t0 = std::chrono::steady_clock::now();
  const raster::RenderedLayers r =
      raster::renderLayers(depth, attrs, s.reference, s.target, s.settings);
  const DeviceImage img = download(r);
  auto t1 = std::chrono::steady_clock::now();
  const ReferenceImage want = referenceRender(s);
  auto t2 = std::chrono::steady_clock::now();
  std::printf("[ timing ] 2048x2048 (3 layers 9x12, K=4, f32): device %.2f s (first call, with "
              "kernel builds), CPU reference %.2f s\n",
              std::chrono::duration<double>(t1 - t0).count(),
              std::chrono::duration<double>(t2 - t1).count());
  EXPECT_LT(want.ambiguousCount(), 2048 * 2048 / 100);
  EXPECT_LT(maxRelativeError(img, want), 1e-5);
}

TEST(RasterExtremes, DepthsFromMilliToMega) {
  raster::RasterSettings settings;
  settings.nearZ = 1e-4;
  settings.farZ = 0; // disabled
  {
    // Flat layers spanning nine decades, a slightly translated camera.
    LayerScene s = flatScene({1e6, 1e3, 1.0, 1e-3}, 7, 9, 4, 81);
    s.settings = settings;
    s.target = movedTarget(s.reference, {2e-5, -1e-5, 1e-5}, 36, 28);
    for (Dtype dt : {Dtype::F32, Dtype::F64}) {
      const DeviceImage img = renderAndCheckFinite(s, dt);
      const ReferenceImage want = referenceRender(s);
      EXPECT_LT(want.ambiguousCount(), 36 * 28 / 5);
      EXPECT_LT(maxRelativeError(img, want), dt == Dtype::F32 ? 1e-5 : 1e-10);
    }
  }
  {
    // Log-uniform random depths inside each layer: wildly folded, huge triangles.
    LayerScene s = randomScene(3, 8, 10, 4, 0.0, 82);
    const std::vector<double> e = randomValues(s.depth.size(), -3.0, 6.0, 83);
    for (std::size_t i = 0; i < e.size(); ++i)
      s.depth[i] = std::pow(10.0, e[i]);
    s.settings = settings;
    s.target = movedTarget(s.reference, {0.01, -0.02, 0.005}, 40, 30, smallRotation(2.0, 4));
    renderAndCheckFinite(s, Dtype::F32);
    renderAndCheckFinite(s, Dtype::F64);
  }
}

TEST(RasterExtremes, NonFiniteDepthsSkipTheirTriangles) {
  LayerScene s = randomScene(2, 6, 7, 4, 0.2, 91);
  s.depth[10] = std::numeric_limits<double>::quiet_NaN();
  s.depth[50] = std::numeric_limits<double>::infinity();
  s.depth[60] = -std::numeric_limits<double>::infinity();
  s.target = movedTarget(s.reference, {0.1, 0.0, 0.1}, 30, 26);
  PoisonScope poison;
  const raster::RenderedLayers r = raster::renderLayers(
      s.depthTensor(Dtype::F32), s.attrTensor(Dtype::F32), s.reference, s.target);
  const DeviceImage img = download(r);
  EXPECT_TRUE(allFinite(img.colour));
  EXPECT_TRUE(allFinite(img.opacity));
  EXPECT_TRUE(allFinite(img.depth));
  EXPECT_TRUE(allFinite(img.weights));
}

} // namespace
} // namespace simpli::test

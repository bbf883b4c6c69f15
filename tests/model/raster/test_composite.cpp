// Forward rendering of the MLI rasterizer against independent expectations and the CPU
// double reference (raster_reference.h).
#include "raster_test_util.h"

#include "simpli/model/raster/rasterizer.h"
#include "simpli/ocl/autograd.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace simpli::test {
namespace {

using ocl::Dtype;

const char* name(Dtype d) {
  return d == Dtype::F32 ? "f32" : "f64";
}

// ---- reference camera: vertices on pixel centres ---------------------------------------------
//
// Design: a target with the reference pose whose W x H pixel centres are exactly the
// corner-grid vertex rays (intrinsics scaled by (W-1)/W plus half a pixel, cornerGridCamera).
// Whatever the layer depths, vertex (i, j) of every layer then projects onto the centre of
// pixel (i, j), so the pixel sees each layer exactly at its texel: the expected image is the
// over-composite of the texels sorted by their depths (farthest opaque), computed here without
// any rasterization. The depths are random and the layers interleave, so the per-pixel order
// differs from the layer order. Pixels off the image border lie inside every layer and must
// see all L layers once each. The border pixels lie on the layers' boundary: with exact
// arithmetic the top-left rule would keep the top row and left column and drop the bottom row
// and right column, but the projected vertex differs from the centre by rounding (~1e-5 px in
// float32, ~1e-13 px in float64; coverage is exact on the rounded geometry), so each layer may
// or may not cover them; there the test takes the layers the rasterizer found (each at most
// once, in depth order) and checks their composite. Values: in float32 the interpolated value
// differs from the texel by the rounding offset times the neighbouring texel differences (tolerance
// 2e-4); in float64 the match is to 1e-9.
class ReferenceCamera : public ::testing::TestWithParam<Dtype> {};

TEST_P(ReferenceCamera, ReproducesTheTextureComposite) {
  const Dtype dt = GetParam();
  const int L = 4, H = 13, W = 17, A = 5;
  LayerScene s = randomScene(L, H, W, A, 0.45, 101, 0.05, 0.95);
  const std::size_t texels = std::size_t(H) * W;
  // Exact alpha extremes on a few texels.
  for (int k = 0; k < L; ++k) {
    s.attrs[(std::size_t(k) * A + A - 1) * texels + 3 * k + 20] = 0.0;
    s.attrs[(std::size_t(k) * A + A - 1) * texels + 5 * k + 40] = 1.0;
  }
  s.target = cornerGridCamera(s.reference, W, H);
  PoisonScope poison;
  const raster::RasterFragments f =
      raster::rasterizeLayers(s.depthTensor(dt), s.reference, s.target);
  const raster::RenderedLayers r = raster::shadeFragments(f, s.depthTensor(dt), s.attrTensor(dt));
  const DeviceImage img = download(r);
  const std::vector<double> layerOf = f.layerIndex().toVector();
  const double tol = dt == Dtype::F32 ? 2e-4 : 1e-9;
  const int K = 16;
  int boundaryHits = 0;
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      const std::size_t pix = std::size_t(i) * W + j;
      std::vector<double> colour(A - 1, 0.0), weights(K, 0.0);
      std::vector<int> order;
      double opacity = 0, depth = 0;
      if (i > 0 && j > 0 && i < H - 1 && j < W - 1) {
        order.resize(L);
        std::iota(order.begin(), order.end(), 0);
        std::sort(order.begin(), order.end(), [&](int a, int b) {
          return s.depth[a * texels + pix] < s.depth[b * texels + pix];
        });
      } else {
        for (int n = 0; n < K && layerOf[n * texels + pix] >= 0; ++n)
          order.push_back(static_cast<int>(layerOf[n * texels + pix]));
        std::vector<int> sorted = order;
        std::sort(sorted.begin(), sorted.end());
        ASSERT_TRUE(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end())
            << "a layer covers boundary pixel " << i << "," << j << " twice";
        for (std::size_t n = 1; n < order.size(); ++n)
          ASSERT_LT(s.depth[order[n - 1] * texels + pix], s.depth[order[n] * texels + pix]);
        boundaryHits += static_cast<int>(order.size());
      }
      const int hits = static_cast<int>(order.size());
      if (hits > 0) {
        double trans = 1;
        for (int n = 0; n < hits; ++n) {
          const int k = order[n];
          const double a =
              n == hits - 1 ? 1.0 : s.attrs[(std::size_t(k) * A + A - 1) * texels + pix];
          weights[n] = a * trans;
          trans *= (1 - a) + 1e-6;
          for (int c = 0; c < A - 1; ++c)
            colour[c] += weights[n] * s.attrs[(std::size_t(k) * A + c) * texels + pix];
          depth += weights[n] * s.depth[k * texels + pix];
        }
        for (int n = hits; n < K; ++n)
          trans *= 1 + 1e-6;
        opacity = 1 - trans;
      }
      for (int c = 0; c < A - 1; ++c)
        ASSERT_NEAR(img.colour[c * texels + pix], colour[c], tol)
            << name(dt) << " pixel " << i << "," << j << " channel " << c;
      ASSERT_NEAR(img.opacity[pix], opacity, tol) << "pixel " << i << "," << j;
      ASSERT_NEAR(img.depth[pix], depth, tol * std::max(1.0, depth)) << "pixel " << i << "," << j;
      for (int n = 0; n < K; ++n) {
        ASSERT_NEAR(img.weights[n * texels + pix], weights[n], tol) << "slot " << n;
        const double wantLayer = n < static_cast<int>(order.size()) ? order[n] : -1;
        ASSERT_EQ(layerOf[n * texels + pix], wantLayer)
            << "pixel " << i << "," << j << " slot " << n;
      }
    }
  // Boundary pixels: only rounding lets a layer in (never all of them everywhere).
  EXPECT_LT(boundaryHits, L * (2 * (H + W) - 4));
}

INSTANTIATE_TEST_SUITE_P(Raster, ReferenceCamera, ::testing::Values(Dtype::F32, Dtype::F64),
                         [](const auto& info) { return std::string(name(info.param)); });

// ---- flat layers, translated camera: analytic expectation ------------------------------------
//
// Fronto-parallel planes seen from a camera that is only translated (any direction) map to the
// reference image by an affine map per plane, so screen-space interpolation of the projected
// mesh equals the mesh's own piecewise-linear interpolation on the corner grid at the point
// where the pixel ray meets the plane (in both interpolation modes). That point, the grid
// triangle containing it and the per-plane composite (planes in depth order, farthest opaque)
// are computed here in closed form.
struct FlatCase {
  Dtype dtype;
  raster::RasterInterpolation mode;
};

class FlatLayers : public ::testing::TestWithParam<FlatCase> {};

TEST_P(FlatLayers, MatchTheAnalyticPlaneComposite) {
  const FlatCase fc = GetParam();
  const std::vector<double> planes{9.0, 5.0, 3.0};
  const int H = 9, W = 12, A = 4, L = 3, Ht = 40, Wt = 52, K = 16;
  LayerScene s = flatScene(planes, H, W, A, 202);
  const Eigen::Vector3d delta(0.21, -0.13, 0.4); // in reference-camera coordinates
  s.target = s.reference;
  s.target.t = s.reference.t + delta;
  s.target.width = Wt;
  s.target.height = Ht;
  s.settings.interpolation = fc.mode;
  const raster::RenderedLayers r = raster::renderLayers(
      s.depthTensor(fc.dtype), s.attrTensor(fc.dtype), s.reference, s.target, s.settings);
  const DeviceImage img = download(r);
  const scene::Camera& ref = s.reference;
  const std::size_t texels = std::size_t(H) * W, plane = std::size_t(Ht) * Wt;
  int compared = 0;
  double worst = 0;
  for (int rr = 0; rr < Ht; ++rr)
    for (int cc = 0; cc < Wt; ++cc) {
      const std::size_t pix = std::size_t(rr) * Wt + cc;
      const double ut = (cc + 0.5) / Wt, vt = (rr + 0.5) / Ht;
      bool ambiguous = false;
      std::vector<std::vector<double>> hit; // per hit layer (near to far): A attributes, z
      for (int k = L - 1; k >= 0; --k) {    // layer L-1 is the nearest plane
        const double d = planes[k], zt = d + delta.z();
        const double xr = (ut - ref.cx) * zt / ref.fx - delta.x();
        const double yr = (vt - ref.cy) * zt / ref.fy - delta.y();
        const double gx = (ref.fx * xr / d + ref.cx) * (W - 1);
        const double gy = (ref.fy * yr / d + ref.cy) * (H - 1);
        const double margin = 1e-3;
        if (std::abs(gx) < margin || std::abs(gx - (W - 1)) < margin || std::abs(gy) < margin ||
            std::abs(gy - (H - 1)) < margin)
          ambiguous = true;
        // Inside means [0, W-1) x [0, H-1): the right and bottom boundary lines are outside.
        if (gx < 0 || gx >= W - 1 || gy < 0 || gy >= H - 1)
          continue;
        const int j0 = static_cast<int>(std::floor(gx)), i0 = static_cast<int>(std::floor(gy));
        const double fx = gx - j0, fy = gy - i0;
        const std::size_t b = std::size_t(i0) * W + j0;
        std::vector<double> val(A + 1);
        for (int c = 0; c < A; ++c) {
          const double* t = &s.attrs[(std::size_t(k) * A + c) * texels];
          val[c] = fy >= fx ? (1 - fy) * t[b] + (fy - fx) * t[b + W] + fx * t[b + W + 1]
                            : (1 - fx) * t[b] + fy * t[b + W + 1] + (fx - fy) * t[b + 1];
        }
        val[A] = zt;
        hit.push_back(val);
      }
      if (ambiguous)
        continue;
      ++compared;
      std::vector<double> colour(A - 1, 0.0), weights(K, 0.0);
      double trans = 1, depth = 0;
      const int n = static_cast<int>(hit.size());
      for (int m = 0; m < n; ++m) {
        const double a = m == n - 1 ? 1.0 : hit[m][A - 1];
        weights[m] = a * trans;
        trans *= (1 - a) + 1e-6;
        for (int c = 0; c < A - 1; ++c)
          colour[c] += weights[m] * hit[m][c];
        depth += weights[m] * hit[m][A];
      }
      for (int m = n; m < K; ++m)
        trans *= 1 + 1e-6;
      const double opacity = n > 0 ? 1 - trans : 0.0;
      auto check = [&](double got, double want) {
        const double e = std::abs(got - want) / std::max(1.0, std::abs(want));
        if (e > 1e-6 && getenv("RASTER_DEBUG"))
          printf("pixel %d %d got %.9f want %.9f hits %d\n", rr, cc, got, want, n);
        worst = std::max(worst, e);
      };
      for (int c = 0; c < A - 1; ++c)
        check(img.colour[c * plane + pix], colour[c]);
      check(img.opacity[pix], opacity);
      check(img.depth[pix], depth);
      for (int m = 0; m < K; ++m)
        check(img.weights[m * plane + pix], weights[m]);
    }
  EXPECT_GT(compared, static_cast<int>(plane * 0.95));
  EXPECT_LT(worst, fc.dtype == Dtype::F32 ? 1e-5 : 1e-10) << name(fc.dtype);
}

INSTANTIATE_TEST_SUITE_P(
    Raster, FlatLayers,
    ::testing::Values(FlatCase{Dtype::F32, raster::RasterInterpolation::ScreenLinear},
                      FlatCase{Dtype::F64, raster::RasterInterpolation::ScreenLinear},
                      FlatCase{Dtype::F32, raster::RasterInterpolation::PerspectiveCorrect},
                      FlatCase{Dtype::F64, raster::RasterInterpolation::PerspectiveCorrect}),
    [](const auto& info) {
      return std::string(name(info.param.dtype)) +
             (info.param.mode == raster::RasterInterpolation::ScreenLinear ? "_linear"
                                                                           : "_perspective");
    });

// ---- general cameras against the CPU double reference ----------------------------------------

class CpuReference : public ::testing::TestWithParam<FlatCase> {};

TEST_P(CpuReference, RotatedCameraMatches) {
  const FlatCase fc = GetParam();
  LayerScene s = randomScene(3, 11, 14, 4, 0.3, 303);
  s.target = makeCamera(1.0, 1.25, 0.52, 0.45, 60, 45, smallRotation(5.0, 7) * s.reference.R,
                        s.reference.t + Eigen::Vector3d(-0.35, 0.25, 0.6));
  s.settings.interpolation = fc.mode;
  const ReferenceImage want = referenceRender(s);
  PoisonScope poison;
  const raster::RasterFragments f =
      raster::rasterizeLayers(s.depthTensor(fc.dtype), s.reference, s.target, s.settings);
  const raster::RenderedLayers r =
      raster::shadeFragments(f, s.depthTensor(fc.dtype), s.attrTensor(fc.dtype));
  const double err = maxRelativeError(download(r), want);
  EXPECT_LT(want.ambiguousCount(), 45 * 60 / 20);
  EXPECT_LT(err, fc.dtype == Dtype::F32 ? 1e-5 : 1e-10) << name(fc.dtype);
  const std::vector<int32_t> ids = f.triangleIds();
  const std::size_t plane = 45 * 60;
  int covered = 0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (want.ambiguous[i % plane])
      continue;
    ASSERT_EQ(ids[i], want.ids[i]) << "slot " << i / plane << " pixel " << i % plane;
    covered += ids[i] >= 0;
  }
  EXPECT_GT(covered, static_cast<int>(plane)); // several layers visible
}

INSTANTIATE_TEST_SUITE_P(
    Raster, CpuReference,
    ::testing::Values(FlatCase{Dtype::F32, raster::RasterInterpolation::ScreenLinear},
                      FlatCase{Dtype::F64, raster::RasterInterpolation::ScreenLinear},
                      FlatCase{Dtype::F32, raster::RasterInterpolation::PerspectiveCorrect},
                      FlatCase{Dtype::F64, raster::RasterInterpolation::PerspectiveCorrect}),
    [](const auto& info) {
      return std::string(name(info.param.dtype)) +
             (info.param.mode == raster::RasterInterpolation::ScreenLinear ? "_linear"
                                                                           : "_perspective");
    });

TEST(RasterComposite, ScreenLinearAndPerspectiveDifferOnSlantedLayers) {
  // A strongly bumpy layer seen obliquely: the two modes must give different colours (the
  // option does something), each matching its own reference.
  LayerScene s = randomScene(1, 6, 7, 4, 0.6, 404, 1.0, 1.0);
  s.target = makeCamera(0.9, 1.1, 0.5, 0.5, 40, 32, smallRotation(10.0, 3) * s.reference.R,
                        s.reference.t + Eigen::Vector3d(1.5, 0.0, 0.0));
  double diff = 0;
  std::vector<double> first;
  for (auto mode : {raster::RasterInterpolation::ScreenLinear,
                    raster::RasterInterpolation::PerspectiveCorrect}) {
    s.settings.interpolation = mode;
    const raster::RenderedLayers r = raster::renderLayers(
        s.depthTensor(Dtype::F64), s.attrTensor(Dtype::F64), s.reference, s.target, s.settings);
    const DeviceImage img = download(r);
    EXPECT_LT(maxRelativeError(img, referenceRender(s)), 1e-10);
    if (first.empty())
      first = img.colour;
    else
      for (std::size_t i = 0; i < first.size(); ++i)
        diff = std::max(diff, std::abs(first[i] - img.colour[i]));
  }
  EXPECT_GT(diff, 1e-3);
}

TEST(RasterComposite, KeepsOnlyTheNearestKFragments) {
  LayerScene s = randomScene(6, 8, 9, 4, 0.25, 505);
  s.target = makeCamera(0.95, 1.2, 0.5, 0.5, 30, 26, smallRotation(3.0, 5) * s.reference.R,
                        s.reference.t + Eigen::Vector3d(0.1, 0.05, 0.2));
  for (int K : {1, 3, 6}) {
    s.settings.maxFragments = K;
    PoisonScope poison;
    const raster::RenderedLayers r = raster::renderLayers(
        s.depthTensor(Dtype::F64), s.attrTensor(Dtype::F64), s.reference, s.target, s.settings);
    ASSERT_EQ(r.weights.shape(), (ocl::Shape{K, 26, 30}));
    const ReferenceImage want = referenceRender(s);
    EXPECT_LT(want.ambiguousCount(), 30 * 26 / 10);
    EXPECT_LT(maxRelativeError(download(r), want), 1e-10) << "K = " << K;
  }
}

TEST(RasterComposite, TileSizesAndChunkedBinningGiveIdenticalResults) {
  LayerScene s = randomScene(3, 12, 15, 4, 0.3, 606);
  s.target = makeCamera(1.0, 1.3, 0.5, 0.48, 71, 53, smallRotation(4.0, 9) * s.reference.R,
                        s.reference.t + Eigen::Vector3d(0.2, -0.1, 0.3));
  s.settings.tileSize = 8;
  const raster::RasterFragments base =
      raster::rasterizeLayers(s.depthTensor(Dtype::F32), s.reference, s.target, s.settings);
  const std::vector<int32_t> baseIds = base.triangleIds();
  const std::vector<double> baseColour =
      raster::shadeFragments(base, s.depthTensor(Dtype::F32), s.attrTensor(Dtype::F32))
          .colour.toVector();
  std::vector<raster::RasterSettings> variants;
  for (int tile : {4, 16, 32}) {
    raster::RasterSettings v = s.settings;
    v.tileSize = tile;
    variants.push_back(v);
  }
  raster::RasterSettings chunked = s.settings;
  chunked.maxBinEntries = 1; // one triangle range per chunk down to the tile count
  variants.push_back(chunked);
  for (const raster::RasterSettings& v : variants) {
    const raster::RasterFragments f =
        raster::rasterizeLayers(s.depthTensor(Dtype::F32), s.reference, s.target, v);
    EXPECT_EQ(f.triangleIds(), baseIds) << "tile " << v.tileSize << " budget " << v.maxBinEntries;
    EXPECT_EQ(raster::shadeFragments(f, s.depthTensor(Dtype::F32), s.attrTensor(Dtype::F32))
                  .colour.toVector(),
              baseColour);
  }
}

TEST(RasterComposite, RepeatedRendersAreIdentical) {
  LayerScene s = randomScene(4, 10, 12, 4, 0.4, 707);
  s.target = makeCamera(1.0, 1.2, 0.5, 0.5, 64, 48, smallRotation(6.0, 1) * s.reference.R,
                        s.reference.t + Eigen::Vector3d(0.3, 0.1, -0.2));
  const DeviceImage a = download(raster::renderLayers(
      s.depthTensor(Dtype::F32), s.attrTensor(Dtype::F32), s.reference, s.target));
  const DeviceImage b = download(raster::renderLayers(
      s.depthTensor(Dtype::F32), s.attrTensor(Dtype::F32), s.reference, s.target));
  EXPECT_EQ(a.colour, b.colour);
  EXPECT_EQ(a.opacity, b.opacity);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.weights, b.weights);
}

TEST(RasterComposite, PixelsWithoutFragmentsAreZero) {
  // The target looks away from the layers: nothing covers any pixel.
  LayerScene s = randomScene(2, 5, 6, 4, 0.2, 808);
  s.target = s.reference;
  s.target.R = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix() * s.reference.R;
  s.target.t = -s.target.R * s.reference.centre(); // same centre, looking backwards
  s.target.width = 17;
  s.target.height = 9;
  PoisonScope poison;
  const raster::RasterFragments f =
      raster::rasterizeLayers(s.depthTensor(Dtype::F32), s.reference, s.target);
  for (int32_t id : f.triangleIds())
    ASSERT_EQ(id, -1);
  const DeviceImage img =
      download(raster::shadeFragments(f, s.depthTensor(Dtype::F32), s.attrTensor(Dtype::F32)));
  for (const auto* v : {&img.colour, &img.opacity, &img.depth, &img.weights})
    for (double x : *v)
      ASSERT_EQ(x, 0.0);
  for (double x : f.depth.toVector())
    ASSERT_EQ(x, 0.0);
}

TEST(RasterComposite, FarCutDropsDistantFragmentsAndCanBeDisabled) {
  // Layers at 200 and 50: with the default cut (120) only the near one renders (and becomes
  // the farthest, opaque, fragment); with the cut disabled both do.
  LayerScene s = flatScene({200.0, 50.0}, 5, 6, 4, 909);
  s.target = cornerGridCamera(s.reference, 6, 5);
  const std::vector<double> layerCut =
      raster::rasterizeLayers(s.depthTensor(Dtype::F64), s.reference, s.target)
          .layerIndex()
          .toVector();
  raster::RasterSettings off;
  off.farZ = 0;
  const std::vector<double> layerAll =
      raster::rasterizeLayers(s.depthTensor(Dtype::F64), s.reference, s.target, off)
          .layerIndex()
          .toVector();
  const std::size_t plane = 5 * 6;
  const std::size_t pix = 2 * 6 + 3; // an interior pixel
  EXPECT_EQ(layerCut[pix], 1);
  EXPECT_EQ(layerCut[plane + pix], -1);
  EXPECT_EQ(layerAll[pix], 1);
  EXPECT_EQ(layerAll[plane + pix], 0);
  for (auto mode : {0, 1}) {
    s.settings.farZ = mode == 0 ? 120.0 : std::numeric_limits<double>::infinity();
    EXPECT_LT(maxRelativeError(
                  download(raster::renderLayers(s.depthTensor(Dtype::F32), s.attrTensor(Dtype::F32),
                                                s.reference, s.target, s.settings)),
                  referenceRender(s)),
              1e-5);
  }
}

} // namespace
} // namespace simpli::test

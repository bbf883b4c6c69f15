// Adaptive layer meshes (mli/adaptive_mesh.h): analytic cases (planes, a depth step, empty and
// partly transparent layers), the mesh's topology (no cracks, no overlaps) and the error bound
// on random depth maps, measured by measureAdaptiveMesh and checked to catch a poisoned mesh.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "mli_test_util.h"
#include "simpli/model/mli/adaptive_mesh.h"
#include "simpli/model/mli/mesh.h"

namespace simpli::test {
namespace {

mli::MLI oneLayer(int W, int H, float depth = 4.0f, float alpha = 1.0f) {
  mli::MLI mli = mli::MLI::allocate(generalCamera(W, H), 1);
  std::fill(mli.layers[0].depth.begin(), mli.layers[0].depth.end(), depth);
  for (std::size_t p = 0; p < mli.texels(); ++p)
    mli.layers[0].rgba[4 * p + 3] = alpha;
  return mli;
}

// Twice the signed area of triangle t in grid coordinates, positive for the mesh's winding.
double doubleArea(const mli::AdaptiveLayerMesh& m, std::size_t t) {
  const std::int32_t* v = &m.triangles[3 * t];
  auto g = [&](int c, int axis) { return static_cast<double>(m.grid[2 * v[c] + axis]); };
  return -((g(1, 0) - g(0, 0)) * (g(2, 1) - g(0, 1)) - (g(2, 0) - g(0, 0)) * (g(1, 1) - g(0, 1)));
}

double totalArea(const mli::AdaptiveLayerMesh& m) {
  double sum = 0;
  for (std::size_t t = 0; t < m.numTriangles(); ++t)
    sum += 0.5 * doubleArea(m, t);
  return sum;
}

// Every triangle has positive area (one winding) and, on a layer without cuts, every edge
// inside the domain is used by exactly two triangles in opposite directions; edges used once
// lie on the domain boundary. With positive areas summing to the domain's, the triangles tile
// the domain without gaps, overlaps or T-junctions.
void expectWatertight(const mli::AdaptiveLayerMesh& m, int W, int H) {
  std::map<std::pair<std::int32_t, std::int32_t>, int> directed;
  for (std::size_t t = 0; t < m.numTriangles(); ++t) {
    ASSERT_GT(doubleArea(m, t), 0.0) << "triangle " << t << " is degenerate or flipped";
    for (int e = 0; e < 3; ++e)
      ++directed[{m.triangles[3 * t + e], m.triangles[3 * t + (e + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    ASSERT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " used twice";
    if (directed.count({edge.second, edge.first}))
      continue;
    const float *a = &m.grid[2 * edge.first], *b = &m.grid[2 * edge.second];
    const bool onBoundary = (a[0] == b[0] && (a[0] == 0 || a[0] == W - 1)) ||
                            (a[1] == b[1] && (a[1] == 0 || a[1] == H - 1));
    EXPECT_TRUE(onBoundary) << "open edge (" << a[0] << "," << a[1] << ")-(" << b[0] << "," << b[1]
                            << ") inside the domain: a crack or T-junction";
  }
  EXPECT_NEAR(totalArea(m), static_cast<double>(W - 1) * (H - 1), 1e-6);
}

TEST(AdaptiveMesh, ConstantDepthOpaqueLayerIsTwoTriangles) {
  const mli::MLI mli = oneLayer(101, 77, 3.5f);
  const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0);
  EXPECT_EQ(m.numTriangles(), 2u);
  EXPECT_EQ(m.numPoints(), 4u);
  expectWatertight(m, 101, 77);
  const mli::AdaptiveMeshError e = mli::measureAdaptiveMesh(mli, 0, m);
  EXPECT_LT(e.maxPixels, 1e-9); // float32 depths: 1/d round trips to ~1e-16
  EXPECT_EQ(e.uncoveredVisibleTexels, 0u);
  EXPECT_EQ(e.visibleTexels, mli.texels());
}

TEST(AdaptiveMesh, VerticesLieOnTheirTexelRays) {
  const mli::MLI mli = oneLayer(9, 6, 2.75f);
  const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0);
  const mli::MLIMesh perTexel = mli::buildLayerMesh(mli, 0);
  ASSERT_EQ(m.numPoints(), 4u);
  for (std::size_t v = 0; v < m.numPoints(); ++v) {
    const int x = static_cast<int>(m.grid[2 * v]), y = static_cast<int>(m.grid[2 * v + 1]);
    const std::size_t p = static_cast<std::size_t>(y) * 9 + x;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(m.points[3 * v + c], perTexel.points[3 * p + c], 1e-5) << "vertex " << v;
    EXPECT_EQ(m.depth[v], 2.75f);
  }
}

// A plane n . X = c in reference-camera coordinates: 1/z = n . ray / c, affine in (u, v).
mli::MLI tiltedPlane(int W, int H, const Eigen::Vector3d& n, double c) {
  mli::MLI mli = oneLayer(W, H);
  const scene::Camera& cam = mli.camera;
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      const Eigen::Vector3d ray((j / (W - 1.0) - cam.cx) / cam.fx,
                                (i / (H - 1.0) - cam.cy) / cam.fy, 1.0);
      mli.layers[0].depth[static_cast<std::size_t>(i) * W + j] = static_cast<float>(c / n.dot(ray));
    }
  return mli;
}

TEST(AdaptiveMesh, TiltedPlaneIsExactAtAnyTolerance) {
  const mli::MLI mli = tiltedPlane(120, 90, {0.4, -0.3, 1.0}, 5.0);
  // The geometry is exact whatever the tolerance (down to float32 rounding of the depths); the
  // triangle count follows the texture swim, which shrinks with the tolerance.
  std::size_t previous = 0;
  for (double tolerance : {4.0, 0.25, 0.1, 1e-3}) {
    mli::AdaptiveMeshOptions o;
    o.tolerancePixels = tolerance;
    const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0, o);
    const mli::AdaptiveMeshError e = mli::measureAdaptiveMesh(mli, 0, m, o);
    EXPECT_LT(e.maxPixels, 1e-4) << "tolerance " << tolerance;
    EXPECT_LE(e.maxTextureSwim, tolerance) << "tolerance " << tolerance;
    EXPECT_GE(m.numTriangles(), previous) << "tolerance " << tolerance;
    expectWatertight(m, 120, 90);
    previous = m.numTriangles();
  }
  // A plane whose depth varies by 0.1 % over the layer swims by ~0.03 texels: two triangles.
  const mli::MLI gentle = tiltedPlane(120, 90, {0.0005, 0.0, 1.0}, 5.0);
  EXPECT_EQ(mli::buildAdaptiveLayerMesh(gentle, 0).numTriangles(), 2u);
}

TEST(AdaptiveMesh, TextureSwimOfTwoTrianglesIsMeasured) {
  // The poison for the swim: a slanted plane as two triangles (built at a huge tolerance) swims
  // by more than a texel, and the measurement sees it.
  const mli::MLI mli = tiltedPlane(120, 90, {0.4, -0.3, 1.0}, 5.0);
  mli::AdaptiveMeshOptions loose;
  loose.tolerancePixels = 1e5;
  const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0, loose);
  EXPECT_EQ(m.numTriangles(), 2u);
  EXPECT_GT(mli::measureAdaptiveMesh(mli, 0, m, loose).maxTextureSwim, 1.0);
}

TEST(AdaptiveMesh, CurvedLayerNeedsMoreTrianglesAtSmallerTolerance) {
  mli::MLI mli = oneLayer(200, 150);
  for (int i = 0; i < 150; ++i)
    for (int j = 0; j < 200; ++j)
      mli.layers[0].depth[static_cast<std::size_t>(i) * 200 + j] =
          static_cast<float>(4.0 + std::sin(j / 30.0) * std::cos(i / 25.0));
  std::size_t previous = 0;
  for (double tolerance : {4.0, 1.0, 0.25, 0.05}) {
    mli::AdaptiveMeshOptions o;
    o.tolerancePixels = tolerance;
    const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0, o);
    EXPECT_GT(m.numTriangles(), previous) << "tolerance " << tolerance;
    EXPECT_LT(m.numTriangles(), 2u * 199 * 149 / 4) << "tolerance " << tolerance;
    const mli::AdaptiveMeshError e = mli::measureAdaptiveMesh(mli, 0, m, o);
    EXPECT_LE(e.maxPixels, tolerance);
    EXPECT_LE(e.maxTextureSwim, tolerance);
    expectWatertight(m, 200, 150);
    previous = m.numTriangles();
  }
}

TEST(AdaptiveMesh, AllTransparentLayerHasNoTriangles) {
  const mli::MLI mli = oneLayer(33, 17, 2.0f, 0.5f / 255.0f);
  const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0);
  EXPECT_EQ(m.numTriangles(), 0u);
  EXPECT_EQ(m.numPoints(), 0u);
  // With threshold 0 everything counts as visible.
  mli::AdaptiveMeshOptions keepAll;
  keepAll.alphaThreshold = 0.0f;
  EXPECT_EQ(mli::buildAdaptiveLayerMesh(mli, 0, keepAll).numTriangles(), 2u);
}

TEST(AdaptiveMesh, OpaqueQuadrantIsTwoTriangles) {
  // The root cell is 64 x 48 quads; its top-left child is quads [0, 32) x [0, 24), i.e. the
  // texels x < 32, y < 24 visible (a quad is visible when a corner is).
  const int W = 65, H = 49;
  mli::MLI mli = oneLayer(W, H, 6.0f, 0.0f);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x)
      mli.layers[0].rgba[4 * (static_cast<std::size_t>(y) * W + x) + 3] = 1.0f;
  const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0);
  EXPECT_EQ(m.numTriangles(), 2u);
  EXPECT_NEAR(totalArea(m), 32.0 * 24.0, 1e-9);
  EXPECT_EQ(mli::measureAdaptiveMesh(mli, 0, m).uncoveredVisibleTexels, 0u);
}

TEST(AdaptiveMesh, TransparentRegionsAreRemovedAndNoTriangleIsInvisible) {
  const int W = 90, H = 70;
  mli::MLI mli = oneLayer(W, H, 5.0f, 0.0f);
  // A visible disc.
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      if (std::hypot(x - 40.3, y - 33.1) < 21.0)
        mli.layers[0].rgba[4 * (static_cast<std::size_t>(y) * W + x) + 3] = 0.8f;
  // Cut tightly (cells keep at most 16 transparent quads), and by default (at most 256: fewer
  // triangles, more of the transparent border drawn).
  mli::AdaptiveMeshOptions tight;
  tight.maxTransparentQuads = 16;
  const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0, tight);
  const mli::AdaptiveLayerMesh loose = mli::buildAdaptiveLayerMesh(mli, 0);
  const double disc = 3.14159265358979 * 21.0 * 21.0;
  EXPECT_GT(totalArea(m), 0.9 * disc);
  EXPECT_LT(totalArea(m), 1.5 * disc) << "transparent regions were drawn";
  EXPECT_LT(totalArea(loose), static_cast<double>(W - 1) * (H - 1) / 2);
  EXPECT_LT(loose.numTriangles(), m.numTriangles());
  EXPECT_EQ(mli::measureAdaptiveMesh(mli, 0, m).uncoveredVisibleTexels, 0u);
  EXPECT_EQ(mli::measureAdaptiveMesh(mli, 0, loose).uncoveredVisibleTexels, 0u);
  // No triangle lies over transparent quads only: sample each triangle's centroid's quad and
  // its neighbourhood (the triangle's own quads are within its bounding box).
  for (std::size_t t = 0; t < m.numTriangles(); ++t) {
    float x0 = 1e9f, x1 = -1e9f, y0 = 1e9f, y1 = -1e9f;
    for (int c = 0; c < 3; ++c) {
      const float* g = &m.grid[2 * m.triangles[3 * t + c]];
      x0 = std::min(x0, g[0]);
      x1 = std::max(x1, g[0]);
      y0 = std::min(y0, g[1]);
      y1 = std::max(y1, g[1]);
    }
    bool anyVisible = false;
    for (int y = static_cast<int>(std::floor(y0)); y <= static_cast<int>(std::ceil(y1)); ++y)
      for (int x = static_cast<int>(std::floor(x0)); x <= static_cast<int>(std::ceil(x1)); ++x)
        anyVisible =
            anyVisible || mli.layers[0].rgba[4 * (static_cast<std::size_t>(y) * W + x) + 3] > 0;
    EXPECT_TRUE(anyVisible) << "triangle " << t << " covers transparent texels only";
  }
}

// A layer at depth 2 on the left, 10 on the right of column `step`.
mli::MLI stepLayer(int W, int H, int step) {
  mli::MLI mli = oneLayer(W, H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      mli.layers[0].depth[static_cast<std::size_t>(y) * W + x] = x <= step ? 2.0f : 10.0f;
  return mli;
}

bool bridges(const mli::AdaptiveLayerMesh& m) {
  for (std::size_t t = 0; t < m.numTriangles(); ++t) {
    float lo = 1e30f, hi = 0;
    for (int c = 0; c < 3; ++c) {
      lo = std::min(lo, m.depth[m.triangles[3 * t + c]]);
      hi = std::max(hi, m.depth[m.triangles[3 * t + c]]);
    }
    if (hi > 1.5f * lo)
      return true;
  }
  return false;
}

TEST(AdaptiveMesh, DepthStepIsNotBridged) {
  const int W = 70, H = 41, step = 23;
  const mli::MLI mli = stepLayer(W, H, step);
  const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0);
  EXPECT_FALSE(bridges(m));
  EXPECT_EQ(m.cutQuads, static_cast<std::size_t>(H - 1));
  // The cut quads' quarters tile the domain: nothing is missing at the reference camera.
  for (std::size_t t = 0; t < m.numTriangles(); ++t)
    ASSERT_GT(doubleArea(m, t), 0.0);
  EXPECT_NEAR(totalArea(m), static_cast<double>(W - 1) * (H - 1), 1e-6);
  const mli::AdaptiveMeshError e = mli::measureAdaptiveMesh(mli, 0, m);
  EXPECT_EQ(e.uncoveredVisibleTexels, 0u);
  EXPECT_LT(e.maxPixels, 1e-9);
  // Few triangles: two planes plus the column of cut quads and the fans next to it.
  EXPECT_LT(m.numTriangles(), 30u * (H - 1));

  // Without cutting, the step is bridged (so the check above can fail).
  mli::AdaptiveMeshOptions bridge;
  bridge.discontinuityPixels = std::numeric_limits<double>::infinity();
  const mli::AdaptiveLayerMesh b = mli::buildAdaptiveLayerMesh(mli, 0, bridge);
  EXPECT_TRUE(bridges(b));
  EXPECT_EQ(b.cutQuads, 0u);
  expectWatertight(b, W, H);
}

// Smooth random relief, a few random steps, fine noise on part of it, and transparent blobs.
mli::MLI randomDepthLayer(int W, int H, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  mli::MLI mli = oneLayer(W, H);
  double a[4], f[4], ph[4];
  for (int k = 0; k < 4; ++k) {
    a[k] = 0.05 + 0.1 * uni(rng);
    f[k] = 2.0 + 10.0 * uni(rng);
    ph[k] = 6.28 * uni(rng);
  }
  const double stepX = uni(rng), stepY = uni(rng), blobX = uni(rng), blobY = uni(rng);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double u = x / (W - 1.0), v = y / (H - 1.0);
      double disparity = 0.6 + a[0] * std::sin(f[0] * u + ph[0]) +
                         a[1] * std::cos(f[1] * v + ph[1]) +
                         a[2] * std::sin(f[2] * (u + v) + ph[2]);
      if (u > stepX && v < stepY)
        disparity += 0.2; // a step
      if (u < 0.3 && v > 0.6)
        disparity += 0.002 * (uni(rng) - 0.5); // fine noise
      const std::size_t p = static_cast<std::size_t>(y) * W + x;
      mli.layers[0].depth[p] = static_cast<float>(1.0 / disparity);
      const bool hole = std::hypot(u - blobX, v - blobY) < 0.15 + 0.1 * std::sin(a[3] * 40 * u);
      mli.layers[0].rgba[4 * p + 3] =
          hole ? static_cast<float>(0.003 * uni(rng)) : static_cast<float>(0.05 + 0.95 * uni(rng));
      if (hole && uni(rng) < 0.5)
        mli.layers[0].depth[p] = static_cast<float>(1.0 + 50.0 * uni(rng)); // free depth
    }
  return mli;
}

struct RandomCase {
  int W, H;
  unsigned seed;
  double tolerance;
};

class AdaptiveMeshRandom : public ::testing::TestWithParam<RandomCase> {};

TEST_P(AdaptiveMeshRandom, ErrorIsWithinToleranceAndEveryVisibleTexelIsCovered) {
  const RandomCase c = GetParam();
  const mli::MLI mli = randomDepthLayer(c.W, c.H, c.seed);
  mli::AdaptiveMeshOptions o;
  o.tolerancePixels = c.tolerance;
  const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0, o);
  const mli::AdaptiveMeshError e = mli::measureAdaptiveMesh(mli, 0, m, o);
  ASSERT_GT(e.visibleTexels, 0u);
  EXPECT_EQ(e.uncoveredVisibleTexels, 0u);
  EXPECT_LE(e.maxPixels, c.tolerance * (1 + 1e-9));
  EXPECT_LE(e.maxTextureSwim, c.tolerance * (1 + 1e-9));
  // At most the eight quarter triangles of a cut quad per quad.
  EXPECT_LE(m.numTriangles(), 8u * (c.W - 1) * (c.H - 1));
  std::printf("%d x %d, tolerance %g px: %zu triangles (per-texel %d), %zu cut quads, %d passes\n",
              c.W, c.H, c.tolerance, m.numTriangles(), 2 * (c.W - 1) * (c.H - 1), m.cutQuads,
              m.passes);
  for (std::size_t t = 0; t < m.numTriangles(); ++t)
    ASSERT_GT(doubleArea(m, t), 0.0) << "triangle " << t;

  // Poison: move one vertex that a visible texel sits on off its depth by 2x the tolerance's
  // worth of 1/d; the measurement must see it.
  const double scale = mli::pixelsPerInverseDepth(mli, o);
  for (std::size_t v = 0; v < m.numPoints(); ++v) {
    const float gx = m.grid[2 * v], gy = m.grid[2 * v + 1];
    if (gx != std::floor(gx) || gy != std::floor(gy))
      continue;
    const std::size_t p = static_cast<std::size_t>(gy) * c.W + static_cast<std::size_t>(gx);
    if (mli.layers[0].rgba[4 * p + 3] < o.alphaThreshold)
      continue;
    mli::AdaptiveLayerMesh poisoned = m;
    const double disparity = 1.0 / m.depth[v] + (2.0 * c.tolerance + 0.1) / scale;
    poisoned.depth[v] = static_cast<float>(1.0 / disparity);
    EXPECT_GT(mli::measureAdaptiveMesh(mli, 0, poisoned, o).maxPixels, c.tolerance);
    break;
  }
}

TEST_P(AdaptiveMeshRandom, OpaqueWithoutCutsIsWatertight) {
  const RandomCase c = GetParam();
  mli::MLI mli = randomDepthLayer(c.W, c.H, c.seed);
  for (std::size_t p = 0; p < mli.texels(); ++p)
    mli.layers[0].rgba[4 * p + 3] = 1.0f;
  mli::AdaptiveMeshOptions o;
  o.tolerancePixels = c.tolerance;
  o.discontinuityPixels = std::numeric_limits<double>::infinity();
  const mli::AdaptiveLayerMesh m = mli::buildAdaptiveLayerMesh(mli, 0, o);
  expectWatertight(m, c.W, c.H);
  EXPECT_LE(mli::measureAdaptiveMesh(mli, 0, m, o).maxPixels, c.tolerance * (1 + 1e-9));
}

std::string randomCaseName(const ::testing::TestParamInfo<RandomCase>& info) {
  const RandomCase& c = info.param;
  return "W" + std::to_string(c.W) + "_H" + std::to_string(c.H) + "_seed" + std::to_string(c.seed) +
         "_tol" + std::to_string(static_cast<int>(c.tolerance * 1000)) + "milli";
}

INSTANTIATE_TEST_SUITE_P(Cases, AdaptiveMeshRandom,
                         ::testing::Values(RandomCase{2, 2, 1, 0.25}, RandomCase{3, 97, 2, 0.25},
                                           RandomCase{37, 23, 3, 0.1}, RandomCase{128, 96, 4, 0.25},
                                           RandomCase{161, 121, 5, 1.0},
                                           RandomCase{250, 180, 6, 0.05},
                                           RandomCase{250, 180, 7, 0.5}),
                         randomCaseName);

TEST(AdaptiveMesh, CameraOffsetScalesTheErrorMeasure) {
  const mli::MLI mli = oneLayer(40, 30, 4.0f);
  mli::AdaptiveMeshOptions o;
  // Focus depth of a constant layer is its depth: the default offset is 0.05 x 4.
  EXPECT_NEAR(mli::defaultCameraOffset(mli), 0.2, 1e-12);
  const double fpx = std::max(mli.camera.fx * 40, mli.camera.fy * 30);
  EXPECT_NEAR(mli::pixelsPerInverseDepth(mli, o), 0.2 * fpx, 1e-9);
  o.cameraOffset = 0.7;
  EXPECT_NEAR(mli::pixelsPerInverseDepth(mli, o), 0.7 * fpx, 1e-9);
}

TEST(AdaptiveMesh, BadOptionsAndLayerIndexAreNamedErrors) {
  const mli::MLI mli = oneLayer(4, 3);
  auto with = [&](auto set) {
    mli::AdaptiveMeshOptions o;
    set(o);
    return [&mli, o] { mli::buildAdaptiveLayerMesh(mli, 0, o); };
  };
  expectError(with([](auto& o) { o.tolerancePixels = -1; }), {"tolerancePixels", "-1"});
  expectError(with([](auto& o) { o.tolerancePixels = std::nan(""); }), {"tolerancePixels"});
  expectError(with([](auto& o) { o.cameraOffset = -0.5; }), {"cameraOffset", "-0.5"});
  expectError(with([](auto& o) { o.discontinuityPixels = 0; }), {"discontinuityPixels", "0"});
  expectError(with([](auto& o) { o.alphaThreshold = 2; }), {"alphaThreshold", "2"});
  expectError(with([](auto& o) { o.maxTransparentQuads = -1; }), {"maxTransparentQuads", "-1"});
  expectError([&] { mli::buildAdaptiveLayerMesh(mli, 1); }, {"layer index 1", "[0, 1)"});
}

} // namespace
} // namespace simpli::test

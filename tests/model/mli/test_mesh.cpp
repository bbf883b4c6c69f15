// Corner-grid meshes (spec §6.6) against analytic cases.
#include <array>
#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "mli_test_util.h"
#include "simpli/error.h"
#include "simpli/model/mli/mesh.h"

namespace simpli::test {
namespace {

scene::Camera identityCamera(int W, int H) {
  scene::Camera c;
  c.fx = 0.8;
  c.fy = 1.1;
  c.cx = 0.45;
  c.cy = 0.55;
  c.width = W;
  c.height = H;
  return c;
}

Eigen::Vector3d point(const mli::MLIMesh& m, std::size_t p) {
  return {m.points[3 * p], m.points[3 * p + 1], m.points[3 * p + 2]};
}

TEST(MLIMesh, ConstantDepthWithIdentityCameraLiesOnTheCornerGrid) {
  const int H = 5, W = 7;
  const float d = 3.25f;
  mli::MLI mli = mli::MLI::allocate(identityCamera(W, H), 1);
  for (float& v : mli.layers[0].depth)
    v = d;
  const mli::MLIMesh mesh = mli::buildMLIMesh(mli);
  ASSERT_EQ(mesh.numPoints(), static_cast<std::size_t>(H * W));
  const scene::Camera& c = mli.camera;
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      const std::size_t p = static_cast<std::size_t>(i) * W + j;
      const double u = static_cast<double>(j) / (W - 1), v = static_cast<double>(i) / (H - 1);
      EXPECT_EQ(mesh.points[3 * p + 0], static_cast<float>(d * ((u - c.cx) / c.fx)));
      EXPECT_EQ(mesh.points[3 * p + 1], static_cast<float>(d * ((v - c.cy) / c.fy)));
      EXPECT_EQ(mesh.points[3 * p + 2], d);
      EXPECT_FLOAT_EQ(mesh.uv[2 * p + 0], static_cast<float>(u));
      EXPECT_FLOAT_EQ(mesh.uv[2 * p + 1], static_cast<float>(v));
      EXPECT_EQ(mesh.depth[p], d);
    }
  // The four image corners sit on the rays through the corners of the image.
  EXPECT_FLOAT_EQ(mesh.points[0], static_cast<float>(d * (0 - c.cx) / c.fx));
  EXPECT_FLOAT_EQ(mesh.points[3 * (W - 1)], static_cast<float>(d * (1 - c.cx) / c.fx));
}

TEST(MLIMesh, GeneralCameraVerticesProjectBackToTheirTexels) {
  const int L = 2, H = 6, W = 9;
  const mli::MLI mli = randomMLI(L, H, W, 11, 1.0f, 20.0f);
  const mli::MLIMesh mesh = mli::buildMLIMesh(mli);
  const scene::Camera& c = mli.camera;
  ASSERT_EQ(mesh.numPoints(), static_cast<std::size_t>(L * H * W));
  for (int k = 0; k < L; ++k)
    for (int i = 0; i < H; ++i)
      for (int j = 0; j < W; ++j) {
        const std::size_t t = static_cast<std::size_t>(i) * W + j;
        const std::size_t p = static_cast<std::size_t>(k) * H * W + t;
        const Eigen::Vector3d xc = c.R * point(mesh, p) + c.t;
        const double d = mli.layers[static_cast<std::size_t>(k)].depth[t];
        // Points are stored as float: ~1e-7 relative to the scene scale (~20).
        EXPECT_NEAR(xc.z(), d, 2e-5 * d);
        EXPECT_NEAR(c.fx * xc.x() / xc.z() + c.cx, static_cast<double>(j) / (W - 1), 1e-5);
        EXPECT_NEAR(c.fy * xc.y() / xc.z() + c.cy, static_cast<double>(i) / (H - 1), 1e-5);
        // And the helper agrees with the builder.
        EXPECT_LT((mli::mliVertex(c, i, j, d) - point(mesh, p)).norm(), 1e-5 * d);
      }
}

TEST(MLIMesh, VertexAttributesAreTheTexels) {
  const mli::MLI mli = randomMLI(3, 4, 5, 12);
  const mli::MLIMesh mesh = mli::buildMLIMesh(mli);
  const std::size_t n = 20;
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t t = 0; t < n; ++t) {
      EXPECT_EQ(mesh.depth[k * n + t], mli.layers[k].depth[t]);
      for (std::size_t ch = 0; ch < 4; ++ch)
        EXPECT_EQ(mesh.rgba[4 * (k * n + t) + ch], mli.layers[k].rgba[4 * t + ch]);
    }
}

TEST(MLIMesh, FacesOfTwoLayersOfTwoByThree) {
  const mli::MLI mli = randomMLI(2, 2, 3, 13);
  const mli::MLIMesh mesh = mli::buildMLIMesh(mli);
  // Written out by hand from §6.6: quads at b = 0, 1; layer 1 offset 6.
  const std::vector<std::int32_t> expected = {0, 3, 4,  0, 4,  1, 1, 4,  5,  1, 5,  2,
                                              6, 9, 10, 6, 10, 7, 7, 10, 11, 7, 11, 8};
  EXPECT_EQ(mesh.triangles, expected);
}

TEST(MLIMesh, FaceCountAndIndexRangePerLayer) {
  const int L = 3, H = 5, W = 8;
  const mli::MLI mli = randomMLI(L, H, W, 14);
  const mli::MLIMesh mesh = mli::buildMLIMesh(mli);
  const std::size_t perLayer = 2 * (H - 1) * (W - 1);
  ASSERT_EQ(mesh.numTriangles(), L * perLayer);
  for (std::size_t f = 0; f < mesh.numTriangles(); ++f) {
    const std::int32_t k = static_cast<std::int32_t>(f / perLayer);
    for (int v = 0; v < 3; ++v) {
      EXPECT_GE(mesh.triangles[3 * f + v], k * H * W);
      EXPECT_LT(mesh.triangles[3 * f + v], (k + 1) * H * W);
    }
  }
}

TEST(MLIMesh, WindingIsConsistentAndFacesTheReferenceCamera) {
  // Camera z forward, y down: (b, b+W, b+W+1) turns so that its normal points back to -z.
  const int H = 4, W = 5;
  mli::MLI mli = mli::MLI::allocate(identityCamera(W, H), 1);
  for (float& v : mli.layers[0].depth)
    v = 2.0f;
  const mli::MLIMesh mesh = mli::buildMLIMesh(mli);
  for (std::size_t f = 0; f < mesh.numTriangles(); ++f) {
    const Eigen::Vector3d a = point(mesh, mesh.triangles[3 * f]);
    const Eigen::Vector3d b = point(mesh, mesh.triangles[3 * f + 1]);
    const Eigen::Vector3d c = point(mesh, mesh.triangles[3 * f + 2]);
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    EXPECT_LT(normal.z(), 0.0) << "face " << f;
    EXPECT_NEAR(normal.x(), 0.0, 1e-9);
    EXPECT_NEAR(normal.y(), 0.0, 1e-9);
  }
}

TEST(MLIMesh, LayerMeshIsTheSliceOfTheFullMeshWithLocalIndices) {
  const int L = 3, H = 4, W = 6;
  const mli::MLI mli = randomMLI(L, H, W, 15);
  const mli::MLIMesh all = mli::buildMLIMesh(mli);
  const std::size_t n = H * W, perLayer = 2 * (H - 1) * (W - 1);
  for (int k = 0; k < L; ++k) {
    const mli::MLIMesh one = mli::buildLayerMesh(mli, k);
    ASSERT_EQ(one.numPoints(), n);
    ASSERT_EQ(one.numTriangles(), perLayer);
    for (std::size_t e = 0; e < 3 * n; ++e)
      EXPECT_EQ(one.points[e], all.points[3 * k * n + e]);
    for (std::size_t e = 0; e < 3 * perLayer; ++e)
      EXPECT_EQ(one.triangles[e] + k * static_cast<std::int32_t>(n),
                all.triangles[3 * k * perLayer + e]);
  }
  expectError([&] { mli::buildLayerMesh(mli, 3); }, {"layer index 3", "out of range"});
  expectError([&] { mli::buildLayerMesh(mli, -1); }, {"layer index -1"});
}

TEST(MLIMesh, DropsOnlyTrianglesWhoseThreeVerticesAreTransparent) {
  const int H = 5, W = 6;
  mli::MLI mli = randomMLI(2, H, W, 16);
  // Layer 0: alpha 0 on the left half (columns 0..2), 1 elsewhere. Layer 1: alpha 0 everywhere.
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      mli.layers[0].rgba[4 * (i * W + j) + 3] = j <= 2 ? 0.0f : 1.0f;
      mli.layers[1].rgba[4 * (i * W + j) + 3] = 0.0f;
    }
  EXPECT_EQ(mli::emptyLayers(mli), std::vector<int>{1});

  const std::size_t full = 2 * (H - 1) * (W - 1);
  EXPECT_EQ(mli::buildMLIMesh(mli).numTriangles(), 2 * full) << "default keeps everything";

  mli::MLIMeshOptions drop;
  drop.dropAlphaBelow = 1.0f / 255.0f;
  const mli::MLIMesh mesh = mli::buildMLIMesh(mli, drop);
  // Quads with j in {0, 1} are fully transparent; those with j = 2 touch column 3 on both of
  // their triangles, so they stay. Layer 1 loses everything.
  EXPECT_EQ(mesh.numTriangles(), full - 2 * (H - 1) * 2);
  EXPECT_EQ(mesh.numPoints(), static_cast<std::size_t>(2 * H * W)) << "vertices are kept";
  for (std::size_t f = 0; f < mesh.numTriangles(); ++f) {
    bool visible = false;
    for (int v = 0; v < 3; ++v) {
      const std::int32_t idx = mesh.triangles[3 * f + v];
      ASSERT_LT(idx, H * W) << "no face may come from the empty layer";
      visible = visible || mesh.rgba[4 * idx + 3] >= drop.dropAlphaBelow;
    }
    EXPECT_TRUE(visible) << "face " << f;
  }
  EXPECT_EQ(mli::buildLayerMesh(mli, 1, drop).numTriangles(), 0u);
}

TEST(MLIMesh, InvalidMLIIsRejectedBeforeBuilding) {
  mli::MLI mli = randomMLI(1, 3, 3, 17);
  mli.layers[0].depth[4] = -1.0f;
  expectError([&] { mli::buildMLIMesh(mli); }, {"buildMLIMesh", "depth at (row 1, col 1)"});
}

} // namespace
} // namespace simpli::test

// Bad-use errors, the triangle numbering and the MLI bridge of the rasterizer.
#include "raster_test_util.h"

#include "support/expect_error.h"

#include "simpli/model/mli/mesh.h"
#include "simpli/model/raster/rasterizer.h"
#include "simpli/model/raster/render_mli.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace simpli::test {
namespace {

using ocl::Dtype;
using ocl::Tensor;

struct Fixture {
  LayerScene s = randomScene(2, 4, 5, 4, 0.2, 7);
  Fixture() { s.target = cornerGridCamera(s.reference, 5, 4); }
  Tensor depth() const { return s.depthTensor(Dtype::F32); }
  Tensor attrs() const { return s.attrTensor(Dtype::F32); }
};

TEST(RasterErrors, BadDepthAndAttributes) {
  Fixture f;
  const scene::Camera& ref = f.s.reference;
  const scene::Camera& tgt = f.s.target;
  expectError([&] { raster::rasterizeLayers(Tensor(), ref, tgt); }, {"rasterizeLayers", "depth"});
  expectError(
      [&] {
        raster::rasterizeLayers(Tensor::ones({4, 5}), ref, tgt);
      },
      {"rasterizeLayers", "depth", "f32[4, 5]", "[L, H, W]"});
  expectError(
      [&] {
        raster::rasterizeLayers(Tensor::ones({2, 1, 5}), ref, tgt);
      },
      {"depth", "f32[2, 1, 5]", "2 x 2"});
  expectError(
      [&] {
        raster::renderLayers(f.depth(), Tensor::ones({2, 4, 3, 5}), ref, tgt);
      },
      {"shadeFragments", "attributes", "f32[2, 4, 3, 5]", "[2, A, 4, 5]"});
  expectError(
      [&] {
        raster::renderLayers(f.depth(), Tensor::ones({2, 1, 4, 5}), ref, tgt);
      },
      {"attributes", "f32[2, 1, 4, 5]", "A >= 2"});
  expectError(
      [&] {
        raster::renderLayers(f.depth(), Tensor::ones({2, 4, 5}), ref, tgt);
      },
      {"renderLayers", "attributes", "f32[2, 4, 5]"});
  expectError([&] { raster::renderLayers(f.depth(), f.s.attrTensor(Dtype::F64), ref, tgt); },
              {"dtype", "f64[2, 4, 4, 5]", "f32[2, 4, 5]"});
  const raster::RasterFragments frags = raster::rasterizeLayers(f.depth(), ref, tgt);
  expectError([&] { raster::shadeFragments(frags, f.s.depthTensor(Dtype::F64), f.attrs()); },
              {"shadeFragments", "depth", "f64[2, 4, 5]", "dtype"});
  expectError(
      [&] {
        raster::shadeFragments(frags, Tensor::ones({3, 4, 5}), f.attrs());
      },
      {"shadeFragments", "depth", "f32[3, 4, 5]", "[2, 4, 5]"});
  expectError([&] { raster::shadeFragments(raster::RasterFragments{}, f.depth(), f.attrs()); },
              {"shadeFragments", "empty"});
  expectError([&] { raster::RasterFragments{}.triangleIds(); }, {"triangleIds"});
  expectError([&] { raster::RasterFragments{}.layerIndex(); }, {"layerIndex"});
}

TEST(RasterErrors, BadCameras) {
  Fixture f;
  scene::Camera bad = f.s.target;
  bad.fx = 0;
  expectError([&] { raster::rasterizeLayers(f.depth(), f.s.reference, bad); },
              {"rasterizeLayers", "target", "fx = 0"});
  bad = f.s.reference;
  bad.cy = std::numeric_limits<double>::quiet_NaN();
  expectError([&] { raster::rasterizeLayers(f.depth(), bad, f.s.target); },
              {"reference", "cy", "nan"});
  bad = f.s.target;
  bad.R(0, 0) = -bad.R(0, 0);
  expectError([&] { raster::rasterizeLayers(f.depth(), f.s.reference, bad); },
              {"target", "rotation"});
  bad = f.s.target;
  bad.t.x() = std::numeric_limits<double>::infinity();
  expectError([&] { raster::rasterizeLayers(f.depth(), f.s.reference, bad); },
              {"target", "non-finite"});
  bad = f.s.target;
  bad.width = 0;
  expectError([&] { raster::rasterizeLayers(f.depth(), f.s.reference, bad); },
              {"target", "size", "0x4"});
}

TEST(RasterErrors, BadSettings) {
  Fixture f;
  auto run = [&](raster::RasterSettings s) {
    raster::rasterizeLayers(f.depth(), f.s.reference, f.s.target, s);
  };
  raster::RasterSettings s;
  s.maxFragments = 0;
  expectError([&] { run(s); }, {"maxFragments = 0", "1..64"});
  s = {};
  s.maxFragments = 65;
  expectError([&] { run(s); }, {"maxFragments = 65"});
  s = {};
  s.nearZ = 0;
  expectError([&] { run(s); }, {"nearZ = 0"});
  s = {};
  s.nearZ = std::numeric_limits<double>::infinity();
  expectError([&] { run(s); }, {"nearZ = inf"});
  s = {};
  s.farZ = 0.005;
  expectError([&] { run(s); }, {"farZ = 0.005", "nearZ = 0.01"});
  s = {};
  s.farZ = std::numeric_limits<double>::quiet_NaN();
  expectError([&] { run(s); }, {"farZ", "NaN"});
  s = {};
  s.tileSize = 12;
  expectError([&] { run(s); }, {"tileSize = 12"});
  s = {};
  s.maxBinEntries = 0;
  expectError([&] { run(s); }, {"maxBinEntries = 0"});
  s = {};
  s.interpolation = static_cast<raster::RasterInterpolation>(7);
  expectError([&] { run(s); }, {"interpolation = 7"});
}

TEST(RasterApi, TriangleNumberingFollowsTheReferenceMesh) {
  // Quad with top-left vertex b = i*W + j gives (b, b+W, b+W+1) then (b, b+W+1, b+1); layers
  // are offset by H*W vertices and 2(H-1)(W-1) triangles.
  const int H = 4, W = 5;
  EXPECT_EQ(raster::layerTriangleVertices(0, H, W), (std::array<int64_t, 3>{0, 5, 6}));
  EXPECT_EQ(raster::layerTriangleVertices(1, H, W), (std::array<int64_t, 3>{0, 6, 1}));
  EXPECT_EQ(raster::layerTriangleVertices(2 * 5 + 1, H, W), (std::array<int64_t, 3>{6, 12, 7}));
  EXPECT_EQ(raster::layerTriangleVertices(24, H, W), (std::array<int64_t, 3>{20, 25, 26}));
  expectError([] { raster::layerTriangleVertices(-1, 4, 5); }, {"layerTriangleVertices", "-1"});
  expectError([] { raster::layerTriangleVertices(0, 1, 5); }, {"layerTriangleVertices", "1x5"});
}

TEST(RasterApi, TriangleNumberingMatchesTheMeshBuilder) {
  scene::Camera cam = testReferenceCamera(5, 4);
  mli::MLI mli = mli::MLI::allocate(cam, 2);
  const mli::MLIMesh mesh = mli::buildMLIMesh(mli);
  ASSERT_EQ(mesh.numTriangles(), std::size_t(2 * 2 * 3 * 4));
  // Same triangles (as vertex sets with orientation) in some order.
  std::vector<std::array<int64_t, 3>> ours, theirs;
  for (std::size_t t = 0; t < mesh.numTriangles(); ++t) {
    ours.push_back(raster::layerTriangleVertices(static_cast<int64_t>(t), 4, 5));
    theirs.push_back({mesh.triangles[3 * t], mesh.triangles[3 * t + 1], mesh.triangles[3 * t + 2]});
  }
  std::sort(ours.begin(), ours.end());
  std::sort(theirs.begin(), theirs.end());
  EXPECT_EQ(ours, theirs);
}

TEST(RasterApi, MliTensorsAndRenderMli) {
  const int H = 6, W = 7, L = 3;
  scene::Camera cam = testReferenceCamera(W, H);
  mli::MLI mli = mli::MLI::allocate(cam, L);
  const std::vector<double> rnd = randomValues(std::size_t(L) * H * W * 5, 0.0, 1.0, 3);
  std::size_t n = 0;
  for (int k = 0; k < L; ++k) {
    for (auto& d : mli.layers[k].depth)
      d = static_cast<float>(8.0 / (1 + k) * (1 + 0.2 * rnd[n++]));
    for (auto& c : mli.layers[k].rgba)
      c = static_cast<float>(rnd[n++]);
  }
  const raster::MLITensors t = raster::mliTensors(mli, Dtype::F64);
  ASSERT_EQ(t.depth.shape(), (ocl::Shape{L, H, W}));
  ASSERT_EQ(t.rgba.shape(), (ocl::Shape{L, 4, H, W}));
  const std::vector<double> depth = t.depth.toVector(), rgba = t.rgba.toVector();
  for (int k = 0; k < L; ++k)
    for (int p = 0; p < H * W; ++p) {
      ASSERT_EQ(depth[k * H * W + p], mli.layers[k].depth[p]);
      for (int c = 0; c < 4; ++c)
        ASSERT_EQ(rgba[(k * 4 + c) * H * W + p], mli.layers[k].rgba[4 * p + c]);
    }
  const scene::Camera target = cornerGridCamera(cam, W, H);
  const raster::RenderedLayers a = raster::renderMLI(mli, target, {}, Dtype::F64);
  const raster::RenderedLayers b = raster::renderLayers(t.depth, t.rgba, cam, target);
  EXPECT_EQ(a.colour.toVector(), b.colour.toVector());
  EXPECT_EQ(a.opacity.toVector(), b.opacity.toVector());
  EXPECT_EQ(a.colour.shape(), (ocl::Shape{3, H, W}));
  mli.layers[1].depth[4] = -1.0f;
  expectError([&] { raster::mliTensors(mli); }, {"mliTensors", "depth", "-1"});
}

} // namespace
} // namespace simpli::test

// The OpenCL renderer of the adaptive display form (raster/render_adaptive.h): a textured plane
// against a closed-form ray-plane-texture reference, the farthest-fragment rule, agreement with
// the per-texel rasterizer on a layered MLI, poisoned outputs, float vs double, errors.
#include "raster_test_util.h"
#include "support/expect_error.h"

#include "simpli/model/raster/render_adaptive.h"
#include "simpli/model/raster/render_mli.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <string>

namespace simpli::test {
namespace {

using ocl::Dtype;

// One layer at constant depth d, random RGBA with alpha in [aLo, aHi].
mli::MLI texturedPlane(int W, int H, float d, double aLo, double aHi, unsigned seed) {
  mli::MLI mli = mli::MLI::allocate(testReferenceCamera(W, H), 1);
  const std::vector<double> rnd = randomValues(mli.texels() * 4, 0.0, 1.0, seed);
  for (std::size_t p = 0; p < mli.texels(); ++p) {
    mli.layers[0].depth[p] = d;
    for (int c = 0; c < 3; ++c)
      mli.layers[0].rgba[4 * p + c] = static_cast<float>(rnd[4 * p + c]);
    mli.layers[0].rgba[4 * p + 3] = static_cast<float>(aLo + (aHi - aLo) * rnd[4 * p + 3]);
  }
  return mli;
}

// Closed form for a constant-depth layer: the ray of pixel (c, r) meets the plane z_ref = d;
// its reference projection gives the grid position; the texels are sampled bilinearly. Returns
// false outside the grid.
bool planeReference(const mli::MLI& mli, const scene::Camera& target, int c, int r, double* rgb) {
  const Eigen::Matrix3d K = target.pixelK();
  const Eigen::Vector3d dir =
      target.R.transpose() * K.inverse() * Eigen::Vector3d(c + 0.5, r + 0.5, 1.0);
  const Eigen::Vector3d origin = target.centre();
  const scene::Camera& ref = mli.camera;
  const double d = mli.layers[0].depth[0];
  // z_ref(origin + s dir) = d.
  const double s = (d - ref.depth(origin)) / (ref.R.row(2).dot(dir));
  const Eigen::Vector2d uv = ref.project(origin + s * dir);
  const int W = mli.width(), H = mli.height();
  const double gx = uv.x() * (W - 1), gy = uv.y() * (H - 1);
  if (!(gx >= 0 && gx <= W - 1 && gy >= 0 && gy <= H - 1))
    return false;
  const int j0 = std::min(static_cast<int>(gx), W - 2), i0 = std::min(static_cast<int>(gy), H - 2);
  const double a = gx - j0, b = gy - i0;
  auto texel = [&](int i, int j, int ch) {
    return static_cast<double>(mli.layers[0].rgba[4 * (static_cast<std::size_t>(i) * W + j) + ch]);
  };
  for (int ch = 0; ch < 3; ++ch)
    rgb[ch] = (1 - b) * ((1 - a) * texel(i0, j0, ch) + a * texel(i0, j0 + 1, ch)) +
              b * ((1 - a) * texel(i0 + 1, j0, ch) + a * texel(i0 + 1, j0 + 1, ch));
  return true;
}

scene::Camera movedCamera(const scene::Camera& ref, int W, int H) {
  scene::Camera cam = ref;
  cam.R = smallRotation(3.0, 5) * ref.R;
  cam.t = cam.R * -(ref.centre() + ref.R.transpose() * Eigen::Vector3d(0.3, -0.2, 0.4));
  cam.width = W;
  cam.height = H;
  cam.fx = 0.9;
  cam.fy = 0.9 * W / H;
  return cam;
}

TEST(RenderAdaptive, TexturedPlaneMatchesTheRayPlaneTextureReference) {
  PoisonScope poison;
  const mli::MLI mli = texturedPlane(23, 17, 5.0f, 1.0, 1.0, 1);
  const raster::AdaptiveMLI adaptive = raster::buildAdaptiveMLI(mli);
  ASSERT_EQ(adaptive.numTriangles(), 2u);
  const scene::Camera target = movedCamera(mli.camera, 96, 72);
  for (Dtype dt : {Dtype::F64, Dtype::F32}) {
    const raster::AdaptiveRender out = raster::renderAdaptiveMLI(adaptive, target, {}, dt);
    ASSERT_EQ(out.colour.shape(), (ocl::Shape{3, 72, 96}));
    const std::vector<double> colour = out.colour.toVector(), opacity = out.opacity.toVector();
    ASSERT_TRUE(allFinite(colour) && allFinite(opacity)) << "unwritten (poisoned) pixels";
    // The mesh's vertices are float32 world points: ~1e-7 of position error even in double.
    const double tol = dt == Dtype::F64 ? 2e-6 : 2e-4;
    int inside = 0;
    for (int r = 0; r < 72; ++r)
      for (int c = 0; c < 96; ++c) {
        double rgb[3];
        const std::size_t p = static_cast<std::size_t>(r) * 96 + c;
        if (!planeReference(mli, target, c, r, rgb)) {
          continue; // outside the grid, or on its border where rounding decides
        }
        ++inside;
        EXPECT_NEAR(opacity[p], 1.0, tol) << "pixel " << c << ", " << r;
        for (int ch = 0; ch < 3; ++ch)
          EXPECT_NEAR(colour[ch * 72 * 96 + p], rgb[ch], tol) << "pixel " << c << ", " << r;
      }
    EXPECT_GT(inside, 72 * 96 / 4);
  }
}

TEST(RenderAdaptive, FarthestFragmentIsOpaqueAndEmptyPixelsAreZero) {
  PoisonScope poison;
  const mli::MLI mli = texturedPlane(12, 9, 4.0f, 0.3, 0.3, 2);
  const raster::AdaptiveMLI adaptive = raster::buildAdaptiveMLI(mli);
  // A wide view: the plane fills the middle; the border sees nothing.
  scene::Camera target = mli.camera;
  target.fx *= 0.5;
  target.fy *= 0.5;
  target.width = 40;
  target.height = 30;
  const raster::AdaptiveRender out = raster::renderAdaptiveMLI(adaptive, target);
  const std::vector<double> colour = out.colour.toVector(), opacity = out.opacity.toVector();
  ASSERT_TRUE(allFinite(colour) && allFinite(opacity));
  EXPECT_EQ(opacity[0], 0.0);
  EXPECT_EQ(colour[0], 0.0);
  const std::size_t centre = 15 * 40 + 20;
  EXPECT_FLOAT_EQ(static_cast<float>(opacity[centre]), 1.0f) << "alpha 0.3, yet the only fragment";
  // All transparent: nothing drawn at all.
  mli::MLI clear = mli;
  for (std::size_t p = 0; p < clear.texels(); ++p)
    clear.layers[0].rgba[4 * p + 3] = 0.0f;
  const raster::AdaptiveMLI none = raster::buildAdaptiveMLI(clear);
  EXPECT_EQ(none.numTriangles(), 0u);
  const raster::AdaptiveRender empty = raster::renderAdaptiveMLI(none, target);
  for (double v : empty.opacity.toVector())
    ASSERT_EQ(v, 0.0);
}

// Three smooth layers, the far one opaque, the others with holes and partial alpha.
mli::MLI layeredMLI(int W, int H) {
  mli::MLI mli = mli::MLI::allocate(testReferenceCamera(W, H), 3);
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      const std::size_t p = static_cast<std::size_t>(i) * W + j;
      const double u = j / (W - 1.0), v = i / (H - 1.0);
      for (int k = 0; k < 3; ++k) {
        mli::MLILayer& l = mli.layers[static_cast<std::size_t>(k)];
        l.depth[p] = static_cast<float>(9.0 / (1 + k) * (1 + 0.1 * std::sin(3 * u + k) * v));
        l.rgba[4 * p + 0] = static_cast<float>(0.5 + 0.4 * std::sin(0.4 * j + k));
        l.rgba[4 * p + 1] = static_cast<float>(0.5 + 0.4 * std::cos(0.3 * i));
        l.rgba[4 * p + 2] = static_cast<float>(0.5 + 0.3 * std::sin(0.2 * (i + j)));
        const double hole = std::hypot(u - 0.3 * k - 0.2, v - 0.5) < 0.2 ? 0.0 : 0.6;
        l.rgba[4 * p + 3] = static_cast<float>(k == 0 ? 1.0 : hole * (0.5 + 0.5 * u));
      }
    }
  return mli;
}

TEST(RenderAdaptive, AgreesWithThePerTexelRasterizer) {
  const mli::MLI mli = layeredMLI(64, 48);
  // A mesh finer than the default (1 px): the comparison is of the renderers, not the meshes.
  mli::AdaptiveMeshOptions fine;
  fine.tolerancePixels = 0.25;
  const raster::AdaptiveMLI adaptive = raster::buildAdaptiveMLI(mli, fine);
  EXPECT_LT(adaptive.numTriangles(), 3u * 2 * 63 * 47 / 4);
  const scene::Camera target = movedCamera(mli.camera, 160, 120);
  raster::RasterSettings perspective;
  perspective.interpolation = raster::RasterInterpolation::PerspectiveCorrect;
  const raster::RenderedLayers ref = raster::renderMLI(mli, target, perspective, Dtype::F64);
  const raster::AdaptiveRender out = raster::renderAdaptiveMLI(adaptive, target, {}, Dtype::F64);
  const std::vector<double> a = out.colour.toVector(), b = ref.colour.toVector();
  const std::vector<double> oa = out.opacity.toVector(), ob = ref.opacity.toVector();
  const std::size_t n = 160 * 120;
  double se = 0;
  std::size_t compared = 0;
  for (std::size_t p = 0; p < n; ++p) {
    if (!(oa[p] > 0.999 && ob[p] > 0.999))
      continue;
    ++compared;
    for (int c = 0; c < 3; ++c)
      se += (a[c * n + p] - b[c * n + p]) * (a[c * n + p] - b[c * n + p]);
  }
  ASSERT_GT(compared, n * 7 / 10);
  const double psnr = 10 * std::log10(3.0 * compared / se);
  std::printf("adaptive (%zu triangles) vs per-texel rasterizer: %.2f dB over %zu pixels\n",
              adaptive.numTriangles(), psnr, compared);
  EXPECT_GT(psnr, 40.0);
}

TEST(RenderAdaptive, BadInputIsANamedError) {
  const mli::MLI mli = texturedPlane(6, 5, 3.0f, 1.0, 1.0, 3);
  raster::AdaptiveMLI adaptive = raster::buildAdaptiveMLI(mli);
  const scene::Camera target = movedCamera(mli.camera, 16, 12);
  raster::AdaptiveRenderSettings s;
  s.tileSize = 2;
  expectError([&] { raster::renderAdaptiveMLI(adaptive, target, s); }, {"tileSize", "2"});
  s = {};
  s.nearZ = 0;
  expectError([&] { raster::renderAdaptiveMLI(adaptive, target, s); }, {"nearZ", "0"});
  raster::AdaptiveMLI wrong = adaptive;
  wrong.meshes.push_back(wrong.meshes[0]);
  expectError([&] { raster::renderAdaptiveMLI(wrong, target); }, {"2 meshes for 1 layers"});
  wrong = adaptive;
  wrong.meshes[0].grid[0] = 9.0f;
  expectError([&] { raster::renderAdaptiveMLI(wrong, target); },
              {"layer 0", "vertex 0", "outside the 6 x 5 grid"});
  wrong = adaptive;
  wrong.meshes[0].triangles[1] = 7;
  expectError([&] { raster::renderAdaptiveMLI(wrong, target); }, {"vertex 7 of 4"});
}

} // namespace
} // namespace simpli::test

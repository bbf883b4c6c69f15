// The plane-sweep stereo baseline (baselines/plane_sweep_stereo.h) on an analytic scene: a
// textured fronto-parallel plane at depth 3 behind a textured rectangle at depth 1.5, seen by
// four cameras of a handheld path. Away from the rectangle's edges and the image border, the
// recovered depth must match the rendered true depth within a plane spacing of disparity, and
// the colour the reference camera's own render; options and inputs out of range are named
// errors.
#include "simpli/model/baselines/plane_sweep_stereo.h"
#include "simpli/model/generator/scene_input.h"
#include "simpli/model/geometry/planes.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/synthetic/renderer.h"
#include "simpli/model/synthetic/scene.h"

#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include "support/expect_error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace simpli {
namespace {

synthetic::Texture noiseTexture(uint64_t seed, double frequency) {
  synthetic::Texture t;
  t.pattern = synthetic::Pattern::Noise;
  t.colourA = Eigen::Vector3d(0.1, 0.3, 0.15);
  t.colourB = Eigen::Vector3d(0.9, 0.7, 0.5);
  t.frequency = frequency;
  t.detail = 0.5;
  t.seed = seed;
  return t;
}

struct StereoCase {
  synthetic::SyntheticScene scene;
  std::vector<io::Image> images;
  generator::GeneratorInput input;
  synthetic::RenderedView truth; ///< the reference camera's own render (colour and depth)
};

StereoCase makeCase() {
  synthetic::SyntheticSceneParams p;
  p.width = 192;
  p.height = 144;
  p.views = 4;
  p.nearDepth = 1.0;
  p.translation = 0.3; // the farthest camera 0.3 from the mean: ~17 px at depth 3, ~33 at 1.5
  p.antialias = 2;
  p.seed = 3;
  synthetic::Shape background;
  background.kind = synthetic::ShapeKind::Plane;
  background.role = synthetic::ShapeRole::Background;
  background.centre = Eigen::Vector3d(0, 0, 3);
  background.texture = noiseTexture(1, 6.0);
  synthetic::Shape front;
  front.kind = synthetic::ShapeKind::Rectangle;
  front.role = synthetic::ShapeRole::FrontoPlane;
  front.centre = Eigen::Vector3d(0.05, 0.0, 1.5);
  front.size = Eigen::Vector3d(0.2, 0.15, 0);
  front.texture = noiseTexture(2, 12.0);
  StereoCase c;
  c.scene = synthetic::makeSyntheticScene(p, background, {front});
  std::vector<const io::Image*> pointers;
  for (const synthetic::RenderedView& v : synthetic::renderViews(c.scene))
    c.images.push_back(v.image());
  for (const io::Image& im : c.images)
    pointers.push_back(&im);
  const scene::Camera reference = scene::referenceCamera(c.scene.cameras);
  c.input = generator::scaledInput(pointers, c.scene.cameras, reference, 1.0, ocl::Dtype::F32);
  c.input.minDepth = 1.0;
  c.input.maxDepth = 100.0;
  c.truth = synthetic::renderView(c.scene, reference, /*jitterSeed=*/7);
  return c;
}

/// True when every true depth within `radius` pixels of (x, y) equals the pixel's own (one
/// surface all around, inside the image).
bool awayFromEdges(const synthetic::RenderedView& t, int x, int y, int radius) {
  if (x < radius || y < radius || x + radius >= t.width || y + radius >= t.height)
    return false;
  const float z = t.depthAt(x, y);
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx)
      if (std::abs(t.depthAt(x + dx, y + dy) - z) > 0.05f * z) // another surface
        return false;
  return true;
}

TEST(PlaneSweepStereo, RecoversTwoFrontoParallelSurfaces) {
  const StereoCase c = makeCase();
  const baselines::PlaneSweepStereoOptions options;
  const generator::GeneratorOutput out = baselines::planeSweepStereo(c.input, options);
  const int H = c.truth.height, W = c.truth.width;
  ASSERT_EQ(out.rgba.shape(), (ocl::Shape{1, 4, H, W}));
  ASSERT_EQ(out.depth.shape(), (ocl::Shape{1, H, W}));
  const std::vector<float> depth = out.depth.toVectorF32(), rgba = out.rgba.toVectorF32();
  const io::Image truthImage = c.truth.image();
  const std::vector<double> planes = geometry::planeDepths(options.planes, 1.0, 100.0);
  const double spacing = 1.0 / planes[1] - 1.0 / planes[0]; // uniform in disparity
  const size_t HW = size_t(H) * W;
  int checked[2] = {0, 0}, matched[2] = {0, 0};
  double colourError = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * W + x;
      EXPECT_EQ(rgba[3 * HW + i], 1.0f);
      const float z = c.truth.depthAt(x, y);
      const int surface = z < 2 ? 1 : 0; // 1 = the rectangle in front
      // Background: beyond the disparity difference (~17 px) plus half the window (5) from the
      // rectangle; rectangle: beyond half the window from its edge.
      if (!awayFromEdges(c.truth, x, y, surface == 1 ? 6 : 24))
        continue;
      ++checked[surface];
      if (std::abs(1.0 / depth[i] - 1.0 / z) <= 1.5 * spacing)
        ++matched[surface];
      for (int ch = 0; ch < 3; ++ch)
        colourError += std::abs(rgba[ch * HW + i] - truthImage.data[ch * HW + i]);
    }
  ASSERT_GT(checked[0], 200);
  ASSERT_GT(checked[1], 100);
  EXPECT_GE(matched[0], 0.95 * checked[0]) << matched[0] << " of " << checked[0];
  EXPECT_GE(matched[1], 0.95 * checked[1]) << matched[1] << " of " << checked[1];
  // RGB in [-1, 1]: the mean of four resampled views against the reference's own render.
  EXPECT_LT(colourError / (3.0 * (checked[0] + checked[1])), 0.06);
}

// The softmin distribution over another plane set (a network's 17 planes), area-averaged to a
// quarter of the size: every cell sums to 1, and cells inside the rectangle peak at its plane.
TEST(PlaneSweepStereo, PlaneProbabilitiesOnANetworksPlanes) {
  const StereoCase c = makeCase();
  const std::vector<double> planes = geometry::planeDepths(17, 1.0, 100.0);
  const int H = c.truth.height, W = c.truth.width, h = H / 4, w = W / 4;
  const std::vector<std::vector<double>> prob =
      baselines::planeProbabilities(c.input, planes, {}, h, w);
  ASSERT_EQ(prob.size(), planes.size());
  size_t nearestToFront = 0;
  for (size_t p = 1; p < planes.size(); ++p)
    if (std::abs(1 / planes[p] - 1 / 1.5) < std::abs(1 / planes[nearestToFront] - 1 / 1.5))
      nearestToFront = p;
  int inside = 0, peaked = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t j = size_t(y) * w + x;
      double sum = 0;
      size_t best = 0;
      for (size_t p = 0; p < planes.size(); ++p) {
        sum += prob[p][j];
        if (prob[p][j] > prob[best][j])
          best = p;
      }
      EXPECT_NEAR(sum, 1.0, 1e-9);
      if (awayFromEdges(c.truth, 4 * x + 2, 4 * y + 2, 8) &&
          c.truth.depthAt(4 * x + 2, 4 * y + 2) < 2) {
        ++inside;
        peaked += best == nearestToFront;
      }
    }
  ASSERT_GT(inside, 10);
  EXPECT_GE(peaked, 0.9 * inside) << peaked << " of " << inside;
  test::expectError([&] { baselines::planeProbabilities(c.input, planes, {}, 7, w); },
                    {"does not divide", "192 x 144"});
}

/// Largest |device - host| over a [P, h, w] volume and its host reference [P][h * w].
double maxDifference(const ocl::Tensor& device, const std::vector<std::vector<double>>& host) {
  const std::vector<double> d = device.toVector();
  EXPECT_EQ(device.shape(), (ocl::Shape{int64_t(host.size()), device.size(1), device.size(2)}));
  double worst = 0;
  for (size_t p = 0; p < host.size(); ++p)
    for (size_t j = 0; j < host[p].size(); ++j)
      worst = std::max(worst, std::abs(d[p * host[p].size() + j] - host[p][j]));
  return worst;
}

// The device volume (the network's photo prior) against the host version in double precision:
// the default options at a quarter of the size, and a wider window, a softer softmin and
// chunks of 3 planes (the counts concatenated) at full size. Near planes leave border points
// seen by fewer than two sources (the unmatched cost); with one source every point is
// unmatched and the distribution uniform.
TEST(PlaneSweepStereo, DeviceVolumeMatchesTheHostReference) {
  StereoCase c = makeCase();
  const std::vector<double> planes = geometry::planeDepths(17, 1.0, 100.0);
  const int H = c.truth.height, W = c.truth.width;
  baselines::PlaneSweepStereoOptions other;
  other.windowFraction = 0.1;
  other.temperature = 1e-2;
  other.planesPerChunk = 3;
  for (const ocl::Dtype dtype : {ocl::Dtype::F64, ocl::Dtype::F32}) {
    generator::GeneratorInput in = c.input;
    in.images = c.input.images.to(dtype);
    const double tolerance = dtype == ocl::Dtype::F64 ? 1e-6 : 1e-3;
    const ocl::Tensor quarter = baselines::planeProbabilityVolume(in, planes, {}, H / 4, W / 4);
    EXPECT_EQ(quarter.dtype(), dtype);
    EXPECT_LT(maxDifference(quarter, baselines::planeProbabilities(in, planes, {}, H / 4, W / 4)),
              tolerance);
    EXPECT_LT(maxDifference(baselines::planeProbabilityVolume(in, planes, other, H, W),
                            baselines::planeProbabilities(in, planes, other, H, W)),
              tolerance);
  }
  // Some points of the nearest plane are seen by fewer than two sources (else the unmatched
  // branch above went untested).
  const std::vector<double> seen =
      ocl::sum(geometry::planeSweep(c.input.images, c.input.reference, c.input.sources,
                                    {planes.back()}, H, W)
                   .mask,
               0)
          .toVector();
  EXPECT_GT(std::count_if(seen.begin(), seen.end(), [](double n) { return n < 2; }), 100);
  generator::GeneratorInput one = c.input;
  one.images = ocl::slice(c.input.images, 0, 0, 1);
  one.sources.resize(1);
  const std::vector<double> uniform =
      baselines::planeProbabilityVolume(one, planes, {}, H / 4, W / 4).toVector();
  for (double v : uniform)
    ASSERT_NEAR(v, 1.0 / 17.0, 1e-6);
  test::expectError([&] { baselines::planeProbabilityVolume(c.input, planes, {}, 7, W); },
                    {"does not divide", "192 x 144"});
}

TEST(PlaneSweepStereo, OptionsAndInputsAreNamed) {
  using test::expectError;
  const StereoCase c = makeCase();
  auto bad = [&](auto change, std::initializer_list<std::string> parts) {
    baselines::PlaneSweepStereoOptions o;
    change(o);
    expectError([&] { baselines::planeSweepStereo(c.input, o); }, parts);
  };
  bad([](auto& o) { o.planes = 1; }, {"planes 1", "2 .. 4096"});
  bad([](auto& o) { o.windowFraction = -0.1; }, {"windowFraction -0.1"});
  bad([](auto& o) { o.temperature = 0; }, {"temperature 0"});
  bad([](auto& o) { o.temperature = std::nan(""); }, {"temperature nan"});
  bad([](auto& o) { o.planesPerChunk = 0; }, {"planesPerChunk 0"});
  generator::GeneratorInput fewer = c.input;
  fewer.sources.pop_back();
  expectError([&] { baselines::planeSweepStereo(fewer); }, {"4 images for 3 source cameras"});
  baselines::PlaneSweepStereoOptions o;
  EXPECT_EQ(baselines::windowPixels(o, 256), 15);
  EXPECT_EQ(baselines::windowPixels(o, 10), 1);
  o.windowFraction = 0;
  EXPECT_EQ(baselines::windowPixels(o, 256), 1);
}

} // namespace
} // namespace simpli

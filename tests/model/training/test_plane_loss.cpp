// The level-0 plane supervision: targets against analytic cameras and surfaces, the
// cross-entropy against a double reference and central differences.
#include "support/expect_error.h"

#include "simpli/model/geometry/planes.h"
#include "simpli/model/training/plane_loss.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace simpli::training {
namespace {

scene::Camera camera(const Eigen::Vector3d& centre) {
  scene::Camera c;
  c.fx = 0.9;
  c.fy = 1.2;
  c.cx = 0.47;
  c.cy = 0.52;
  c.width = 8;
  c.height = 6;
  c.t = -c.R * centre;
  return c;
}

// Planes at depths 1, 2, 4 (disparities 1, 0.5, 0.25), listed farthest first.
const std::vector<double> kPlanes{4.0, 2.0, 1.0};

// The target of source `v`'s pixel (x, y) on plane p, for a 4x3 render.
double at(const PlaneTargets& t, int v, int p, int y, int x) {
  return t.values[size_t(((v * 3 + p) * 3 + y) * 4 + x)];
}

TEST(PlaneLoss, TargetsFollowTheTrueDisparity) {
  const scene::Camera ref = camera({0, 0, 0});
  // A source beside the reference sees a fronto-parallel wall at the same z; one 1 unit behind
  // it sees the wall 1 unit farther than the reference does.
  const std::vector<scene::Camera> sources{camera({0.3, -0.2, 0}), camera({0, 0, -1})};
  // 8x6 depth maps rendered at 4x3: each render pixel takes the texel under its centre.
  std::vector<float> wallA(48, 2.0f), wallB(48, 3.0f);
  wallA[size_t(1 * 8 + 1)] = 0;            // render pixel (0, 0): texel (1, 1) sees the sky
  wallA[size_t(3 * 8 + 3)] = 1.0f / 0.75f; // render pixel (1, 1): disparity 0.75
  wallA[size_t(5 * 8 + 7)] = 100.0f;       // render pixel (3, 2): beyond the farthest plane
  wallB[size_t(1 * 8 + 1)] = 0.5f; // source 1 pixel (0, 0): z_ref 0.5 - 1 < 0, behind the reference
  const PlaneTargets t = planeTargets(kPlanes, ref, sources, {wallA, wallB}, 8, 6, 3, 4);
  ASSERT_EQ(t.values.size(), 2u * 3u * 12u);
  // Source 0 sits 0.3 to the right: its wall points (z 2) appear 0.9 * 0.3 / 2 = 0.135 further
  // right in the reference, so its last column (u 0.875) falls outside the reference image
  // (outside the MPI) except at z 100: 12 - 2 = 10 targets. Source 1, 1 unit
  // behind, sees 1.5x wider than the reference at the wall: only (u, v) in the middle
  // columns of rows 1 and 2 map inside: 4 targets.
  EXPECT_EQ(t.known, 10 + 4);
  for (int p = 0; p < 3; ++p) {
    EXPECT_EQ(at(t, 0, p, 0, 3), 0.0) << "outside the MPI, no target";
    EXPECT_EQ(at(t, 0, p, 1, 3), 0.0) << "outside the MPI, no target";
    EXPECT_EQ(at(t, 1, p, 0, 0), 0.0) << "behind the reference, no target";
  }
  // Wall at z 2 (source 0): all on the middle plane. Disparity 0.75: half way between 1 and 2.
  EXPECT_DOUBLE_EQ(at(t, 0, 1, 1, 2), 1.0);
  EXPECT_NEAR(at(t, 0, 1, 1, 1), 0.5, 1e-6); // (the depth map is float)
  EXPECT_NEAR(at(t, 0, 2, 1, 1), 0.5, 1e-6);
  EXPECT_DOUBLE_EQ(at(t, 0, 0, 2, 3), 1.0); // z 100: the back plane takes it all
  EXPECT_DOUBLE_EQ(at(t, 0, 0, 0, 0), 1.0); // the sky (z 0, at infinity): likewise
  EXPECT_EQ(at(t, 0, 1, 0, 0) + at(t, 0, 2, 0, 0), 0.0);
  // Source 1 sees z 3, i.e. z_ref 2: the middle plane.
  EXPECT_NEAR(at(t, 1, 1, 2, 2), 1.0, 1e-12);
  // Every known pixel's targets sum to 1.
  for (int v = 0; v < 2; ++v)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) {
        const double s = at(t, v, 0, y, x) + at(t, v, 1, y, x) + at(t, v, 2, y, x);
        EXPECT_TRUE(s == 0.0 || std::abs(s - 1) < 1e-12) << v << " " << y << " " << x;
      }
}

// A tilted source: the point it sees is moved into the reference and the target follows its
// reference z, checked against a point placed by hand.
TEST(PlaneLoss, TargetsUseTheReferenceDepthOfTheSeenPoint) {
  const std::vector<double> planes = geometry::planeDepths(9, 1.0, 10.0);
  const scene::Camera ref = camera({0, 0, 0});
  scene::Camera src = camera({0.4, 0.1, -0.3});
  src.R = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  src.t = -src.R * Eigen::Vector3d(0.4, 0.1, -0.3);
  const std::vector<float> depth(48, 2.5f);
  const PlaneTargets t = planeTargets(planes, ref, {src}, {depth}, 8, 6, 3, 4);
  // Render pixel (x 2, y 1): ray through (2.5 / 4, 1.5 / 3) at source z 2.5.
  const double u = 2.5 / 4, w = 1.5 / 3, z = 2.5;
  const Eigen::Vector3d world =
      src.cameraToWorld({(u - src.cx) / src.fx * z, (w - src.cy) / src.fy * z, z});
  const double s = 1 / ref.worldToCamera(world).z();
  double expected = 0; // the mean disparity of the target distribution
  for (size_t p = 0; p < planes.size(); ++p)
    expected += t.values[p * 12 + 1 * 4 + 2] / planes[p];
  EXPECT_NEAR(expected, s, 1e-12);
  EXPECT_NE(std::abs(s - 1 / z), 0.0) << "the rotation and offset change the depth";
}

// The sky (depth 0) lies at infinity: only the rotation between the cameras moves it. A source
// turned 0.5 rad about y sees directions whose azimuth atan((u - cx) / fx) is 0.5 rad smaller
// in the reference: columns u 0.125 .. 0.875 go from -0.37, -0.10, 0.17, 0.42 rad to -0.87,
// -0.60, -0.33, -0.08, and the reference sees -0.48 .. 0.53 rad: the last two columns (every
// row: their vertical slopes stay within 0.92-1.04x) land on the back plane, the first two
// have no target. Translation does not matter at infinity.
TEST(PlaneLoss, SkyTargetsTheBackPlaneWhereItsDirectionIsInTheReference) {
  const scene::Camera ref = camera({0, 0, 0});
  scene::Camera src = camera({5, -3, 2});
  src.R = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()).toRotationMatrix();
  src.t = -src.R * Eigen::Vector3d(5, -3, 2);
  std::vector<float> sky(48, 0.0f);
  std::vector<float> bad = sky;
  bad[size_t(1 * 8 + 7)] = -2.0f; // render pixel (3, 0): a negative depth, no target
  const PlaneTargets t = planeTargets(kPlanes, ref, {src, src}, {sky, bad}, 8, 6, 3, 4);
  EXPECT_EQ(t.known, 6 + 5);
  for (int v = 0; v < 2; ++v)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) {
        const bool back = x >= 2 && !(v == 1 && y == 0 && x == 3);
        EXPECT_EQ(at(t, v, 0, y, x), back ? 1.0 : 0.0) << v << " " << y << " " << x;
        EXPECT_EQ(at(t, v, 1, y, x) + at(t, v, 2, y, x), 0.0) << v << " " << y << " " << x;
      }
}

TEST(PlaneLoss, CrossEntropyMatchesDoubleReferenceAndFiniteDifferences) {
  std::mt19937 g(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const ocl::Shape shape{2, 3, 1, 2, 2};
  const size_t n = 24;
  std::vector<double> w(n);
  for (double& x : w)
    x = unit(g);
  PlaneTargets t;
  t.values.assign(n, 0.0);
  for (int v = 0; v < 2; ++v)
    for (int pix = 0; pix < 4; ++pix) {
      if (v == 1 && pix == 3)
        continue; // unknown pixel
      const double a = unit(g);
      t.values[size_t((v * 3 + pix % 3) * 4 + pix)] = a;
      t.values[size_t((v * 3 + (pix + 1) % 3) * 4 + pix)] = 1 - a;
      ++t.known;
    }
  auto reference = [&](const std::vector<double>& weights) {
    double s = 0;
    for (size_t k = 0; k < n; ++k)
      s -= t.values[k] * std::log(weights[k] + 1e-6);
    return s / double(t.known);
  };
  ocl::Tensor x = ocl::Tensor::fromHost(w, shape, ocl::Dtype::F64);
  x.setRequiresGrad(true);
  const ocl::Tensor loss = planeCrossEntropy(x, t);
  EXPECT_NEAR(loss.item(), reference(w), 1e-12);
  loss.backward();
  const std::vector<double> grad = x.grad().toVector();
  const double h = 1e-6;
  for (size_t k = 0; k < n; ++k) {
    std::vector<double> p = w, m = w;
    p[k] += h;
    m[k] -= h;
    EXPECT_NEAR(grad[k], (reference(p) - reference(m)) / (2 * h), 1e-6) << k;
  }
  // Weights equal to the targets minimise it over distributions; none known: 0.
  const ocl::Tensor exact = ocl::Tensor::fromHost(t.values, shape, ocl::Dtype::F64);
  EXPECT_LT(planeCrossEntropy(exact, t).item(), loss.item());
  PlaneTargets none;
  none.values.assign(n, 0.0);
  EXPECT_EQ(planeCrossEntropy(x, none).item(), 0.0);
}

TEST(PlaneLoss, RejectsMismatchedInputs) {
  const scene::Camera ref = camera({0, 0, 0});
  const std::vector<float> depth(48, 2.0f);
  test::expectError([&] { planeTargets({}, ref, {ref}, {depth}, 8, 6, 3, 4); }, {"no planes"});
  test::expectError(
      [&] {
        planeTargets({1.0, 2.0}, ref, {ref}, {depth}, 8, 6, 3, 4);
      },
      {"farthest to the nearest"});
  test::expectError(
      [&] {
        planeTargets(kPlanes, ref, {ref, ref}, {depth}, 8, 6, 3, 4);
      },
      {"1 depth maps for 2 sources"});
  test::expectError([&] { planeTargets(kPlanes, ref, {ref}, {depth}, 8, 5, 3, 4); },
                    {"depth map 0 has 48 values, not 8x5"});
  PlaneTargets t;
  t.values.assign(10, 0.0);
  test::expectError(
      [&] {
        planeCrossEntropy(ocl::Tensor::zeros({2, 3, 1, 2, 2}, ocl::Dtype::F64), t);
      },
      {"planeCrossEntropy", "10 target values"});
}

} // namespace
} // namespace simpli::training

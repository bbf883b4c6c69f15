// Spiral and orbit trajectories: frame count, closed paths, the focus point at the principal
// point of every frame, radii, no roll, LLFF defaults, and clear errors for bad parameters.
#include "simpli/model/scene/trajectory.h"

#include "simpli/error.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace simpli {
namespace {

scene::Camera reference() {
  scene::Camera c;
  c.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  c.t = Eigen::Vector3d(0.4, -0.2, 1.3);
  c.fx = 0.9;
  c.fy = 1.2;
  c.cx = 0.45;
  c.cy = 0.55;
  c.width = 64;
  c.height = 48;
  return c;
}

scene::TrajectoryOptions options(scene::TrajectoryKind kind) {
  scene::TrajectoryOptions o;
  o.kind = kind;
  o.frames = 24;
  o.radii = Eigen::Vector3d(0.3, 0.2, 0.1);
  o.focusDepth = 5.0;
  return o;
}

// Offset of the camera centre in the reference frame.
Eigen::Vector3d offsetOf(const scene::Camera& ref, const scene::Camera& c) {
  return ref.R * (c.centre() - ref.centre());
}

std::string errorOf(const scene::TrajectoryOptions& o, const scene::Camera& ref = reference()) {
  try {
    scene::makeTrajectory(ref, o);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

class TrajectoryKinds : public ::testing::TestWithParam<scene::TrajectoryKind> {};

TEST_P(TrajectoryKinds, FrameCountAndIntrinsics) {
  const scene::Camera ref = reference();
  for (int n : {1, 2, 7, 60}) {
    scene::TrajectoryOptions o = options(GetParam());
    o.frames = n;
    const auto cams = scene::makeTrajectory(ref, o);
    ASSERT_EQ(static_cast<int>(cams.size()), n);
    for (const scene::Camera& c : cams) {
      EXPECT_EQ(c.fx, ref.fx);
      EXPECT_EQ(c.fy, ref.fy);
      EXPECT_EQ(c.cx, ref.cx);
      EXPECT_EQ(c.cy, ref.cy);
      EXPECT_EQ(c.width, ref.width);
      EXPECT_EQ(c.height, ref.height);
    }
  }
}

TEST_P(TrajectoryKinds, ClosedPath) {
  const scene::Camera ref = reference();
  const scene::TrajectoryOptions o = options(GetParam());
  const scene::Camera a = scene::trajectoryCamera(ref, o, 0.0),
                      b = scene::trajectoryCamera(ref, o, 1.0);
  EXPECT_LT((a.centre() - b.centre()).norm(), 1e-12);
  EXPECT_LT((a.R - b.R).cwiseAbs().maxCoeff(), 1e-12);
  // ... and the frames do move: consecutive frames differ, the last one is near the first.
  const auto cams = scene::makeTrajectory(ref, o);
  const double step = (cams[1].centre() - cams[0].centre()).norm();
  EXPECT_GT(step, 1e-3);
  EXPECT_LT((cams.back().centre() - cams.front().centre()).norm(), 2.0 * step);
}

TEST_P(TrajectoryKinds, FocusPointAtThePrincipalPoint) {
  const scene::Camera ref = reference();
  const scene::TrajectoryOptions o = options(GetParam());
  const Eigen::Vector3d F = ref.backproject({ref.cx, ref.cy}, o.focusDepth);
  for (const scene::Camera& c : scene::makeTrajectory(ref, o)) {
    const Eigen::Vector2d uv = c.project(F);
    EXPECT_NEAR(uv.x(), ref.cx, 1e-12);
    EXPECT_NEAR(uv.y(), ref.cy, 1e-12);
    EXPECT_NEAR(c.depth(F), (F - c.centre()).norm(), 1e-12); // in front, on the axis
    // Proper rotation, and no roll: the camera's x axis is orthogonal to the reference's down.
    EXPECT_LT((c.R * c.R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(c.R.determinant(), 1.0, 1e-12);
    EXPECT_NEAR(c.R.row(0).dot(ref.R.row(1)), 0.0, 1e-12);
    EXPECT_GT(c.R.row(1).dot(ref.R.row(1)), 0.9); // still upright
  }
}

INSTANTIATE_TEST_SUITE_P(Kinds, TrajectoryKinds,
                         ::testing::Values(scene::TrajectoryKind::Spiral,
                                           scene::TrajectoryKind::Orbit),
                         [](const auto& info) { return std::string(toString(info.param)); });

TEST(Trajectory, OrbitIsAnEllipseInTheImagePlane) {
  const scene::Camera ref = reference();
  const scene::TrajectoryOptions o = options(scene::TrajectoryKind::Orbit);
  for (const scene::Camera& c : scene::makeTrajectory(ref, o)) {
    const Eigen::Vector3d d = offsetOf(ref, c);
    EXPECT_NEAR(std::pow(d.x() / 0.3, 2) + std::pow(d.y() / 0.2, 2), 1.0, 1e-12);
    EXPECT_NEAR(d.z(), 0.0, 1e-12);
  }
  // Frame 0 at +x, a quarter turn later at +y.
  scene::TrajectoryOptions four = o;
  four.frames = 4;
  const auto cams = scene::makeTrajectory(ref, four);
  EXPECT_LT((offsetOf(ref, cams[0]) - Eigen::Vector3d(0.3, 0, 0)).norm(), 1e-12);
  EXPECT_LT((offsetOf(ref, cams[1]) - Eigen::Vector3d(0, 0.2, 0)).norm(), 1e-12);
}

TEST(Trajectory, SpiralRadiiAndDepth) {
  const scene::Camera ref = reference();
  scene::TrajectoryOptions o = options(scene::TrajectoryKind::Spiral);
  o.frames = 400;
  Eigen::Vector3d maxAbs = Eigen::Vector3d::Zero();
  for (const scene::Camera& c : scene::makeTrajectory(ref, o)) {
    const Eigen::Vector3d d = offsetOf(ref, c);
    maxAbs = maxAbs.cwiseMax(d.cwiseAbs());
    // LLFF's parametrisation: (rx cos t, -ry sin t, -rz sin(t/2)).
    const double cosT = d.x() / 0.3, sinT = -d.y() / 0.2;
    EXPECT_NEAR(cosT * cosT + sinT * sinT, 1.0, 1e-9);
  }
  EXPECT_NEAR(maxAbs.x(), 0.3, 1e-6);
  EXPECT_NEAR(maxAbs.y(), 0.2, 1e-4);
  EXPECT_NEAR(maxAbs.z(), 0.1, 1e-4);
  // Frame 0 sits at +x exactly.
  EXPECT_LT(
      (offsetOf(ref, scene::trajectoryCamera(ref, o, 0.0)) - Eigen::Vector3d(0.3, 0, 0)).norm(),
      1e-12);
}

TEST(Trajectory, RadiiFromCameras) {
  const scene::Camera ref = reference();
  std::vector<scene::Camera> cams;
  // Centres at known offsets in the reference frame: |x| = 0..0.9 in steps of 0.1.
  for (int i = 0; i < 10; ++i) {
    scene::Camera c = ref;
    const Eigen::Vector3d C =
        ref.centre() + ref.R.transpose() * Eigen::Vector3d((i % 2 ? -0.1 : 0.1) * i, 0.02 * i, 0);
    c.t = -c.R * C;
    cams.push_back(c);
  }
  const Eigen::Vector3d r = scene::trajectoryRadii(ref, cams);
  // numpy.percentile(|x|, 90) of 0, 0.1, ..., 0.9 = 0.81.
  EXPECT_NEAR(r.x(), 0.81, 1e-12);
  EXPECT_NEAR(r.y(), 0.162, 1e-12);
  EXPECT_NEAR(r.z(), 0.0, 1e-12);
  EXPECT_EQ(scene::trajectoryRadii(ref, {ref}), Eigen::Vector3d::Zero());
  EXPECT_THROW(scene::trajectoryRadii(ref, {}), Error);
}

TEST(Trajectory, FocusDepth) {
  EXPECT_DOUBLE_EQ(scene::trajectoryFocusDepth(2.0, 2.0), 2.0);
  EXPECT_DOUBLE_EQ(scene::trajectoryFocusDepth(1.0, 100.0), 1.0 / (0.25 + 0.0075));
  EXPECT_THROW(scene::trajectoryFocusDepth(0.0, 10.0), Error);
  EXPECT_THROW(scene::trajectoryFocusDepth(5.0, 1.0), Error);
  EXPECT_THROW(scene::trajectoryFocusDepth(1.0, NAN), Error);
}

TEST(Trajectory, ResolveDefaults) {
  const scene::Camera ref = reference();
  scene::TrajectoryOptions o;
  o.frames = 5;
  // No cameras: focus from the bounds, the small default motion.
  scene::TrajectoryOptions r = scene::resolveTrajectory(o, ref, {}, 2.0, 2.0);
  EXPECT_DOUBLE_EQ(r.focusDepth, 2.0);
  EXPECT_LT((r.radii - Eigen::Vector3d(0.1, 0.1, 0.05)).norm(), 1e-15);
  // Cameras: LLFF's percentile radii.
  scene::Camera moved = ref;
  moved.t = -moved.R * (ref.centre() + ref.R.transpose() * Eigen::Vector3d(0.2, 0, 0));
  r = scene::resolveTrajectory(o, ref, {ref, moved}, 1.0, 100.0);
  EXPECT_NEAR(r.radii.x(), 0.18, 1e-12); // 90th percentile of {0, 0.2}
  EXPECT_DOUBLE_EQ(r.focusDepth, 1.0 / (0.25 + 0.0075));
  // Explicit values are kept; bad bounds are reported when they are needed.
  o.radii = Eigen::Vector3d(1, 2, 3);
  o.focusDepth = 7;
  r = scene::resolveTrajectory(o, ref, {}, -1, -1);
  EXPECT_EQ(r.radii, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(r.focusDepth, 7);
  o.focusDepth = 0;
  EXPECT_THROW(scene::resolveTrajectory(o, ref, {}, 0, 10), Error);
}

TEST(Trajectory, KindNames) {
  EXPECT_EQ(scene::parseTrajectoryKind("spiral"), scene::TrajectoryKind::Spiral);
  EXPECT_EQ(scene::parseTrajectoryKind("orbit"), scene::TrajectoryKind::Orbit);
  try {
    scene::parseTrajectoryKind("circle");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'circle'"), std::string::npos) << e.what();
  }
}

TEST(Trajectory, BadParameters) {
  scene::TrajectoryOptions o = options(scene::TrajectoryKind::Spiral);
  o.frames = 0;
  EXPECT_NE(errorOf(o).find("frames = 0"), std::string::npos) << errorOf(o);
  o = options(scene::TrajectoryKind::Spiral);
  o.radii = Eigen::Vector3d(0.1, -0.2, 0);
  EXPECT_NE(errorOf(o).find("radii (0.1, -0.2, 0)"), std::string::npos) << errorOf(o);
  o.radii = Eigen::Vector3d::Zero();
  EXPECT_NE(errorOf(o).find("are all 0"), std::string::npos) << errorOf(o);
  o = options(scene::TrajectoryKind::Orbit);
  o.radii = Eigen::Vector3d(0, 0, 0.5); // orbit ignores z
  EXPECT_NE(errorOf(o).find("all 0 for the orbit path"), std::string::npos) << errorOf(o);
  o = options(scene::TrajectoryKind::Spiral);
  o.focusDepth = -1;
  EXPECT_NE(errorOf(o).find("focus depth = -1"), std::string::npos) << errorOf(o);
  o.focusDepth = NAN;
  EXPECT_NE(errorOf(o).find("focus depth = nan"), std::string::npos) << errorOf(o);
  o = options(scene::TrajectoryKind::Spiral);
  o.turns = 0;
  EXPECT_NE(errorOf(o).find("turns = 0"), std::string::npos) << errorOf(o);
  scene::Camera noSize = reference();
  noSize.width = 0;
  EXPECT_NE(errorOf(options(scene::TrajectoryKind::Spiral), noSize).find("image size 0 x 48"),
            std::string::npos);
}

} // namespace
} // namespace simpli

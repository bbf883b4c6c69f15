// Reference camera (spec §6.1): Markley quaternion average + mean centre.
#include "support/expect_error.h"
#include "support/scene_fixtures.h"

#include "simpli/model/io/safetensors.h"
#include "simpli/model/scene/reference_camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

using namespace simpli;
using simpli::test::rotation;

TEST(ReferenceCamera, IdenticalCamerasGiveTheSameCamera) {
  scene::Camera c = test::makeRig(3)[2];
  const scene::Camera ref = scene::referenceCamera({c, c, c});
  EXPECT_LT((ref.R - c.R).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((ref.t - c.t).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(ref.fx, c.fx);
  EXPECT_EQ(ref.width, c.width);
}

TEST(ReferenceCamera, SymmetricRotationsAverageToIdentity) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -1.0, 0.2).normalized();
  for (double theta : {0.01, 0.3, 1.2}) {
    scene::Camera a, b;
    a.R = rotation(axis, theta);
    b.R = rotation(axis, -theta);
    a.t = -a.R * Eigen::Vector3d(1, 0, 0); // centres (1,0,0) and (-1,2,0)
    b.t = -b.R * Eigen::Vector3d(-1, 2, 0);
    b.fx = 7; // intrinsics come from view 0
    const scene::Camera ref = scene::referenceCamera({a, b});
    EXPECT_LT((ref.R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12) << theta;
    EXPECT_LT((ref.centre() - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);
    EXPECT_EQ(ref.fx, a.fx);
  }
}

TEST(ReferenceCamera, AverageIsSignInvariantAndDeterministic) {
  // Rotations near 180 degrees: Eigen's quaternion of each may come out with either sign.
  const Eigen::Vector3d axis(0, 0, 1);
  const std::vector<Eigen::Matrix3d> rs = {rotation(axis, M_PI - 0.1), rotation(axis, -M_PI + 0.1)};
  const Eigen::Quaterniond q = scene::averageRotation(rs);
  // The average of +-(pi - 0.1) about z is the rotation by pi about z.
  EXPECT_NEAR(std::abs(q.w()), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(q.z()), 1.0, 1e-12);
  EXPECT_LT((q.toRotationMatrix() - rotation(axis, M_PI)).cwiseAbs().maxCoeff(), 1e-12);
  // Small rotations: w > 0, and the order of the inputs does not matter.
  const std::vector<Eigen::Matrix3d> small = {rotation({1, 0, 0}, 0.2), rotation({0, 1, 0}, -0.1),
                                              rotation({0, 0, 1}, 0.05)};
  const Eigen::Quaterniond q1 = scene::averageRotation(small);
  const Eigen::Quaterniond q2 = scene::averageRotation({small[2], small[0], small[1]});
  EXPECT_GT(q1.w(), 0);
  EXPECT_LT((q1.coeffs() - q2.coeffs()).norm(), 1e-12);
  test::expectError([] { scene::averageRotation({}); }, {"no rotations"});
  test::expectError([] { scene::referenceCamera({}); }, {"no source cameras"});
}

TEST(ReferenceCamera, MatchesGolden) {
  const std::string path = std::string(SIMPLI_GOLDEN_DIR) + "/inputs.safetensors";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << "golden data not found at " << path << " (set SIMPLI_GOLDEN_DIR)";
  const io::SafeTensorsReader r(path);
  const auto ext = r.readF64("src_extrinsics");    // [3, 3, 4]
  const auto intr = r.readF64("src_intrinsics");   // [3, 3, 3]
  const auto golden = r.readF64("ref_extrinsics"); // [3, 4]
  ASSERT_EQ(ext.shape, (std::vector<int64_t>{3, 3, 4}));
  ASSERT_EQ(golden.shape, (std::vector<int64_t>{3, 4}));
  std::vector<scene::Camera> cams;
  for (int v = 0; v < 3; ++v) {
    scene::Camera c;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j)
        c.R(i, j) = ext.data[size_t(12 * v + 4 * i + j)];
      c.t[i] = ext.data[size_t(12 * v + 4 * i + 3)];
    }
    c.fx = intr.data[size_t(9 * v + 0)];
    c.cx = intr.data[size_t(9 * v + 2)];
    c.fy = intr.data[size_t(9 * v + 4)];
    c.cy = intr.data[size_t(9 * v + 5)];
    cams.push_back(c);
  }
  const scene::Camera ref = scene::referenceCamera(cams);
  double maxErr = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      maxErr = std::max(maxErr, std::abs(ref.R(i, j) - golden.data[size_t(4 * i + j)]));
    maxErr = std::max(maxErr, std::abs(ref.t[i] - golden.data[size_t(4 * i + 3)]));
  }
  EXPECT_LT(maxErr, 1e-6) << "reference camera differs from the official one";
  EXPECT_EQ(ref.fx, cams[0].fx);
  EXPECT_EQ(ref.cy, cams[0].cy);
}

// widenedCamera: the same pose and pixel grid over a wider field of view; a point at relative
// u maps to (u + m) / (1 + 2 m), so the old frame's edges land m / (1 + 2 m) inside the new one.
TEST(ReferenceCamera, WidenedCameraKeepsPoseAndMapsTheOldFrameInside) {
  const scene::Camera c = test::makeRig(3)[1];
  const double m = 0.06;
  const scene::Camera w = scene::widenedCamera(c, m);
  EXPECT_EQ(w.R, c.R);
  EXPECT_EQ(w.t, c.t);
  EXPECT_EQ(w.width, c.width);
  EXPECT_EQ(w.height, c.height);
  for (const Eigen::Vector2d& uv : {Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1),
                                   Eigen::Vector2d(0.3, 0.8), Eigen::Vector2d(-m, 1 + m)}) {
    const Eigen::Vector3d X = c.backproject(uv, 4.5);
    const Eigen::Vector2d expected = (uv.array() + m) / (1 + 2 * m);
    EXPECT_LT((w.project(X) - expected).cwiseAbs().maxCoeff(), 1e-12) << uv.transpose();
  }
  const scene::Camera same = scene::widenedCamera(c, 0);
  EXPECT_EQ(same.fx, c.fx);
  EXPECT_EQ(same.cx, c.cx);
  for (double bad : {-0.01, 0.51, std::nan("")})
    test::expectError([&] { scene::widenedCamera(c, bad); },
                      {"reference margin", "between 0 and 0.5"});
}

// Camera helpers: projection, back-projection, matrices.
#include "support/cameras.h"
#include "support/expect_error.h"
#include "support/scene_fixtures.h"

#include "simpli/model/scene/camera.h"

#include <gtest/gtest.h>

using namespace simpli;

TEST(Camera, ProjectBackprojectRoundTrip) {
  const auto rig = test::makeRig(3);
  for (const scene::Camera& c : rig) {
    for (double u : {0.0, 0.3, 1.0})
      for (double v : {0.1, 0.5, 0.9})
        for (double d : {1.0, 7.5}) {
          const Eigen::Vector3d X = c.backproject({u, v}, d);
          EXPECT_NEAR(c.depth(X), d, 1e-12);
          const Eigen::Vector2d uv = c.project(X);
          EXPECT_NEAR(uv.x(), u, 1e-12);
          EXPECT_NEAR(uv.y(), v, 1e-12);
        }
  }
}

TEST(Camera, AnalyticIdentityCamera) {
  scene::Camera c = test::pinholeCamera(100, 50, 0.8, 1.2, 0.5, 0.4);
  c.t = Eigen::Vector3d(0, 0, -1); // centre at world z = 1
  EXPECT_TRUE(c.centre().isApprox(Eigen::Vector3d(0, 0, 1)));
  // A point on the optical axis at world z = 3 is 2 in front of the camera.
  EXPECT_NEAR(c.depth({0, 0, 3}), 2.0, 1e-15);
  const Eigen::Vector2d uv = c.project({1, 1, 3});
  EXPECT_NEAR(uv.x(), 0.8 * 0.5 + 0.5, 1e-15);
  EXPECT_NEAR(uv.y(), 1.2 * 0.5 + 0.4, 1e-15);
  // z = 0 is pushed to +1e-6 (sign kept), as in the reference.
  EXPECT_NEAR(c.project({1e-7, 0, 1}).x(), 0.8 * 0.1 + 0.5, 1e-12);
  const Eigen::Matrix3d K = c.pixelK();
  EXPECT_DOUBLE_EQ(K(0, 0), 80.0);
  EXPECT_DOUBLE_EQ(K(1, 1), 60.0);
  EXPECT_DOUBLE_EQ(K(0, 2), 50.0);
  EXPECT_DOUBLE_EQ(K(1, 2), 20.0);
  EXPECT_DOUBLE_EQ(c.extrinsic()(2, 3), -1.0);
  EXPECT_DOUBLE_EQ(c.relativeK()(1, 2), 0.4);
}

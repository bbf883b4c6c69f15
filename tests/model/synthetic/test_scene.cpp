// Scene generation and camera paths (synthetic/scene_generator.h, camera_path.h).
#include "simpli/model/scene/scene.h"
#include "simpli/model/synthetic/camera_path.h"
#include "simpli/model/synthetic/renderer.h"
#include "simpli/model/synthetic/scene_writer.h"

#include "support/expect_error.h"
#include "synthetic_test_util.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <set>

using namespace simpli::synthetic;
using Eigen::Vector3d;
using simpli::scene::Camera;
using simpli::test::expectError;

namespace {

constexpr double kDeg = M_PI / 180.0;

SyntheticSceneParams withSeed(uint64_t seed) {
  SyntheticSceneParams p;
  p.seed = seed;
  return p;
}

} // namespace

TEST(SyntheticGenerator, ParamsAreValidated) {
  auto bad = [](auto change, std::initializer_list<std::string> parts) {
    SyntheticSceneParams p;
    change(p);
    expectError([&] { p.validate(); }, parts);
    expectError([&] { generateSyntheticScene(p); }, parts);
  };
  bad([](auto& p) { p.views = 0; }, {"'views' is 0"});
  bad([](auto& p) { p.width = 0; }, {"'width' is 0"});
  bad([](auto& p) { p.height = -4; }, {"'height' is -4"});
  bad([](auto& p) { p.objects = -1; }, {"'objects' is -1"});
  bad([](auto& p) { p.antialias = 0; }, {"'antialias' is 0"});
  bad([](auto& p) { p.nearDepth = 0; }, {"'nearDepth' is 0"});
  bad([](auto& p) { p.backgroundDepthMin = 3; }, {"'backgroundDepthMin' is 3"});
  bad([](auto& p) { p.translation = std::nan(""); }, {"'translation' is nan"});
  bad([](auto& p) { p.fovDegrees = 110; }, {"background could be missed", "fovDegrees 110"});
  bad([](auto& p) { p.height = 4000; }, {"less elongated size"});
  SyntheticSceneParams ok;
  EXPECT_NO_THROW(ok.validate());
  EXPECT_NEAR(ok.fx(), 0.5 / std::tan(30 * kDeg), 1e-15);
  EXPECT_NEAR(ok.fx() * ok.width, ok.fy() * ok.height, 1e-12); // square pixels
}

TEST(SyntheticGenerator, CameraPathIsSmallHandheldAndForwardFacing) {
  const SyntheticSceneParams p;
  const double maxOffset = p.translation * p.nearDepth;
  double along = 0, across = 0;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const std::vector<Camera> cams = generateSyntheticScene(withSeed(seed)).cameras;
    ASSERT_EQ(cams.size(), 12u);
    Vector3d mean = Vector3d::Zero();
    double farthest = 0;
    for (const Camera& c : cams) {
      EXPECT_LT((c.R.transpose() * c.R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_NEAR(c.R.determinant(), 1.0, 1e-12);
      const Vector3d ypr = yawPitchRoll(c.R.transpose());
      EXPECT_LE(ypr.cwiseAbs().maxCoeff(), p.rotationDegrees * kDeg + 1e-12);
      // Looking along +z: the optical axis within the combined rotation bound.
      EXPECT_GT(c.R.row(2).dot(Vector3d::UnitZ()),
                std::cos(std::sqrt(2.0) * p.rotationDegrees * kDeg) - 1e-12);
      EXPECT_EQ(c.cx, 0.5);
      EXPECT_EQ(c.cy, 0.5);
      EXPECT_EQ(c.fx, p.fx());
      EXPECT_EQ(c.width, p.width);
      const Vector3d C = c.centre();
      mean += C;
      farthest = std::max(farthest, C.norm());
      along += std::abs(C.z());
      across += std::hypot(C.x(), C.y());
    }
    EXPECT_LT((mean / 12.0).norm(), 1e-12);
    EXPECT_NEAR(farthest, maxOffset, 1e-12); // a few % of the near depth
    EXPECT_LE(simpli::scene::maxBaseline(cams), 2 * maxOffset + 1e-12);
  }
  EXPECT_LT(along, 0.5 * across); // mostly in the image plane
}

TEST(SyntheticGenerator, YawPitchRollRoundTrip) {
  const Eigen::Matrix3d m =
      (Eigen::AngleAxisd(0.02, Vector3d::UnitY()) * Eigen::AngleAxisd(-0.015, Vector3d::UnitX()) *
       Eigen::AngleAxisd(0.01, Vector3d::UnitZ()))
          .toRotationMatrix();
  EXPECT_TRUE(yawPitchRoll(m).isApprox(Vector3d(0.02, -0.015, 0.01), 1e-12));
}

TEST(SyntheticGenerator, SingleViewIsTheIdentityCamera) {
  SyntheticSceneParams p;
  p.views = 1;
  const std::vector<Camera> cams = generateSyntheticScene(p).cameras;
  ASSERT_EQ(cams.size(), 1u);
  EXPECT_TRUE(cams[0].R.isIdentity(1e-15));
  EXPECT_LT(cams[0].t.norm(), 1e-15);
}

TEST(SyntheticGenerator, ObjectsAreVariedVisibleAndInFrontOfTheBackground) {
  for (uint64_t seed = 0; seed < 10; ++seed) {
    const SyntheticScene s = generateSyntheticScene(withSeed(seed));
    ASSERT_EQ(s.objects.size(), 8u);
    std::set<ShapeRole> roles;
    const Shape& bg = s.background;
    EXPECT_EQ(bg.kind, ShapeKind::Plane);
    EXPECT_LE(std::acos(-bg.axes.col(2).z()), s.params.maxBackgroundSlantDegrees * kDeg + 1e-12);
    for (const Shape& o : s.objects) {
      roles.insert(o.role);
      const double front = o.centre.z() - o.extent(-Vector3d::UnitZ());
      EXPECT_GE(front, s.params.nearDepth * (1 - 1e-12)) << toString(o.role);
      const double clearance = bg.axes.col(2).dot(o.centre - bg.centre) - o.extent(-bg.axes.col(2));
      EXPECT_GT(clearance, 0.0) << toString(o.role);
      // The centre projects into the (mean) image.
      const double u = 0.5 + s.params.fx() * o.centre.x() / o.centre.z();
      const double v = 0.5 + s.params.fy() * o.centre.y() / o.centre.z();
      EXPECT_TRUE(u > 0 && u < 1 && v > 0 && v < 1) << u << ", " << v;
    }
    EXPECT_EQ(roles.size(), 6u) << "seed " << seed; // every kind, thin structures included
  }
}

TEST(SyntheticGenerator, EveryPixelSeesASurfaceAndObjectsOcclude) {
  for (uint64_t seed = 0; seed < 5; ++seed) {
    SyntheticSceneParams p = withSeed(seed);
    p.width = 64;
    p.height = 48;
    p.views = 2;
    p.antialias = 1;
    const SyntheticScene s = generateSyntheticScene(p);
    for (const RenderedView& v : renderViews(s))
      for (float z : v.depth)
        ASSERT_GT(z, 0.0f) << "seed " << seed;
    // Occlusion: some centre ray of view 0 passes through two objects.
    int overlapping = 0;
    for (int y = 0; y < p.height; ++y)
      for (int x = 0; x < p.width; ++x) {
        const Ray ray = cameraRay(s.cameras[0], (x + 0.5) / p.width, (y + 0.5) / p.height);
        int hits = 0;
        for (const Shape& o : s.objects) {
          SurfaceHit h;
          hits += o.intersect(ray, 1e-9, h);
        }
        overlapping += hits >= 2;
      }
    EXPECT_GT(overlapping, 10) << "seed " << seed;
  }
}

TEST(SyntheticGenerator, DeterministicAndStableAcrossCounts) {
  const SyntheticSceneParams p = withSeed(42);
  const SyntheticScene a = generateSyntheticScene(p), b = generateSyntheticScene(p);
  EXPECT_EQ(sceneDescriptionJson(a, {}, 0.001), sceneDescriptionJson(b, {}, 0.001));
  const SyntheticScene c = generateSyntheticScene(withSeed(43));
  EXPECT_NE(sceneDescriptionJson(a, {}, 0.001), sceneDescriptionJson(c, {}, 0.001));

  // More views: same geometry. Fewer objects: same cameras and the same first objects.
  SyntheticSceneParams moreViews = p;
  moreViews.views = 20;
  const SyntheticScene d = generateSyntheticScene(moreViews);
  ASSERT_EQ(d.objects.size(), a.objects.size());
  for (size_t i = 0; i < a.objects.size(); ++i)
    EXPECT_EQ(d.objects[i].centre, a.objects[i].centre);
  SyntheticSceneParams fewer = p;
  fewer.objects = 3;
  const SyntheticScene e = generateSyntheticScene(fewer);
  ASSERT_EQ(e.objects.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(e.objects[i].centre, a.objects[i].centre);
    EXPECT_EQ(e.objects[i].role, a.objects[i].role);
  }
  for (size_t i = 0; i < a.cameras.size(); ++i)
    EXPECT_EQ(e.cameras[i].t, a.cameras[i].t);
  SyntheticSceneParams none = p;
  none.objects = 0;
  EXPECT_TRUE(generateSyntheticScene(none).objects.empty());
}

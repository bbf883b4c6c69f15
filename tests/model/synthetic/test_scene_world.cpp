// The world style of the synthetic scenes (synthetic/scene.h, scene_world.cpp): over many
// seeds, the stated ranges of field of view, near / far ratio, sky, baseline relative to the
// nearest depth, rotations and thin structures hold on the rendered depth maps themselves.
#include "simpli/model/scene/scene.h"
#include "simpli/model/synthetic/camera_path.h"
#include "simpli/model/synthetic/renderer.h"
#include "simpli/model/synthetic/scene_writer.h"

#include "support/expect_error.h"
#include "synthetic_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

using namespace simpli::synthetic;
using Eigen::Vector3d;
using simpli::test::expectError;

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kSeeds = 40;

SyntheticSceneParams worldParams(uint64_t seed, int width = 64, int height = 48) {
  SyntheticSceneParams p;
  p.style = SceneStyle::World;
  p.seed = seed;
  p.width = width;
  p.height = height;
  p.views = 4;
  p.antialias = 1;
  return p;
}

bool isThin(ShapeRole r) {
  return r == ShapeRole::Pole || r == ShapeRole::Post || r == ShapeRole::Wire ||
         r == ShapeRole::Branch;
}

struct DepthStats {
  double nearest = std::numeric_limits<double>::infinity(), farthest = 0;
  size_t sky = 0, pixels = 0;
};

DepthStats depthStats(const std::vector<RenderedView>& views) {
  DepthStats d;
  for (const RenderedView& v : views)
    for (float z : v.depth) {
      ++d.pixels;
      if (z == 0) {
        ++d.sky;
        continue;
      }
      d.nearest = std::min(d.nearest, double(z));
      d.farthest = std::max(d.farthest, double(z));
    }
  return d;
}

} // namespace

TEST(WorldStyle, RangesHoldOverManySeeds) {
  const WorldStyleParams w;
  int skies = 0, thinScenes = 0;
  double minRatio = 1e9, maxRatio = 0, minFov = 1e9, maxFov = 0, sumBaseline = 0;
  for (uint64_t seed = 0; seed < kSeeds; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const SyntheticSceneParams p = worldParams(seed);
    const SyntheticScene s = generateSyntheticScene(p);
    const WorldLayout& l = s.world;
    const DepthStats d = depthStats(renderViews(s));

    // Field of view: every camera's horizontal FOV is the drawn one, in [50, 70] degrees.
    EXPECT_GE(l.fovDegrees, w.fovDegreesMin);
    EXPECT_LE(l.fovDegrees, w.fovDegreesMax);
    for (const simpli::scene::Camera& c : s.cameras) {
      EXPECT_NEAR(2 * std::atan(0.5 / c.fx) / kDeg, l.fovDegrees, 1e-9);
      EXPECT_NEAR(c.fx * c.width, c.fy * c.height, 1e-9); // square pixels
    }
    minFov = std::min(minFov, l.fovDegrees);
    maxFov = std::max(maxFov, l.fovDegrees);

    // The nearest surface is at the near depth (object 0), give or take the camera motion.
    ASSERT_TRUE(std::isfinite(d.nearest));
    EXPECT_GE(d.nearest, 0.9 * p.nearDepth);
    EXPECT_LE(d.nearest, 1.25 * p.nearDepth);
    for (const Shape& o : s.objects)
      EXPECT_GE(o.centre.z() - o.extent(-Vector3d::UnitZ()), p.nearDepth * (1 - 1e-12))
          << toString(o.role);

    // Near / far: the far layer at 10 .. 100 x the near depth; what the views see of it.
    EXPECT_GE(l.farDepth, w.farRatioMin * p.nearDepth * (1 - 1e-12));
    EXPECT_LE(l.farDepth, w.farRatioMax * p.nearDepth * (1 + 1e-12));
    const double ratio = d.farthest / d.nearest;
    EXPECT_GE(ratio, 0.5 * w.farRatioMin);
    EXPECT_LE(ratio, 1.8 * w.farRatioMax);
    minRatio = std::min(minRatio, ratio);
    maxRatio = std::max(maxRatio, ratio);

    // Sky at infinity (depth 0) exactly in the scenes that have one, covering part of the views.
    EXPECT_EQ(s.hasSky, l.sky);
    if (l.sky) {
      ++skies;
      EXPECT_EQ(s.sky.pattern, Pattern::Sky);
      EXPECT_GT(d.sky, d.pixels / 100);
      EXPECT_LT(d.sky, d.pixels * 9 / 10);
    } else {
      EXPECT_EQ(d.sky, 0u);
      EXPECT_EQ(s.background.kind, ShapeKind::Plane);
    }

    // Handheld rig: the farthest camera centre lies translation x near depth from the mean,
    // 1 .. 30 % of the nearest depth seen (as in LLFF captures); small rotations.
    double farthestCentre = 0;
    for (const simpli::scene::Camera& c : s.cameras) {
      farthestCentre = std::max(farthestCentre, c.centre().norm());
      const Vector3d ypr = yawPitchRoll(c.R.transpose());
      EXPECT_LE(ypr.cwiseAbs().maxCoeff(), l.rotationDegrees * kDeg + 1e-12);
    }
    EXPECT_NEAR(farthestCentre, l.translation * p.nearDepth, 1e-12);
    EXPECT_GE(l.translation, w.translationMin);
    EXPECT_LE(l.translation, w.translationMax);
    EXPECT_LE(l.rotationDegrees, w.rotationDegreesMax);
    const double baseline = farthestCentre / d.nearest;
    EXPECT_GE(baseline, 0.5 * w.translationMin);
    EXPECT_LE(baseline, 1.2 * w.translationMax);
    sumBaseline += baseline;

    // Occluders and thin structures.
    int thin = 0;
    for (const Shape& o : s.objects)
      thin += isThin(o.role);
    EXPECT_GE(thin, w.thinStructuresMin);
    thinScenes += thin > 0;
  }
  // The draws spread over their ranges.
  EXPECT_GT(skies, kSeeds / 4);
  EXPECT_LT(skies, kSeeds * 9 / 10);
  EXPECT_EQ(thinScenes, kSeeds);
  EXPECT_LT(minRatio, 20.0);
  EXPECT_GT(maxRatio, 60.0);
  EXPECT_LT(minFov, 54.0);
  EXPECT_GT(maxFov, 66.0);
  EXPECT_GT(sumBaseline / kSeeds, 0.04); // log-uniform over 1 .. 30 %: mean about 8.5 %
  EXPECT_LT(sumBaseline / kSeeds, 0.15);
}

TEST(WorldStyle, ThinStructuresAreThin) {
  // Poles, posts, wires and branches are at most 5 pixels thick where they stand.
  int thinSeen = 0;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    const SyntheticScene s = generateSyntheticScene(worldParams(seed));
    const double fx = s.cameras[0].fx;
    for (const Shape& o : s.objects) {
      if (!isThin(o.role))
        continue;
      const double pixel = o.centre.z() / (fx * s.params.width);
      const double thickness =
          o.kind == ShapeKind::Cylinder ? 2 * o.size.x() : 2 * std::min(o.size.y(), o.size.x());
      EXPECT_LE(thickness / pixel, 5.0 + 1e-9) << toString(o.role) << " seed " << seed;
      ++thinSeen;
    }
  }
  EXPECT_GT(thinSeen, 20);
}

// world.objectSize bounds the occluders' apparent width: a fronto-parallel rectangle other than
// the first (nearest) occluder is 0.6 .. 1.4 x the drawn fraction of the image width wide.
TEST(WorldStyle, ObjectSizeBoundsTheOccluders) {
  auto widths = [](double low, double high) {
    std::vector<double> w;
    for (uint64_t seed = 0; seed < 10; ++seed) {
      SyntheticSceneParams p = worldParams(seed);
      p.objects = 30;
      p.world.objectSizeMin = low;
      p.world.objectSizeMax = high;
      const SyntheticScene s = generateSyntheticScene(p);
      const double fx = 0.5 / std::tan(0.5 * s.world.fovDegrees * kDeg); // relative to the width
      bool first = true;
      for (const Shape& o : s.objects) {
        if (o.role == ShapeRole::Distant || isThin(o.role))
          continue;
        const bool nearest = first;
        first = false;
        if (nearest || o.role != ShapeRole::FrontoPlane)
          continue;
        w.push_back(2 * o.size.x() * fx / o.centre.z());
      }
    }
    return w;
  };
  const std::vector<double> small = widths(0.02, 0.05);
  ASSERT_GT(small.size(), 20u);
  for (double w : small) {
    EXPECT_GE(w, 0.6 * 0.02 * (1 - 1e-9));
    EXPECT_LE(w, 1.4 * 0.05 * (1 + 1e-9));
  }
  // The default range draws wider ones (the bound above is not vacuous).
  const std::vector<double> wide =
      widths(WorldStyleParams{}.objectSizeMin, WorldStyleParams{}.objectSizeMax);
  EXPECT_GT(*std::max_element(wide.begin(), wide.end()), 0.2);
}

// world.bushes adds clusters of 20 .. 60 small leaves in front of the far layer, which the
// cameras see: a share of the first view's pixels lands on leaves. The default has none, and
// its scenes are unchanged by the option's existence (their own stream).
TEST(WorldStyle, BushesAreClustersOfSmallLeaves) {
  int scenesWithLeafPixels = 0;
  for (uint64_t seed = 0; seed < 8; ++seed) {
    SyntheticSceneParams p = worldParams(seed);
    const SyntheticScene plain = generateSyntheticScene(p);
    p.world.bushesMin = 2;
    p.world.bushesMax = 2;
    const SyntheticScene s = generateSyntheticScene(p);
    for (const Shape& o : plain.objects)
      EXPECT_NE(o.role, ShapeRole::Leaf);
    int leaves = 0;
    const double fx = 0.5 / std::tan(0.5 * s.world.fovDegrees * kDeg);
    for (size_t i = 0; i < s.objects.size(); ++i) {
      const Shape& o = s.objects[i];
      if (o.role != ShapeRole::Leaf) {
        ASSERT_LT(i, plain.objects.size());
        EXPECT_EQ(o.centre, plain.objects[i].centre) << "seed " << seed;
        continue;
      }
      ++leaves;
      EXPECT_EQ(o.kind, ShapeKind::Leaf);
      const double length = 2 * o.size.x() * fx / o.centre.z(); // / image width
      EXPECT_GE(length, 0.03 * 0.6) << "seed " << seed; // leaves behind the bush front look smaller
      EXPECT_LE(length, 0.10 * (1 + 1e-9)) << "seed " << seed;
      EXPECT_GE(o.size.y(), 0.25 * o.size.x() * (1 - 1e-9));
      EXPECT_LE(o.size.y(), 0.5 * o.size.x() * (1 + 1e-9));
      EXPECT_GE(o.centre.z() - o.extent(-Vector3d::UnitZ()), s.params.nearDepth * (1 - 1e-9));
      EXPECT_LT(o.centre.z(), s.world.farDepth);
    }
    EXPECT_GE(leaves, 40) << "seed " << seed;
    EXPECT_LE(leaves, 120) << "seed " << seed;
    const RenderedView v = renderView(s, 0);
    const RenderedView w = renderView(plain, 0);
    size_t changed = 0;
    for (size_t i = 0; i < v.depth.size(); ++i)
      changed += v.depth[i] != w.depth[i];
    scenesWithLeafPixels += changed > 0;
  }
  EXPECT_GE(scenesWithLeafPixels, 6);
}

// world.bushScale multiplies each bush's leaves (and the ball they fill): LLFF flower's leaves
// are 10 .. 35 % of the image long, the default bush's 3 .. 10 %. A fixed factor scales every
// leaf; a range draws one factor per bush, so some bushes hold leaves beyond the default's.
TEST(WorldStyle, BushScaleScalesTheLeaves) {
  double longestInRange = 0;
  for (uint64_t seed = 0; seed < 6; ++seed) {
    for (const double low : {3.0, 1.0}) {
      SyntheticSceneParams p = worldParams(seed);
      p.world.bushesMin = p.world.bushesMax = 2;
      p.world.bushScaleMin = low;
      p.world.bushScaleMax = 3;
      const SyntheticScene s = generateSyntheticScene(p);
      const double fx = 0.5 / std::tan(0.5 * s.world.fovDegrees * kDeg);
      int leaves = 0;
      for (const Shape& o : s.objects) {
        if (o.role != ShapeRole::Leaf)
          continue;
        ++leaves;
        const double length = 2 * o.size.x() * fx / o.centre.z(); // / image width
        EXPECT_GE(length, low * 0.03 * 0.5) << "seed " << seed;   // leaves behind look smaller
        EXPECT_LE(length, 3 * 0.10 * (1 + 1e-9)) << "seed " << seed;
        if (low == 1.0)
          longestInRange = std::max(longestInRange, length);
      }
      EXPECT_GE(leaves, 40) << "seed " << seed;
      const std::string json = sceneDescriptionJson(s, {}, 1);
      EXPECT_NE(json.find(low == 1.0 ? "--bush-scale 1,3" : "--bush-scale 3,3"), std::string::npos);
      EXPECT_NE(json.find("\"bush_scale\""), std::string::npos);
    }
  }
  EXPECT_GT(longestInRange, 0.12);
}

TEST(WorldStyle, DeterministicPerSeed) {
  const SyntheticSceneParams p = worldParams(11);
  const SyntheticScene a = generateSyntheticScene(p), b = generateSyntheticScene(p);
  EXPECT_EQ(sceneDescriptionJson(a, {}, 1), sceneDescriptionJson(b, {}, 1));
  EXPECT_EQ(renderView(a, 1).rgb, renderView(b, 1).rgb);
  EXPECT_NE(sceneDescriptionJson(a, {}, 1),
            sceneDescriptionJson(generateSyntheticScene(worldParams(12)), {}, 1));
  const std::string json = sceneDescriptionJson(a, {}, 1);
  for (const char* part : {"\"style\": \"world\"", "\"world\": {", "\"far_depth\"",
                           "\"fov_degrees\"", "--style world"})
    EXPECT_NE(json.find(part), std::string::npos) << part;
}

TEST(WorldStyle, SkyIsAtInfinity) {
  // The sky's colour depends only on the ray direction: a pure camera translation leaves the
  // sky pixels unchanged, while every surface moves.
  for (uint64_t seed = 0; seed < 40; ++seed) {
    SyntheticSceneParams p = worldParams(seed);
    const SyntheticScene s = generateSyntheticScene(p);
    if (!s.hasSky)
      continue;
    simpli::scene::Camera moved = s.cameras[0];
    moved.t += Vector3d(0.05, 0.02, 0.0); // centre moves, orientation stays
    const RenderedView a = renderView(s, s.cameras[0], 1), b = renderView(s, moved, 1);
    int compared = 0;
    for (size_t i = 0; i < a.depth.size(); ++i)
      if (a.depth[i] == 0 && b.depth[i] == 0) {
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(a.rgb[i * 3 + size_t(c)], b.rgb[i * 3 + size_t(c)]);
        ++compared;
      }
    EXPECT_GT(compared, 0);
    return;
  }
  FAIL() << "no seed with a sky";
}

TEST(WorldStyle, ParamsValidated) {
  auto bad = [](auto change, std::initializer_list<std::string> parts) {
    SyntheticSceneParams p = worldParams(0);
    change(p);
    expectError([&] { p.validate(); }, parts);
    expectError([&] { generateSyntheticScene(p); }, parts);
  };
  bad([](auto& p) { p.world.fovDegreesMin = 10; }, {"'world.fovDegreesMin' is 10"});
  bad([](auto& p) { p.world.fovDegreesMax = 40; }, {"'world.fovDegreesMax' is 40"});
  bad([](auto& p) { p.world.farRatioMax = 5; }, {"'world.farRatioMax' is 5"});
  bad([](auto& p) { p.world.skyProbability = -0.1; }, {"'world.skyProbability' is -0.1"});
  bad([](auto& p) { p.world.translationMin = 0; }, {"'world.translationMin' is 0"});
  bad([](auto& p) { p.world.rotationDegreesMax = 20; }, {"'world.rotationDegreesMax' is 20"});
  bad([](auto& p) { p.world.thinStructuresMax = 0; }, {"'world.thinStructuresMax' is 0"});
  bad([](auto& p) { p.world.objectSizeMin = 0.001; }, {"'world.objectSizeMin' is 0.001"});
  bad([](auto& p) { p.world.objectSizeMax = 0.05; }, {"'world.objectSizeMax' is 0.05"});
  bad([](auto& p) { p.world.objectSizeMax = 1.5; }, {"'world.objectSizeMax' is 1.5"});
  bad([](auto& p) { p.world.bushesMin = -1; }, {"'world.bushesMin' is -1"});
  bad([](auto& p) { p.world.bushesMax = 51; }, {"'world.bushesMax' is 51"});
  bad([](auto& p) { p.world.bushesMin = 3, p.world.bushesMax = 2; }, {"'world.bushesMax' is 2"});
  bad([](auto& p) { p.world.bushScaleMin = 0.1; }, {"'world.bushScaleMin' is 0.1"});
  bad([](auto& p) { p.world.bushScaleMax = 5; }, {"'world.bushScaleMax' is 5"});
  bad([](auto& p) { p.world.bushScaleMin = 2; }, {"'world.bushScaleMax' is 1"});
  bad([](auto& p) { p.world.bushSharedTexture = 1.5; }, {"'world.bushSharedTexture' is 1.5"});
  bad([](auto& p) { p.height = 4000; }, {"far plane could be missed"});
  SyntheticSceneParams sky = worldParams(0, 64, 4000);
  sky.world.skyProbability = 1.0; // every ray that misses sees the sky: no such limit
  EXPECT_NO_THROW(sky.validate());
  expectError([] { parseSceneStyle("flyingthings", "--style"); },
              {"--style 'flyingthings'", "\"objects\"", "\"world\""});
  EXPECT_EQ(parseSceneStyle("world", "x"), SceneStyle::World);
  EXPECT_EQ(parseSceneStyle("objects", "x"), SceneStyle::Objects);
}

TEST(WorldStyle, WrittenSceneReadsBack) {
  simpli::test::TempDir tmp;
  SyntheticSceneParams p = worldParams(5);
  p.views = 3;
  const SyntheticScene s = generateSyntheticScene(p);
  const std::vector<RenderedView> views = renderViews(s);
  const WrittenScene w = writeSyntheticScene(tmp.str("world"), s, views);
  const simpli::scene::Scene back = simpli::scene::readScene(w.dir);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back.width(), 64);
  // Bounds from the finite depths only (sky pixels are 0 = no surface): per view 0.9 x the
  // nearest, 1.1 x the farthest; the scene's are the extremes over the views.
  const DepthStats d = depthStats(views);
  const double ratio = (1.1 / 0.9) * d.farthest / d.nearest;
  EXPECT_NEAR(back.far / back.near, ratio, 1e-4 * ratio);
}

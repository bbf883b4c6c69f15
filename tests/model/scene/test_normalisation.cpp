// Scene normalisation: rules, percentile, invertibility.
#include "support/expect_error.h"
#include "support/scene_fixtures.h"

#include "simpli/model/scene/normalisation.h"

#include <gtest/gtest.h>

using namespace simpli;

TEST(Normalisation, PercentileMatchesNumpyLinear) {
  // numpy.percentile([4, 1, 3, 2, 10], q): 10 -> 1.4, 50 -> 3.0, 99 -> 9.76
  const std::vector<double> v = {4, 1, 3, 2, 10};
  EXPECT_NEAR(scene::percentile(v, 10), 1.4, 1e-12);
  EXPECT_NEAR(scene::percentile(v, 50), 3.0, 1e-12);
  EXPECT_NEAR(scene::percentile(v, 99), 9.76, 1e-12);
  EXPECT_DOUBLE_EQ(scene::percentile(v, 0), 1.0);
  EXPECT_DOUBLE_EQ(scene::percentile(v, 100), 10.0);
  EXPECT_DOUBLE_EQ(scene::percentile({5}, 37), 5.0);
  test::expectError([] { scene::percentile({}, 10); }, {"no values"});
  test::expectError([] { scene::percentile({1.0}, 101); }, {"101"});
}

TEST(Normalisation, Rules) {
  scene::NormalisationOptions o;
  // Auto without points: near bound -> minDepth.
  scene::Normalisation n = scene::chooseNormalisation(o, 2.5, {});
  EXPECT_EQ(n.rule, scene::NormalisationMode::NearBound);
  EXPECT_DOUBLE_EQ(n.scale, 0.4);
  EXPECT_DOUBLE_EQ(n.toNormalised(2.5), 1.0);
  // Auto with points: the reference's p10 -> 1.25.
  std::vector<double> depths;
  for (int i = 1; i <= 11; ++i)
    depths.push_back(double(i)); // p10 = 2
  n = scene::chooseNormalisation(o, 0.5, depths);
  EXPECT_EQ(n.rule, scene::NormalisationMode::PointPercentile);
  EXPECT_DOUBLE_EQ(n.anchorScene, 2.0);
  EXPECT_DOUBLE_EQ(n.scale, 1.25 / 2.0);
  o.mode = scene::NormalisationMode::NearBound;
  o.minDepth = 2.0;
  EXPECT_DOUBLE_EQ(scene::chooseNormalisation(o, 0.5, depths).scale, 4.0);
  o.mode = scene::NormalisationMode::None;
  EXPECT_DOUBLE_EQ(scene::chooseNormalisation(o, 0.5, depths).scale, 1.0);
  EXPECT_EQ(scene::chooseNormalisation(o, 0.5, depths).describe(), "none (scale 1)");
  o.mode = scene::NormalisationMode::PointPercentile;
  test::expectError([&] { scene::chooseNormalisation(o, 0.5, {}); }, {"no SfM points"});
  o.mode = scene::NormalisationMode::NearBound;
  test::expectError([&] { scene::chooseNormalisation(o, -1.0, {}); }, {"-1"});
  o.minDepth = 0;
  test::expectError([&] { scene::chooseNormalisation(o, 1.0, {}); }, {"target depth 0"});
}

TEST(Normalisation, InvertibleAndConsistentWithProjection) {
  scene::Normalisation n;
  n.rule = scene::NormalisationMode::NearBound;
  n.scale = 0.37;
  const scene::Camera c = test::makeRig(3)[1];
  const scene::Camera cn = n.toNormalised(c);
  const scene::Camera back = n.toScene(cn);
  EXPECT_LT((back.t - c.t).norm(), 1e-15);
  EXPECT_EQ(back.R, c.R);
  // Scaling the world and the cameras together leaves images unchanged and scales depths.
  const Eigen::Vector3d X(0.3, -0.2, 4.0);
  const Eigen::Vector3d Xn = n.toNormalised(X);
  EXPECT_LT((cn.project(Xn) - c.project(X)).norm(), 1e-12);
  EXPECT_NEAR(cn.depth(Xn), n.toNormalised(c.depth(X)), 1e-12);
  EXPECT_NEAR(n.toScene(n.toNormalised(3.0)), 3.0, 1e-15);
  EXPECT_LT((n.toScene(Xn) - X).norm(), 1e-15);
}

// The evaluation protocol's input scale (training/eval.h): sampleInput resizes the sources and
// their cameras, nothing else; evaluate() with an input scale scores renders at the targets'
// size.
#include "support/expect_error.h"

#include "simpli/model/network/network.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/data.h"
#include "simpli/model/training/eval.h"
#include "simpli/model/training/trainer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace simpli::training {
namespace {

const std::string kScene = std::string(SIMPLI_DATASETS_SMALL_DIR) + "/synthetic/scene_00";

// The bundled scene at 96x64.
std::unique_ptr<TrainingData> bundledScene() {
  DataOptions d;
  d.width = 96;
  d.height = 64;
  return openTrainingData(kScene, d);
}

TrainingSample firstSample(TrainingData& data) {
  EvalOptions e;
  e.views = 3;
  e.novelViews = 2;
  e.seed = 3;
  TrainingSample first;
  forEachEvalSample(data, e, [&](const TrainingSample& s, uint64_t, int r) {
    if (r == 0)
      first = s;
  });
  return first;
}

TEST(TrainEval, ScaledSizeIsAMultipleOf16) {
  using generator::scaledSize;
  EXPECT_EQ(scaledSize(512, 0.5), 256);
  EXPECT_EQ(scaledSize(384, 0.25), 96);
  EXPECT_EQ(scaledSize(504, 0.5), 256); // 252 rounds to the nearest multiple of 16
  EXPECT_EQ(scaledSize(96, 0.05), 16);  // never below one cell
}

TEST(TrainEval, SampleInputResizesOnlyTheSources) {
  auto data = bundledScene();
  const TrainingSample s = firstSample(*data);
  ASSERT_EQ(s.sources.size(), 3u);

  const generator::GeneratorInput same = sampleInput(s, 1.0, ocl::Dtype::F64);
  ASSERT_EQ(same.images.shape(), (ocl::Shape{3, 3, 64, 96}));
  std::vector<double> expected;
  for (const io::Image& im : s.sources)
    expected.insert(expected.end(), im.data.begin(), im.data.end());
  const std::vector<double> got = same.images.toVector();
  ASSERT_EQ(got.size(), expected.size());
  double worst = 0;
  for (size_t i = 0; i < got.size(); ++i)
    worst = std::max(worst, std::abs(got[i] - expected[i]));
  EXPECT_LT(worst, 1e-6);
  EXPECT_EQ(same.reference.width, 96);

  const generator::GeneratorInput half = sampleInput(s, 0.5, ocl::Dtype::F64);
  ASSERT_EQ(half.images.shape(), (ocl::Shape{3, 3, 32, 48}));
  EXPECT_EQ(half.reference.width, 48);
  EXPECT_EQ(half.reference.height, 32);
  for (size_t v = 0; v < s.sources.size(); ++v) {
    const scene::Camera &a = s.sourceCameras[v], &b = half.sources[v];
    EXPECT_EQ(b.width, 48);
    EXPECT_EQ(b.height, 32);
    // Relative intrinsics and the pose are the same camera.
    EXPECT_EQ(a.relativeK(), b.relativeK());
    EXPECT_EQ(a.R, b.R);
    EXPECT_EQ(a.t, b.t);
  }
  // The resized pixels are io::resizeImage's.
  const io::Image small = io::resizeImage(s.sources[1], 48, 32);
  const std::vector<double> h = half.images.toVector();
  EXPECT_NEAR(h[size_t(3 * 32 * 48) + 5 * 48 + 7], double(small.data[5 * 48 + 7]), 1e-6);
}

// Scale 1 is "as they are" also for a size the network's grid does not divide (as sceneInput).
TEST(TrainEval, SampleInputAtScaleOneKeepsAnySize) {
  DataOptions d;
  d.width = 100;
  d.height = 70;
  auto data = openTrainingData(kScene, d);
  const TrainingSample s = firstSample(*data);
  const generator::GeneratorInput same = sampleInput(s, 1.0, ocl::Dtype::F32);
  EXPECT_EQ(same.images.shape(), (ocl::Shape{3, 3, 70, 100}));
  EXPECT_EQ(same.reference.width, 100);
  EXPECT_EQ(same.sources[2].height, 70);
  const generator::GeneratorInput twice = sampleInput(s, 2.0, ocl::Dtype::F32);
  EXPECT_EQ(twice.images.shape(), (ocl::Shape{3, 3, 144, 208})); // 140 -> 144, 200 -> 208
}

TEST(TrainEval, BadInputScaleIsNamed) {
  auto data = bundledScene();
  const TrainingSample s = firstSample(*data);
  for (double bad : {0.0, -0.5, 2.5, std::numeric_limits<double>::quiet_NaN()})
    test::expectError([&] { sampleInput(s, bad, ocl::Dtype::F32); }, {"input scale", "(0, 2]"});
}

// Half the input resolution: the MLI is built at 48x32 and every score is of a render at the
// targets' 96x64 (finite, and not the full-resolution scores).
TEST(TrainEval, InputScaleScoresRendersAtTheTargetsSize) {
  auto data = bundledScene();
  const TrainingConfig cfg =
      parseTrainingConfig(R"({"network": "tiny.json"})", "tiny-train", SIMPLI_NETWORK_CONFIG_DIR);
  network::SimpliNetwork net(cfg.network, ocl::Dtype::F32, 7);
  EvalOptions e;
  e.views = 3;
  e.novelViews = 2;
  e.seed = 3;
  e.warmUp = false;
  const EvalResult full = evaluate(net, *data, e);
  e.inputScale = 0.5;
  int shown = 0;
  const EvalResult half = evaluate(net, *data, e, {}, [&](const EvalViewImages& v) {
    EXPECT_EQ(v.render.width, 96);
    EXPECT_EQ(v.render.height, 64);
    EXPECT_EQ(v.truth.width, 96);
    ++shown;
  });
  EXPECT_EQ(shown, 2);
  ASSERT_EQ(half.model.size(), full.model.size());
  for (size_t i = 0; i < half.model.size(); ++i) {
    EXPECT_TRUE(std::isfinite(half.model[i].psnr)) << i;
    EXPECT_NE(half.model[i].psnr, full.model[i].psnr) << i;
    EXPECT_EQ(half.baseline[i].psnr, full.baseline[i].psnr) << i; // same targets and sources
  }
}

} // namespace
} // namespace simpli::training

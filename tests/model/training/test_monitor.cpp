// The training run's monitor: validation on its schedule (fixed samples, so a network that does
// not change scores the same), val.csv kept across resume, the pictures it writes, bad scenes.
#include "support/expect_error.h"
#include "support/temp_dir.h"

#include "simpli/model/io/image.h"
#include "simpli/model/io/safetensors.h"
#include "simpli/model/network/config.h"
#include "simpli/model/network/network.h"
#include "simpli/model/training/checkpoint.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/log.h"
#include "simpli/model/training/monitor.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace simpli::training {
namespace {
namespace fs = std::filesystem;
using simpli::test::expectError;
using simpli::test::TempDir;

const std::string kScene = std::string(SIMPLI_DATASETS_SMALL_DIR) + "/synthetic/scene_00";

network::SimpliNetwork tinyNetwork(uint64_t seed = 5) {
  const TrainingConfig c =
      parseTrainingConfig(R"({"network": "tiny.json"})", "tiny-train", SIMPLI_NETWORK_CONFIG_DIR);
  return network::SimpliNetwork(c.network, c.dtype, seed);
}

ValidationOptions smallValidation() {
  ValidationOptions v;
  v.scene = kScene;
  v.every = 2;
  v.width = 64;
  v.height = 48;
  v.views = 3;
  v.novelViews = 1;
  return v;
}

// A log.csv of n steps with a falling loss, as the trainer writes it.
void writeTrainLog(const TempDir& run, int n) {
  TrainLog log(run.str("log.csv"), {"step", "l1", "total"}, -1);
  for (int s = 1; s <= n; ++s)
    log.append({double(s), 1.0 / s, 2.0 / s});
}
} // namespace

TEST(TrainingMonitor, ValidatesOnItsScheduleWithFixedSamples) {
  TempDir run;
  writeTrainLog(run, 5);
  network::SimpliNetwork net = tinyNetwork();
  TrainingMonitor m(run.str(), smallValidation());
  m.begin(-1);
  const auto first = m.update(net, 1);
  ASSERT_TRUE(first); // the first checkpoint always validates
  EXPECT_TRUE(std::isfinite(first->psnr));
  EXPECT_GT(first->nearestPsnr, 0);
  EXPECT_FALSE(m.update(net, 2)); // 1 step since the last validation, every = 2
  const auto third = m.update(net, 3);
  ASSERT_TRUE(third);
  // Same weights, same samples: the same score, bit for bit.
  EXPECT_EQ(third->psnr, first->psnr);
  EXPECT_EQ(third->nearestPsnr, first->nearestPsnr);
  EXPECT_TRUE(m.update(net, 4, /*force=*/true));

  const std::vector<std::vector<double>> rows = TrainLog::read(run.str("val.csv"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0][0], 1);
  EXPECT_EQ(rows[1][0], 3);
  EXPECT_EQ(rows[2][0], 4);
  for (const char* f : {"step_00000001.png", "step_00000003.png", "step_00000004.png"}) {
    const io::Image grid = io::readImage((run / "validation" / f).string());
    EXPECT_EQ(grid.height, 48) << f;
    EXPECT_EQ(grid.width, 4 * 64 + 3 * 4) << f; // truth | render | error | nearest, 4 px gaps
  }
  const io::Image progress = io::readImage(run.str("progress.png"));
  EXPECT_EQ(progress.width, 800);
  EXPECT_EQ(progress.height, 3 * 360); // loss, validation PSNR and SSIM panels
}

TEST(TrainingMonitor, ResumeKeepsValidationRowsUpToTheCheckpoint) {
  TempDir run;
  writeTrainLog(run, 6);
  network::SimpliNetwork net = tinyNetwork();
  {
    TrainingMonitor m(run.str(), smallValidation());
    m.begin(-1);
    m.update(net, 2);
    m.update(net, 4);
    m.update(net, 6);
  }
  TrainingMonitor resumed(run.str(), smallValidation());
  resumed.begin(4); // the run resumes from its step-4 checkpoint: the step-6 row is redone
  EXPECT_FALSE(resumed.update(net, 5)); // 1 step after the resumed step 4
  ASSERT_TRUE(resumed.update(net, 6));
  const std::vector<std::vector<double>> rows = TrainLog::read(run.str("val.csv"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[2][0], 6);
}

// A run stopped between two validations (Ctrl-C at step 5, last validated at 2) keeps their
// schedule: the next validation is at 4, not 2 steps after the resumed step.
TEST(TrainingMonitor, ResumeBetweenValidationsKeepsTheSchedule) {
  TempDir run;
  writeTrainLog(run, 6);
  network::SimpliNetwork net = tinyNetwork();
  {
    TrainingMonitor m(run.str(), smallValidation());
    m.begin(-1);
    m.update(net, 2);
    EXPECT_FALSE(m.update(net, 3));
  }
  TrainingMonitor resumed(run.str(), smallValidation());
  resumed.begin(3);
  ASSERT_TRUE(resumed.update(net, 4)); // 2 steps after the validation at 2
  const std::vector<std::vector<double>> rows = TrainLog::read(run.str("val.csv"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1][0], 4);
}

int64_t bestStep(const TempDir& run) {
  return std::stoll(
      io::SafeTensorsReader(TrainingMonitor::bestWeightsPath(run.str())).metadata().at("step"));
}

// best.safetensors follows the highest PSNR, not the last validation; a resumed run knows the
// best score it kept and replaces it only with a better one. Two initialisations score
// differently; which one is better does not matter.
TEST(TrainingMonitor, KeepsTheWeightsOfTheBestValidation) {
  TempDir run;
  writeTrainLog(run, 10);
  network::SimpliNetwork a = tinyNetwork(5), b = tinyNetwork(7);
  const std::string key = a.parameters().names().front();
  double psnrA = 0, psnrB = 0;
  {
    TrainingMonitor m(run.str(), smallValidation());
    m.begin(-1);
    const auto first = m.update(a, 2);
    ASSERT_TRUE(first);
    EXPECT_TRUE(first->best); // the first validation is the best so far
    EXPECT_EQ(bestStep(run), 2);
    const auto second = m.update(b, 4);
    ASSERT_TRUE(second);
    psnrA = first->psnr;
    psnrB = second->psnr;
    ASSERT_NE(psnrA, psnrB);
    EXPECT_EQ(second->best, psnrB > psnrA);
    const auto third = m.update(a, 6);
    ASSERT_TRUE(third);
    EXPECT_FALSE(third->best) << "equal to the best is not better";
  }
  network::SimpliNetwork& better = psnrB > psnrA ? b : a;
  network::SimpliNetwork& worse = psnrB > psnrA ? a : b;
  const int64_t expectedStep = psnrB > psnrA ? 4 : 2;
  EXPECT_EQ(bestStep(run), expectedStep);
  {
    const io::SafeTensorsReader kept(TrainingMonitor::bestWeightsPath(run.str()));
    const std::vector<float> stored = kept.readF32(key).data;
    const std::vector<double> expected = better.parameters().get(key).toVector();
    ASSERT_EQ(stored.size(), expected.size());
    for (size_t i = 0; i < stored.size(); ++i)
      ASSERT_EQ(stored[i], float(expected[i])) << i;
    EXPECT_EQ(kept.metadata(), weightsMetadata(expectedStep, network::toJson(better.config())));
  }
  // Resumed at step 6: the kept best is known, so neither network replaces it.
  TrainingMonitor resumed(run.str(), smallValidation());
  resumed.begin(6);
  const auto again = resumed.update(worse, 8);
  ASSERT_TRUE(again);
  EXPECT_FALSE(again->best);
  const auto same = resumed.update(better, 10);
  ASSERT_TRUE(same);
  EXPECT_FALSE(same->best);
  EXPECT_EQ(bestStep(run), expectedStep);
}

TEST(TrainingMonitor, WithoutValidationDrawsTheLossCurveOnly) {
  TempDir run;
  writeTrainLog(run, 3);
  network::SimpliNetwork net = tinyNetwork();
  TrainingMonitor m(run.str(), ValidationOptions{});
  m.begin(-1);
  EXPECT_FALSE(m.update(net, 3));
  EXPECT_FALSE(fs::exists(run / "val.csv"));
  EXPECT_FALSE(fs::exists(TrainingMonitor::bestWeightsPath(run.str())));
  const io::Image progress = io::readImage(run.str("progress.png"));
  EXPECT_EQ(progress.height, 360);
}

TEST(TrainingMonitor, RejectsUnusableValidationScenes) {
  TempDir run;
  ValidationOptions v = smallValidation();
  v.scene = run.str("no-such-scene");
  expectError([&] { TrainingMonitor(run.str(), v); }, {"no-such-scene"});
  v = smallValidation();
  v.views = 40;
  expectError([&] { TrainingMonitor(run.str(), v); }, {"validation scene", "40 sources"});
  v = smallValidation();
  v.every = 0;
  expectError([&] { TrainingMonitor(run.str(), v); }, {"validation every 0"});
  EXPECT_TRUE(simpli::test::listDir(run.path()).empty()) << "a failed start writes nothing";
}

} // namespace simpli::training

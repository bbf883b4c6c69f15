// The weights a run keeps for good (training/snapshots.h): which checkpoints keep them (every
// N-th step, also when the checkpoint interval does not divide N, and not again after a resume),
// and that the kept file holds the network's very weights with the run's metadata.
#include "support/expect_error.h"
#include "support/temp_dir.h"

#include "simpli/model/io/safetensors.h"
#include "simpli/model/network/config.h"
#include "simpli/model/network/network.h"
#include "simpli/model/training/checkpoint.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/snapshots.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

namespace simpli::training {
namespace {
namespace fs = std::filesystem;
using simpli::test::expectError;
using simpli::test::TempDir;

network::SimpliNetwork tinyNetwork(uint64_t seed) {
  const TrainingConfig c =
      parseTrainingConfig(R"({"network": "tiny.json"})", "tiny-train", SIMPLI_NETWORK_CONFIG_DIR);
  return network::SimpliNetwork(c.network, c.dtype, seed);
}

// The steps among `checkpoints` whose checkpoint keeps the weights, keeping as a run would.
std::vector<int64_t> keptSteps(WeightSnapshots& s, const std::vector<int64_t>& checkpoints) {
  const network::SimpliNetwork net = tinyNetwork(1);
  std::vector<int64_t> kept;
  for (int64_t step : checkpoints)
    if (s.due(step)) {
      s.keep(net, step);
      kept.push_back(step);
    }
  return kept;
}
} // namespace

TEST(WeightSnapshots, KeepsTheFirstCheckpointAtOrAfterEachMultiple) {
  TempDir run;
  WeightSnapshots every3(run.str(), 3, 0);
  // Checkpoints every 2 steps: 4 is the first at or after 3, 6 reaches 6, 10 passes 9.
  EXPECT_EQ(keptSteps(every3, {2, 4, 6, 8, 10, 11, 12}), (std::vector<int64_t>{4, 6, 10, 12}));
  for (int64_t step : {4, 6, 10, 12})
    EXPECT_TRUE(fs::exists(WeightSnapshots::path(run.str(), step))) << step;
  EXPECT_FALSE(fs::exists(WeightSnapshots::path(run.str(), 2)));
  EXPECT_EQ(fs::path(WeightSnapshots::path(run.str(), 12)).filename(), "step_00000012.safetensors");
  EXPECT_EQ(fs::path(WeightSnapshots::path(run.str(), 12)).parent_path().filename(), "kept");

  // A run resumed at step 6 (which kept it) keeps 9 next, not 6 or 8 again.
  TempDir resumed;
  WeightSnapshots after6(resumed.str(), 3, 6);
  EXPECT_EQ(keptSteps(after6, {7, 8, 9, 10, 12}), (std::vector<int64_t>{9, 12}));

  TempDir none;
  WeightSnapshots off(none.str(), 0, 0);
  EXPECT_EQ(keptSteps(off, {1, 100, 1000}), std::vector<int64_t>{});
  EXPECT_FALSE(fs::exists(fs::path(none.str()) / "kept"));
}

TEST(WeightSnapshots, TheKeptFileHoldsTheNetworkAndItsStep) {
  TempDir run;
  network::SimpliNetwork net = tinyNetwork(5);
  WeightSnapshots s(run.str(), 100, 0);
  ASSERT_TRUE(s.due(100));
  const std::string file = s.keep(net, 100);
  EXPECT_EQ(file, WeightSnapshots::path(run.str(), 100));
  EXPECT_FALSE(s.due(100));

  const io::SafeTensorsReader kept(file);
  EXPECT_EQ(kept.metadata(), weightsMetadata(100, network::toJson(net.config())));
  // Loaded into a network initialised differently, every parameter becomes net's, bit for bit.
  network::SimpliNetwork other = tinyNetwork(6);
  const std::string key = net.parameters().names().front();
  ASSERT_NE(other.parameters().get(key).toVector(), net.parameters().get(key).toVector());
  other.parameters().load(file);
  for (const std::string& name : net.parameters().names())
    ASSERT_EQ(other.parameters().get(name).toVector(), net.parameters().get(name).toVector())
        << name;
}

TEST(WeightSnapshots, ANegativeIntervalIsANamedError) {
  TempDir run;
  expectError([&] { WeightSnapshots(run.str(), -5, 0); }, {"keep-weights-every -5: must be >= 0"});
  EXPECT_FALSE(fs::exists(fs::path(run.str()) / "kept"));
}

} // namespace simpli::training

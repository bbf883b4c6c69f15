// Checkpoints: round trip of weights, Adam state and random state; a failed write leaves the
// previous checkpoint as the newest readable one; old checkpoints are pruned.
#include "support/expect_error.h"

#include "simpli/model/network/parameter_store.h"
#include "simpli/model/training/checkpoint.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace simpli::training {
namespace {
namespace fs = std::filesystem;

struct Fixture {
  network::ParameterStore store{ocl::Dtype::F32, 3};
  std::unique_ptr<ocl::Adam> adam;
  Fixture() {
    store.add("a.weight", {3, 4}, {network::InitKind::FanInUniform, 4});
    store.add("a.bias", {3}, {network::InitKind::FanInUniform, 4});
    store.add("unused", {2}, {network::InitKind::Ones, 0});
    adam = std::make_unique<ocl::Adam>(store.parameters(), 1e-2);
  }
  void step(int n) {
    for (int i = 0; i < n; ++i) {
      adam->zeroGrad();
      auto p = store.parameters();
      p[0].setGrad(ocl::Tensor::uniform({3, 4}, -1, 1, uint64_t(10 + i)));
      p[1].setGrad(ocl::Tensor::uniform({3}, -1, 1, uint64_t(20 + i)));
      adam->step();
    }
  }
  CheckpointData data(int64_t step) const {
    CheckpointData d;
    d.step = step;
    TrainRandom r(step);
    d.random = r.state();
    d.adam = adam->exportState();
    d.configJson = "{\"x\": 1}\n";
    return d;
  }
};

fs::path tempRun(const std::string& name) {
  const fs::path p =
      fs::temp_directory_path() / ("simpli_ckpt_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

TEST(TrainCheckpoint, RoundTripIsExact) {
  const fs::path run = tempRun("roundtrip");
  Fixture f;
  f.step(3);
  const std::string dir = writeCheckpoint(run.string(), f.store, f.data(3));
  EXPECT_EQ(dir, checkpointDir(run.string(), 3));
  EXPECT_TRUE(fs::exists(run / "weights.safetensors"));
  ASSERT_EQ(latestCheckpoint(run.string()).value_or(""), dir);

  Fixture g; // other initial values
  g.store.initialise(77);
  const CheckpointData back = readCheckpoint(dir, g.store);
  EXPECT_EQ(back.step, 3);
  EXPECT_EQ(back.random, f.data(3).random);
  EXPECT_EQ(back.configJson, "{\n  \"x\": 1\n}\n");
  for (const std::string& n : f.store.names())
    EXPECT_EQ(f.store.get(n).toVector(), g.store.get(n).toVector()) << n;
  const ocl::Adam::State a = f.adam->exportState();
  ASSERT_EQ(back.adam.params.size(), a.params.size());
  EXPECT_EQ(back.adam.steps, a.steps);
  for (size_t i = 0; i < a.params.size(); ++i) {
    EXPECT_EQ(back.adam.params[i].step, a.params[i].step);
    EXPECT_EQ(back.adam.params[i].m, a.params[i].m);
    EXPECT_EQ(back.adam.params[i].v, a.params[i].v);
  }
  // Continuing both optimisers gives identical parameters.
  g.adam->importState(back.adam);
  f.step(2);
  g.step(2);
  for (const std::string& n : f.store.names())
    EXPECT_EQ(f.store.get(n).toVector(), g.store.get(n).toVector()) << n;
  fs::remove_all(run);
}

// The weights of a checkpoint carry the run's network section, so that `simpli infer
// --weights` needs no --config; best.safetensors (training/monitor.h) uses the same metadata.
TEST(TrainCheckpoint, WeightsCarryStepAndNetworkConfig) {
  const fs::path run = tempRun("metadata");
  Fixture f;
  CheckpointData d = f.data(12);
  d.configJson = "{\"network\": {\"planes\": 5}, \"steps\": 3}";
  const std::string dir = writeCheckpoint(run.string(), f.store, d);
  const std::string networkConfig = "{\n  \"planes\": 5\n}";
  const std::map<std::string, std::string> expected = weightsMetadata(12, networkConfig);
  EXPECT_EQ(expected.at("format"), "simpli-weights");
  EXPECT_EQ(expected.at("step"), "12");
  EXPECT_EQ(expected.at("network_config"), networkConfig);
  for (const fs::path& file : {fs::path(dir) / "weights.safetensors", run / "weights.safetensors"})
    EXPECT_EQ(io::SafeTensorsReader(file.string()).metadata(), expected) << file;
  // Without a network section the key is left out rather than written empty.
  d.configJson = "{\"steps\": 3}";
  d.step = 13;
  writeCheckpoint(run.string(), f.store, d);
  EXPECT_EQ(io::SafeTensorsReader((run / "weights.safetensors").string()).metadata(),
            weightsMetadata(13, ""));
  EXPECT_EQ(weightsMetadata(13, "").count("network_config"), 0u);
  fs::remove_all(run);
}

TEST(TrainCheckpoint, FailedWriteKeepsLastGoodCheckpoint) {
  const fs::path run = tempRun("atomic");
  Fixture f;
  f.step(1);
  const std::string good = writeCheckpoint(run.string(), f.store, f.data(1));
  const std::vector<double> goodWeights = f.store.get("a.weight").toVector();
  f.step(1);
  for (int failAfter = 1; failAfter <= 3; ++failAfter) {
    CheckpointWriteOptions o;
    o.failAfterFiles = failAfter;
    test::expectError([&] { writeCheckpoint(run.string(), f.store, f.data(2), o); },
                      {"simulated failure"});
    EXPECT_FALSE(fs::exists(checkpointDir(run.string(), 2))) << failAfter;
    ASSERT_EQ(latestCheckpoint(run.string()).value_or(""), good);
    Fixture g;
    const CheckpointData d = readCheckpoint(good, g.store);
    EXPECT_EQ(d.step, 1);
    EXPECT_EQ(g.store.get("a.weight").toVector(), goodWeights);
  }
  // A later successful write cleans up the debris and keeps the last `keep` checkpoints.
  writeCheckpoint(run.string(), f.store, f.data(2));
  f.step(1);
  writeCheckpoint(run.string(), f.store, f.data(3));
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(run / "checkpoints"))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"step_00000002", "step_00000003"}));
  fs::remove_all(run);
}

// Pruning renames a checkpoint out of the step_* names before removing its files: a process
// killed mid-removal leaves a `.old-` folder, which resuming ignores and the next write removes.
TEST(TrainCheckpoint, HalfRemovedOldCheckpointIsIgnoredAndCleanedUp) {
  const fs::path run = tempRun("prune");
  Fixture f;
  for (int s = 1; s <= 3; ++s)
    writeCheckpoint(run.string(), f.store, f.data(s));
  EXPECT_FALSE(fs::exists(checkpointDir(run.string(), 1)));
  // What a SIGKILL during the removal of step 3's folder would leave (state.json only).
  const fs::path halfRemoved = run / "checkpoints" / ".old-step_00000003";
  fs::create_directories(halfRemoved);
  fs::copy_file(fs::path(checkpointDir(run.string(), 3)) / "state.json",
                halfRemoved / "state.json");
  fs::remove_all(checkpointDir(run.string(), 3));
  EXPECT_EQ(latestCheckpoint(run.string()).value_or(""), checkpointDir(run.string(), 2));
  writeCheckpoint(run.string(), f.store, f.data(4));
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(run / "checkpoints"))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"step_00000002", "step_00000004"}));
  fs::remove_all(run);
}

TEST(TrainCheckpoint, BadFilesNameFileAndField) {
  const fs::path run = tempRun("bad");
  Fixture f;
  f.step(1);
  const std::string dir = writeCheckpoint(run.string(), f.store, f.data(1));
  {
    std::ofstream s(dir + "/state.json");
    s << "{\"format\": \"simpli-train-checkpoint\", \"version\": 1, \"step\": 1, "
         "\"random\": \"zz\"}";
  }
  Fixture g;
  test::expectError([&] { readCheckpoint(dir, g.store); }, {"state.json", "random", "zz"});
  // A store with another parameter set.
  network::ParameterStore other(ocl::Dtype::F32, 0);
  other.add("b.weight", {2}, {network::InitKind::Ones, 0});
  writeCheckpoint(run.string(), f.store, f.data(2));
  test::expectError([&] { readCheckpoint(checkpointDir(run.string(), 2), other); },
                    {"weights.safetensors", "b.weight"});
  EXPECT_FALSE(latestCheckpoint((run / "nothing").string()).has_value());
  fs::remove_all(run);
}

} // namespace
} // namespace simpli::training

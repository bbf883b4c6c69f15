// The training loop end to end on a tiny network: resume after an interruption repeats the
// uninterrupted run, a simulated kill loses only the steps after the last checkpoint, and the
// network learns a scene (held-out PSNR rises above its start and the nearest-source
// baseline).
//
// Determinism: the forward pass is deterministic, but the backward passes of grid_sample, the
// plane sweep and the rasterizer scatter with atomic adds, whose order depends on how PoCL
// schedules work-groups over its threads; in float32 (and float64) the sums can then differ
// in the last bits from run to run. Restricting PoCL to one thread (POCL_MAX_PTHREAD_COUNT=1,
// set before the device opens: each test runs in its own process under ctest) makes the
// work-group order fixed and every run bit-identical, which these tests then require exactly.
// On other devices the same comparison would need a tolerance.
#include "support/expect_error.h"

#include "simpli/model/network/network.h"
#include "simpli/model/training/checkpoint.h"
#include "simpli/model/training/data.h"
#include "simpli/model/training/eval.h"
#include "simpli/model/training/trainer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

namespace simpli::training {
namespace {
namespace fs = std::filesystem;

const std::string kScene = std::string(SIMPLI_DATASETS_SMALL_DIR) + "/synthetic/scene_00";

// An explicit POCL_MAX_PTHREAD_COUNT in the environment wins (to study the parallel case).
// The backward kernels add with float atomics, whose order varies with PoCL's threads, so the
// bit-for-bit tests need one thread; PoCL reads the variable once, when the process first uses
// OpenCL. ctest runs every test in its own process; running the whole binary at once makes the
// earlier tests start PoCL on all cores and these tests then differ in the last digits.
void deterministicDevice() {
  ::setenv("POCL_MAX_PTHREAD_COUNT", "1", 0);
}

TrainingConfig tinyConfig(int64_t steps, int64_t every) {
  TrainingConfig c =
      parseTrainingConfig(R"({"network": "tiny.json"})", "tiny-train", SIMPLI_NETWORK_CONFIG_DIR);
  c.steps = steps;
  c.checkpointEvery = every;
  c.sampling.minViews = 2;
  c.sampling.maxViews = 3;
  c.sampling.novelViews = 2;
  c.seed = 11;
  return c;
}

fs::path tempRun(const std::string& name) {
  const fs::path p =
      fs::temp_directory_path() / ("simpli_trainer_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  return p;
}

TrainerOptions options(const fs::path& run) {
  TrainerOptions o;
  o.data = {{kScene}};
  o.runDir = run.string();
  o.dataOptions.height = 32;
  o.dataOptions.width = 48;
  return o;
}

std::vector<std::vector<double>> logWithoutTimes(const fs::path& run) {
  auto rows = TrainLog::read((run / "log.csv").string());
  for (auto& r : rows) {
    r.pop_back(); // step_ms
    for (double& v : r)
      if (std::isnan(v))
        v = -1; // terms that are off (NaN != NaN)
  }
  return rows;
}

TEST(TrainTrainer, ResumeRepeatsTheUninterruptedRun) {
  deterministicDevice();
  TrainingConfig cfg = tinyConfig(6, 3);
  cfg.sampling.maxViews = 2; // the smallest samples: this test runs PoCL on one thread
  cfg.sampling.novelViews = 1;
  cfg.emaDecay = 0.6; // the moving average must resume too
  const fs::path a = tempRun("full"), b = tempRun("resumed");
  std::vector<double> full;
  {
    TrainerOptions o = options(a);
    o.onStep = [&](const StepReport& r) { full.push_back(r.total); };
    Trainer t(&cfg, o);
    const auto res = t.run();
    EXPECT_EQ(res.steps, 6);
    EXPECT_FALSE(res.interrupted);
  }
  std::vector<double> resumed;
  {
    TrainerOptions o = options(b);
    int n = 0;
    o.onStep = [&](const StepReport& r) {
      resumed.push_back(r.total);
      ++n;
    };
    o.stopRequested = [&] { return n >= 2; }; // interrupted after step 2 (checkpoint at 2)
    Trainer t(&cfg, o);
    const auto res = t.run();
    EXPECT_TRUE(res.interrupted);
    EXPECT_EQ(res.steps, 2);
    EXPECT_EQ(latestCheckpoint(b.string()).value_or(""), checkpointDir(b.string(), 2));
  }
  {
    TrainerOptions o = options(b);
    o.resume = true;
    o.crashAfterSteps = 2; // steps 3 (checkpoint) and 4, then a kill without a checkpoint
    o.onStep = [&](const StepReport& r) { resumed.push_back(r.total); };
    Trainer t(nullptr, o);
    EXPECT_EQ(t.startStep(), 2);
    t.run();
    EXPECT_EQ(latestCheckpoint(b.string()).value_or(""), checkpointDir(b.string(), 3));
    EXPECT_EQ(TrainLog::read((b / "log.csv").string()).size(), 4u);
  }
  resumed.pop_back(); // step 4 is redone after the kill
  {
    TrainerOptions o = options(b);
    o.resume = true;
    o.onStep = [&](const StepReport& r) { resumed.push_back(r.total); };
    Trainer t(&cfg, o);
    EXPECT_EQ(t.startStep(), 3);
    t.run();
  }
  ASSERT_EQ(full.size(), 6u);
  ASSERT_EQ(resumed.size(), 6u);
  for (size_t i = 0; i < 6; ++i)
    EXPECT_EQ(full[i], resumed[i]) << "step " << i + 1;
  EXPECT_EQ(logWithoutTimes(a), logWithoutTimes(b));
  // Same final weights.
  network::SimpliNetwork na(cfg.network, cfg.dtype), nb(cfg.network, cfg.dtype);
  na.parameters().load((a / "weights.safetensors").string());
  nb.parameters().load((b / "weights.safetensors").string());
  for (const std::string& n : na.parameters().names())
    EXPECT_EQ(na.parameters().get(n).toVector(), nb.parameters().get(n).toVector()) << n;
  const io::SafeTensorsReader ea((a / "weights_ema.safetensors").string()),
      eb((b / "weights_ema.safetensors").string());
  ASSERT_EQ(ea.keys().size(), na.parameters().names().size());
  for (const std::string& n : ea.keys())
    EXPECT_EQ(ea.readF64(n).data, eb.readF64(n).data) << n;
  for (size_t i = 1; i < full.size(); ++i)
    EXPECT_TRUE(std::isfinite(full[i]));
  fs::remove_all(a);
  fs::remove_all(b);
}

// The fused view aggregation (forward and backward kernels) trains as the composed ops do: in
// float64, the same losses step by step and the same weights after three Adam steps.
TEST(TrainTrainer, FusedAggregationTrainsLikeTheComposedOps) {
  deterministicDevice();
  TrainingConfig cfg = tinyConfig(3, 3);
  cfg.dtype = ocl::Dtype::F64;
  const fs::path a = tempRun("fused"), b = tempRun("composed");
  std::vector<double> fused, composed;
  for (const bool fusedAggregation : {true, false}) {
    TrainerOptions o = options(fusedAggregation ? a : b);
    o.fusedAggregation = fusedAggregation;
    std::vector<double>& totals = fusedAggregation ? fused : composed;
    o.onStep = [&](const StepReport& r) { totals.push_back(r.total); };
    Trainer(&cfg, o).run();
  }
  ASSERT_EQ(fused.size(), 3u);
  ASSERT_EQ(composed.size(), 3u);
  for (size_t i = 0; i < 3; ++i)
    EXPECT_NEAR(fused[i], composed[i], 1e-10 * std::abs(composed[i])) << "step " << i + 1;
  network::SimpliNetwork na(cfg.network, cfg.dtype), nb(cfg.network, cfg.dtype);
  na.parameters().load((a / "weights.safetensors").string());
  nb.parameters().load((b / "weights.safetensors").string());
  int attentionParameters = 0;
  for (const std::string& n : na.parameters().names()) {
    const std::vector<double> wa = na.parameters().get(n).toVector();
    const std::vector<double> wb = nb.parameters().get(n).toVector();
    ASSERT_EQ(wa.size(), wb.size()) << n;
    for (size_t i = 0; i < wa.size(); ++i)
      ASSERT_NEAR(wa[i], wb[i], 1e-8) << n << " element " << i;
    attentionParameters += n.find("attention_agg") != std::string::npos;
  }
  EXPECT_GT(attentionParameters, 0); // the view attention is part of the network trained
  fs::remove_all(a);
  fs::remove_all(b);
}

// The ssim term (not in the reference): a log column only when on, in the total with its weight.
TEST(TrainTrainer, SsimTermIsLoggedAndInTheTotal) {
  deterministicDevice();
  const fs::path run = tempRun("ssim_on");
  TrainingConfig cfg = tinyConfig(2, 2);
  cfg.dtype = ocl::Dtype::F64;
  cfg.lossWeights["ssim"] = 0.25;
  TrainerOptions o = options(run);
  Trainer(&cfg, o).run();
  std::vector<std::string> header;
  const auto rows = TrainLog::read((run / "log.csv").string(), &header);
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& values : rows) {
    std::map<std::string, double> row;
    for (size_t i = 0; i < header.size(); ++i)
      row[header[i]] = values[i];
    ASSERT_EQ(row.count("ssim"), 1u);
    EXPECT_GT(row["ssim"], 0.01); // an untrained network's render is not its target
    EXPECT_LT(row["ssim"], 2.0);
    double total = 0.25 * row["ssim"] + row["l1"] + 0.01 * row["smooth_layers"];
    for (int k = 0; k < 4; ++k)
      total += row["intermediate_loss_" + std::to_string(k) + "_l1"];
    EXPECT_NEAR(row["total"], total, 1e-9 * total);
  }
  fs::remove_all(run);
}

// The level-0 plane term (mpi_depth) on synthetic data, which knows its depth: logged only
// when on, part of the total with its weight, and it reaches the level-0 parameters (the same
// seed and samples without it end with other level-0 weights).
TEST(TrainTrainer, PlaneDepthTermTrainsLevelZero) {
  deterministicDevice();
  const fs::path on = tempRun("mpi_depth_on"), off = tempRun("mpi_depth_off");
  for (const bool withTerm : {true, false}) {
    TrainingConfig cfg = tinyConfig(2, 2);
    cfg.dtype = ocl::Dtype::F64;
    cfg.lossWeights["mpi_depth"] = withTerm ? 0.5 : 0.0;
    TrainerOptions o = options(withTerm ? on : off);
    o.data = {{"synthetic:3"}};
    Trainer(&cfg, o).run();
  }
  std::vector<std::string> header;
  const auto rows = TrainLog::read((on / "log.csv").string(), &header);
  ASSERT_EQ(rows.size(), 2u);
  std::map<std::string, double> row;
  for (size_t i = 0; i < header.size(); ++i)
    row[header[i]] = rows[0][i];
  ASSERT_EQ(row.count("mpi_depth"), 1u);
  EXPECT_TRUE(std::isfinite(row["mpi_depth"]));
  EXPECT_GT(row["mpi_depth"], 0.1); // an untrained network does not know the planes
  double total = 0.5 * row["mpi_depth"] + row["l1"] + 0.01 * row["smooth_layers"];
  for (int k = 0; k < 4; ++k)
    total += row["intermediate_loss_" + std::to_string(k) + "_l1"];
  EXPECT_NEAR(row["total"], total, 1e-9 * total);
  std::vector<std::string> offHeader;
  TrainLog::read((off / "log.csv").string(), &offHeader);
  EXPECT_EQ(std::count(offHeader.begin(), offHeader.end(), "mpi_depth"), 0);

  const TrainingConfig cfg = tinyConfig(2, 2);
  network::SimpliNetwork a(cfg.network, ocl::Dtype::F64), b(cfg.network, ocl::Dtype::F64);
  a.parameters().load((on / "weights.safetensors").string());
  b.parameters().load((off / "weights.safetensors").string());
  double lvl0 = 0, maxDiff = 0;
  for (const std::string& n : a.parameters().names()) {
    if (n.rfind("alpha_decoder_lvl0", 0) != 0)
      continue;
    const std::vector<double> wa = a.parameters().get(n).toVector();
    const std::vector<double> wb = b.parameters().get(n).toVector();
    for (size_t i = 0; i < wa.size(); ++i)
      maxDiff = std::max(maxDiff, std::abs(wa[i] - wb[i]));
    ++lvl0;
  }
  EXPECT_GT(lvl0, 0);
  EXPECT_GT(maxDiff, 1e-6);
  fs::remove_all(on);
  fs::remove_all(off);
}

// ema_decay d: after steps with weights w1, w2 the average is d^2 w0 + d (1 - d) w1 + (1 - d) w2,
// in float64, written beside the weights and loadable as weights.
TEST(TrainTrainer, MovingAverageOfTheWeights) {
  TrainingConfig cfg = tinyConfig(2, 10);
  cfg.sampling.maxViews = 2;
  cfg.sampling.novelViews = 1;
  cfg.emaDecay = 0.75;
  const fs::path run = tempRun("ema");
  TrainerOptions o = options(run);
  std::vector<std::vector<std::vector<double>>> weights; // [snapshot][parameter][value]
  Trainer* trainer = nullptr;
  auto snapshot = [&] {
    std::vector<std::vector<double>> w;
    for (const std::string& n : trainer->network().parameters().names())
      w.push_back(trainer->network().parameters().get(n).toVector());
    weights.push_back(std::move(w));
  };
  o.onStep = [&](const StepReport&) { snapshot(); };
  Trainer t(&cfg, o);
  trainer = &t;
  snapshot();
  t.run();
  ASSERT_EQ(weights.size(), 3u);
  const double d = 0.75, c0 = d * d, c1 = d * (1 - d), c2 = 1 - d;
  const io::SafeTensorsReader average((run / "weights_ema.safetensors").string());
  const std::vector<std::string>& names = t.network().parameters().names();
  ASSERT_EQ(average.keys().size(), names.size());
  double worst = 0, moved = 0;
  for (size_t p = 0; p < names.size(); ++p) {
    const io::HostTensor<double> got = average.readF64(names[p]);
    EXPECT_EQ(got.shape, t.network().parameters().get(names[p]).shape()) << names[p];
    ASSERT_EQ(got.data.size(), weights[0][p].size());
    for (size_t i = 0; i < got.data.size(); ++i) {
      const double expect = c0 * weights[0][p][i] + c1 * weights[1][p][i] + c2 * weights[2][p][i];
      worst = std::max(worst, std::abs(got.data[i] - expect));
      moved = std::max(moved, std::abs(weights[2][p][i] - weights[0][p][i]));
    }
  }
  EXPECT_GT(moved, 1e-5); // the weights did change, so the average means something
  EXPECT_LT(worst, 1e-12);
  // The averaged weights load like weights (config from their metadata).
  network::SimpliNetwork n(cfg.network, cfg.dtype);
  n.parameters().load((run / "weights_ema.safetensors").string());
  // Validation scores the average (rounded to the network's dtype), not the last weights.
  network::SimpliNetwork& scored = t.validationNetwork();
  EXPECT_NE(&scored, &t.network());
  for (size_t p = 0; p < names.size(); ++p) {
    const std::vector<double> got = scored.parameters().get(names[p]).toVector();
    const std::vector<double> expect = average.readF64(names[p]).data;
    ASSERT_EQ(got.size(), expect.size());
    for (size_t i = 0; i < got.size(); ++i)
      ASSERT_EQ(got[i], double(float(expect[i]))) << names[p] << " " << i;
  }
  fs::remove_all(run);
}

// ema_decay turned on in a run's config.json between two sessions: the resumed run's average
// starts at the checkpoint's weights w2, so after one more step it is d w2 + (1 - d) w3. Without
// a moving average, validation scores the network itself.
TEST(TrainTrainer, MovingAverageTurnedOnWhenResuming) {
  TrainingConfig cfg = tinyConfig(2, 1);
  cfg.sampling.maxViews = 2;
  cfg.sampling.novelViews = 1;
  const fs::path run = tempRun("ema_on");
  std::vector<std::vector<double>> w2, w3;
  auto weightsOf = [](network::SimpliNetwork& net) {
    std::vector<std::vector<double>> w;
    for (const std::string& n : net.parameters().names())
      w.push_back(net.parameters().get(n).toVector());
    return w;
  };
  {
    Trainer t(&cfg, options(run));
    t.run();
    EXPECT_EQ(&t.validationNetwork(), &t.network());
    w2 = weightsOf(t.network());
  }
  EXPECT_FALSE(fs::exists(run / "weights_ema.safetensors"));
  TrainingConfig on = cfg;
  on.emaDecay = 0.5;
  { std::ofstream(run / "config.json") << toJson(on); }
  TrainerOptions o = options(run);
  o.resume = true;
  o.steps = 3;
  Trainer t(nullptr, o);
  EXPECT_EQ(t.startStep(), 2);
  t.run();
  w3 = weightsOf(t.network());
  const io::SafeTensorsReader average((run / "weights_ema.safetensors").string());
  const std::vector<std::string>& names = t.network().parameters().names();
  double worst = 0, moved = 0;
  for (size_t p = 0; p < names.size(); ++p) {
    const std::vector<double> got = average.readF64(names[p]).data;
    ASSERT_EQ(got.size(), w2[p].size());
    for (size_t i = 0; i < got.size(); ++i) {
      worst = std::max(worst, std::abs(got[i] - (0.5 * w2[p][i] + 0.5 * w3[p][i])));
      moved = std::max(moved, std::abs(w3[p][i] - w2[p][i]));
    }
  }
  EXPECT_GT(moved, 1e-5);
  EXPECT_LT(worst, 1e-12);
  fs::remove_all(run);
}

TEST(TrainTrainer, RunFolderRules) {
  const TrainingConfig cfg = tinyConfig(1, 1);
  const fs::path run = tempRun("rules");
  fs::create_directories(run);
  { std::ofstream(run / "something") << "x"; }
  test::expectError([&] { Trainer(&cfg, options(run)); }, {run.string(), "not empty", "--resume"});
  TrainerOptions o = options(run);
  o.resume = true;
  test::expectError([&] { Trainer(&cfg, o); }, {"no config.json"});
  // A start that fails on bad input leaves no run folder behind.
  const fs::path unused = tempRun("unused");
  TrainerOptions bad = options(unused);
  bad.data = {{"/no/such/scenes"}};
  test::expectError([&] { Trainer(&cfg, bad); }, {"/no/such/scenes", "does not exist"});
  bad = options(unused);
  bad.vggPath = "/no/such/vgg.safetensors";
  TrainingConfig withVgg = cfg;
  withVgg.lossWeights["perceptual"] = 1;
  test::expectError([&] { Trainer(&withVgg, bad); }, {"/no/such/vgg.safetensors"});
  EXPECT_FALSE(fs::exists(unused));
  fs::remove_all(run);
  // A resumed run refuses a different config.
  {
    Trainer t(&cfg, options(run));
    t.run();
  }
  TrainingConfig other = cfg;
  other.optimizer.lr = 1.0;
  test::expectError([&] { Trainer(&other, o); }, {"differs", "optimizer"});
  fs::remove_all(run);
}

// --init-weights: a new run starts from the given weights instead of its seed's initialisation;
// a missing file or a resumed run is a named error before anything is written.
TEST(TrainTrainer, InitWeightsWarmStartANewRun) {
  const TrainingConfig cfg = tinyConfig(0, 1);
  const fs::path dir = tempRun("init");
  fs::create_directories(dir);
  const std::string weights = (dir / "start.safetensors").string();
  network::SimpliNetwork other(cfg.network, cfg.dtype, /*seed*/ 99);
  other.parameters().save(weights);

  TrainerOptions o = options(dir / "run");
  o.initWeights = weights;
  std::vector<std::string> said;
  o.message = [&](const std::string& m) { said.push_back(m); };
  Trainer t(&cfg, o);
  const network::ParameterStore& got = t.network().parameters();
  const network::ParameterStore& want = other.parameters();
  ASSERT_EQ(got.names(), want.names());
  for (const std::string& name : want.names())
    ASSERT_EQ(got.get(name).toVector(), want.get(name).toVector()) << name;
  bool reported = false;
  for (const std::string& m : said)
    reported = reported || m.find("initial weights: " + weights) != std::string::npos;
  EXPECT_TRUE(reported);
  // Without the option the seed's own initialisation differs.
  Trainer plain(&cfg, options(dir / "plain"));
  EXPECT_NE(plain.network().parameters().get(want.names()[0]).toVector(),
            want.get(want.names()[0]).toVector());

  TrainerOptions missing = options(dir / "missing");
  missing.initWeights = (dir / "none.safetensors").string();
  test::expectError([&] { Trainer(&cfg, missing); }, {"none.safetensors"});
  EXPECT_FALSE(fs::exists(dir / "missing"));
  TrainerOptions resumed = options(dir / "run");
  resumed.resume = true;
  resumed.initWeights = weights;
  test::expectError([&] { Trainer(nullptr, resumed); }, {"--init-weights", "resumed run"});
  fs::remove_all(dir);
}

// The sample streams of data-parallel training: stream 0 is the plain run's sampler, stream s
// its state jumped s times.
TEST(TrainTrainer, SampleStreamsStartFromJumpsOfTheSeed) {
  const std::vector<TrainRandom::State> s = sampleStreams(11, 3);
  ASSERT_EQ(s.size(), 3u);
  TrainRandom r(samplerSeed(11));
  EXPECT_EQ(s[0], r.state());
  r.jump();
  EXPECT_EQ(s[1], r.state());
  r.jump();
  EXPECT_EQ(s[2], r.state());
  EXPECT_NE(s[0], s[1]);
  test::expectError([] { sampleStreams(1, 0); }, {"0 streams"});
}

// --samples-per-rank L (one rank: gradient accumulation, the single-process twin of L MPI
// ranks): every step averages L samples from L streams; the checkpoint keeps every stream, so a
// resume with the same L repeats the uninterrupted run exactly, and a resume with another L
// says what changes and carries on.
TEST(TrainTrainer, SamplesPerRankStreamsResume) {
  deterministicDevice();
  TrainingConfig cfg = tinyConfig(3, 1);
  cfg.sampling.maxViews = 2;
  cfg.sampling.novelViews = 1;
  const fs::path a = tempRun("streams_full"), b = tempRun("streams_resumed");
  std::vector<double> full, resumed;
  {
    TrainerOptions o = options(a);
    o.samplesPerRank = 2;
    o.onStep = [&](const StepReport& r) {
      EXPECT_EQ(r.samples, 2);
      EXPECT_GE(r.exchangeMs, 0);
      full.push_back(r.total);
    };
    Trainer t(&cfg, o);
    EXPECT_EQ(t.samplesPerStep(), 2);
    t.run();
  }
  {
    TrainerOptions o = options(b);
    o.samplesPerRank = 2;
    o.onStep = [&](const StepReport& r) { resumed.push_back(r.total); };
    o.stopRequested = [&] { return resumed.size() >= 1; }; // stopped after step 1
    Trainer t(&cfg, o);
    EXPECT_TRUE(t.run().interrupted);
  }
  const std::string state = checkpointDir(b.string(), 1) + "/state.json";
  std::ifstream in(state);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("\"sample_streams\""), std::string::npos) << text;
  {
    TrainerOptions o = options(b);
    o.resume = true;
    o.samplesPerRank = 2;
    o.onStep = [&](const StepReport& r) { resumed.push_back(r.total); };
    Trainer t(nullptr, o);
    EXPECT_EQ(t.startStep(), 1);
    t.run();
  }
  ASSERT_EQ(full.size(), 3u);
  EXPECT_EQ(full, resumed);
  network::SimpliNetwork na(cfg.network, cfg.dtype), nb(cfg.network, cfg.dtype);
  na.parameters().load((a / "weights.safetensors").string());
  nb.parameters().load((b / "weights.safetensors").string());
  for (const std::string& n : na.parameters().names())
    EXPECT_EQ(na.parameters().get(n).toVector(), nb.parameters().get(n).toVector()) << n;
  // One sample per step: its stream 0 continues, stream 1 is dropped, and it says so.
  {
    TrainerOptions o = options(b);
    o.resume = true;
    o.steps = 4;
    std::string said;
    o.message = [&](const std::string& m) { said += m + "\n"; };
    Trainer t(nullptr, o);
    EXPECT_NE(said.find("the checkpoint has 2 sample stream(s), this run has 1"), std::string::npos)
        << said;
    EXPECT_NE(said.find("streams 1..1 are dropped"), std::string::npos) << said;
    t.run();
    EXPECT_EQ(t.step(), 4);
  }
  TrainerOptions bad = options(tempRun("streams_bad"));
  bad.samplesPerRank = 0;
  test::expectError([&] { Trainer(&cfg, bad); }, {"samples per rank 0", "must be >= 1"});
  fs::remove_all(a);
  fs::remove_all(b);
}

// Training on one scene at 32 x 48 with a constant learning rate; the held-out views of fixed
// evaluation samples are scored every `every` steps (printed: the learning curve).
struct OverfitResult {
  EvalResult before, after;
};
OverfitResult overfit(int steps, int every) {
  TrainingConfig cfg = tinyConfig(steps, steps);
  cfg.optimizer.lr = 1e-3;
  cfg.optimizer.gamma = 1.0;
  const fs::path run = tempRun("overfit");
  TrainerOptions o = options(run);
  Trainer t(&cfg, o);
  auto data = openTrainingData(kScene, o.dataOptions);
  EvalOptions e;
  e.views = 3;
  e.novelViews = 2;
  e.repeats = 3;
  e.seed = 5;
  OverfitResult r;
  r.before = evaluate(t.network(), *data, e);
  std::printf("step 0: held-out PSNR %.2f dB, SSIM %.3f; nearest source view %.2f dB, %.3f\n",
              r.before.modelPsnr.mean, r.before.modelSsim.mean, r.before.baselinePsnr.mean,
              r.before.baselineSsim.mean);
  double ms = 0;
  while (t.step() < steps) {
    const StepReport s = t.trainStep();
    ms += s.ms;
    if (s.step % every == 0 || s.step == steps) {
      r.after = evaluate(t.network(), *data, e);
      std::printf(
          "step %lld: l1 %.4f total %.4f; held-out PSNR %.2f dB, SSIM %.3f (%.0f ms/step)\n",
          static_cast<long long>(s.step), s.terms[0].second, s.total, r.after.modelPsnr.mean,
          r.after.modelSsim.mean, ms / double(s.step));
      std::fflush(stdout);
    }
  }
  fs::remove_all(run);
  return r;
}

// Default set (about a minute on two loaded cores): the held-out PSNR and SSIM rise clearly.
TEST(TrainTrainer, LearnsQuick) {
  const OverfitResult r = overfit(24, 12);
  EXPECT_GT(r.after.modelPsnr.mean, r.before.modelPsnr.mean + 1.0);
  EXPECT_GT(r.after.modelSsim.mean, r.before.modelSsim.mean + 0.2);
}

// Label "slow": long enough to overtake the nearest-source-view baseline.
TEST(TrainTrainer, SlowOverfitsOneScene) {
  const OverfitResult r = overfit(200, 50);
  EXPECT_GT(r.after.modelPsnr.mean, r.before.modelPsnr.mean + 6.0);
  EXPECT_GT(r.after.modelPsnr.mean, r.after.baselinePsnr.mean);
}

} // namespace
} // namespace simpli::training

// Training config (defaults, strictness, round trip) and the CSV log (append, resume cut).
#include "support/expect_error.h"

#include "simpli/model/network/loader.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/log.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace simpli::training {
namespace {
namespace fs = std::filesystem;

fs::path tempDir(const std::string& name) {
  const fs::path p =
      fs::temp_directory_path() / ("simpli_training_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

TEST(TrainConfig, DefaultsAreTheReferenceTblock4Train) {
  const TrainingConfig c = parseTrainingConfig(R"({"network": "official-4l"})", "t.json", "");
  EXPECT_EQ(c.network.numPlanes, 41);
  EXPECT_DOUBLE_EQ(c.optimizer.lr, 3e-4);
  EXPECT_DOUBLE_EQ(c.optimizer.beta1, 0.9);
  EXPECT_DOUBLE_EQ(c.optimizer.beta2, 0.999);
  EXPECT_DOUBLE_EQ(c.optimizer.gamma, 0.999994);
  EXPECT_DOUBLE_EQ(c.optimizer.clipGradNorm, 20);
  EXPECT_DOUBLE_EQ(c.weight("l1"), 1);
  EXPECT_DOUBLE_EQ(c.weight("perceptual"), 0);
  for (int k = 0; k < 4; ++k)
    EXPECT_DOUBLE_EQ(c.weight("intermediate_loss_" + std::to_string(k) + "_l1"), 1);
  EXPECT_DOUBLE_EQ(c.weight("smooth_layers"), 0.01);
  EXPECT_DOUBLE_EQ(c.weight("depth"), 0); // not in the reference: off
  EXPECT_EQ(c.sampling.minViews, 2);
  EXPECT_EQ(c.sampling.maxViews, 8);
  EXPECT_EQ(c.sampling.novelViews, 4);
  EXPECT_DOUBLE_EQ(c.sampling.mixupProbability, 0.9);
  EXPECT_DOUBLE_EQ(c.sampling.mixupLambdaMax, 0.4);
}

TEST(TrainConfig, RoundTripAndNetworkFile) {
  const TrainingConfig c = parseTrainingConfig(
      R"({"network": "tiny.json", "dtype": "f64", "seed": 5, "steps": 7,
          "optimizer": {"lr": 1e-3, "warmup_steps": 25}, "loss_weights": {"perceptual": 10},
          "sampling": {"crop": [32, 48], "mixup_lambda": [0.1, 0.2], "window": 6,
                       "zoom": [1.0, 1.3], "reference_margin": 0.06,
                       "source_gain_std": [0.04, 0.015], "sharpen": [0.5, 1.5]}})",
      "t.json", SIMPLI_NETWORK_CONFIG_DIR);
  EXPECT_EQ(c.network.name, "tiny");
  EXPECT_EQ(c.dtype, ocl::Dtype::F64);
  EXPECT_EQ(c.sampling.cropWidth, 48);
  EXPECT_EQ(c.sampling.zoomScales, (std::vector<double>{1.0, 1.3}));
  EXPECT_DOUBLE_EQ(c.sampling.referenceMargin, 0.06);
  EXPECT_DOUBLE_EQ(c.sampling.sourceExposureStd, 0.04);
  EXPECT_DOUBLE_EQ(c.sampling.sourceChannelStd, 0.015);
  EXPECT_DOUBLE_EQ(c.sampling.sharpenProbability, 0.5);
  EXPECT_DOUBLE_EQ(c.sampling.sharpenMax, 1.5);
  EXPECT_EQ(c.optimizer.warmupSteps, 25);
  const TrainingConfig back = parseTrainingConfig(toJson(c), "back", "");
  EXPECT_EQ(toJson(back), toJson(c));
  EXPECT_EQ(firstIncompatibleField(c, back), "");
  TrainingConfig d = c;
  d.steps = 100;
  EXPECT_EQ(firstIncompatibleField(c, d), "");
  d.optimizer.lr = 2e-3;
  EXPECT_EQ(firstIncompatibleField(c, d), "optimizer");
}

TEST(TrainConfig, BadInputNamesFieldAndValue) {
  using test::expectError;
  expectError([] { parseTrainingConfig("{", "bad.json", ""); }, {"bad.json", "not valid JSON"});
  expectError([] { parseTrainingConfig("{}", "a.json", ""); }, {"a.json", "missing", "network"});
  expectError(
      [] { parseTrainingConfig(R"({"network": "official-4l", "stepz": 3})", "a.json", ""); },
      {"a.json", "unknown", "stepz"});
  expectError(
      [] {
        parseTrainingConfig(R"({"network": "official-4l", "loss_weights": {"l2": 1}})", "a.json",
                            "");
      },
      {"unknown", "loss_weights.l2"});
  expectError(
      [] {
        parseTrainingConfig(R"({"network": "official-4l", "optimizer": {"lr": -1}})", "a.json", "");
      },
      {"optimizer.lr", "-1", "> 0"});
  expectError(
      [] {
        parseTrainingConfig(R"({"network": "official-4l", "optimizer": {"warmup_steps": -5}})",
                            "a.json", "");
      },
      {"a.json", "optimizer.warmup_steps", "-5", ">= 0"});
  expectError(
      [] {
        parseTrainingConfig(R"({"network": "official-4l", "optimizer": {"warmup_steps": 2.5}})",
                            "a.json", "");
      },
      {"a.json", "optimizer.warmup_steps"});
  expectError(
      [] {
        parseTrainingConfig(R"({"network": "official-4l", "sampling": {"crop": [30, 32]}})",
                            "a.json", "");
      },
      {"sampling.crop", "multiples of 16"});
  expectError(
      [] {
        parseTrainingConfig(R"({"network": "official-4l", "sampling": {"crop": [96.5, 128]}})",
                            "a.json", "");
      },
      {"a.json", "\"sampling.crop[0]\" is 96.5", "expected an integer"});
  expectError(
      [] {
        parseTrainingConfig(R"({"network": "official-4l", "max_fragments": 4294967297})", "a.json",
                            "");
      },
      {"a.json", "\"max_fragments\" = 4294967297", "outside"});
  expectError(
      [] {
        parseTrainingConfig(R"({"network": "official-4l", "sampling": {"zoom": [1.2, 0.8]}})",
                            "a.json", "");
      },
      {"a.json", "sampling.zoom", "0.8", "[1, 4]"});
  expectError(
      [] {
        parseTrainingConfig(R"({"network": "official-4l", "sampling": {"zoom": []}})", "a.json",
                            "");
      },
      {"sampling.zoom", "non-empty list"});
  for (const char* margin : {"-0.01", "0.6", "\"wide\""})
    expectError(
        [&] {
          parseTrainingConfig(
              std::string(R"({"network": "official-4l", "sampling": {"reference_margin": )") +
                  margin + "}}",
              "a.json", "");
        },
        {"a.json", "sampling.reference_margin"});
  for (const char* sharpen : {"[1.5, 1]", "[0.5, -1]", "[0.5, 20]", "1"})
    expectError(
        [&] {
          parseTrainingConfig(
              std::string(R"({"network": "official-4l", "sampling": {"sharpen": )") + sharpen +
                  "}}",
              "a.json", "");
        },
        {"a.json", "sharpen"});
  for (const char* gains : {"[-0.01, 0]", "[0.1, 0.6]", "0.05", "[0.1]"})
    expectError(
        [&] {
          parseTrainingConfig(
              std::string(R"({"network": "official-4l", "sampling": {"source_gain_std": )") +
                  gains + "}}",
              "a.json", "");
        },
        {"a.json", "source_gain_std"});
  expectError(
      [] { parseTrainingConfig(R"({"network": "official-4l", "ema_decay": 1})", "a.json", ""); },
      {"a.json", "ema_decay", "[0, 1)"});
  expectError([] { parseTrainingConfig(R"({"network": "nope.json"})", "a.json", "/tmp"); },
              {"a.json", "nope.json", "does not exist"});
  expectError(
      [] { parseTrainingConfig(R"({"network": "official-4l", "dtype": "f16"})", "a.json", ""); },
      {"dtype", "f16"});
}

TEST(TrainConfig, ResolvesNamesAndFilesAsTheCliAndTheFilterDo) {
  // A shipped training config by name, a network config by name with default settings, a
  // network-config file, and an unknown name.
  const TrainingConfig tiny = resolveTrainingConfig("tiny");
  EXPECT_EQ(tiny.network, network::resolveNetworkConfig("tiny"));
  EXPECT_EQ(tiny.steps,
            loadTrainingConfig(network::networkConfigDir() + "/training/tiny.json").steps);
  const TrainingConfig eight = resolveTrainingConfig("official-8l");
  EXPECT_EQ(eight.network, network::officialConfig(8));
  EXPECT_EQ(eight.steps, TrainingConfig{}.steps);
  const TrainingConfig fromFile =
      resolveTrainingConfig(network::networkConfigDir() + "/tiny-mpi.json");
  EXPECT_TRUE(fromFile.network.mpiOnly);
  test::expectError([] { resolveTrainingConfig("no-such-config"); }, {"no-such-config"});
  test::expectError([] { resolveTrainingConfig("/nowhere/c.json"); }, {"/nowhere/c.json"});
}

TEST(TrainConfig, SyntheticSectionDefaultsRoundTripAndCompatibility) {
  const TrainingConfig d = parseTrainingConfig(R"({"network": "official-4l"})", "t.json", "");
  // Without the section: the generator's own defaults (the scenes training always used).
  EXPECT_EQ(d.synthetic.style, synthetic::SceneStyle::Objects);
  EXPECT_EQ(d.synthetic.textures, synthetic::TextureSet::Procedural);
  EXPECT_EQ(d.synthetic.views, 12);
  EXPECT_EQ(d.synthetic.objects, 8);
  EXPECT_EQ(d.synthetic.antialias, 4);
  EXPECT_EQ(d.synthetic.width, 0);
  EXPECT_TRUE(d.synthetic.photosRequired);
  EXPECT_DOUBLE_EQ(d.synthetic.translationMin, synthetic::WorldStyleParams{}.translationMin);
  EXPECT_DOUBLE_EQ(d.synthetic.translationMax, synthetic::WorldStyleParams{}.translationMax);
  EXPECT_DOUBLE_EQ(d.synthetic.objectSizeMin, 0.08);
  EXPECT_DOUBLE_EQ(d.synthetic.objectSizeMax, 0.6);
  const TrainingConfig c = parseTrainingConfig(
      R"({"network": "official-4l",
          "synthetic": {"style": "world", "textures": "photo", "photo_probability": 0.5,
                        "photo_dir": "/photos", "photos_required": false, "views": 16,
                        "objects": 5, "antialias": 2, "size": "256x192",
                        "translation": [0.1, 0.45], "object_size": [0.03, 0.2],
                        "bushes": [1, 3], "bush_scale": [1, 2.5],
                        "bush_shared_texture": 0.5}})",
      "t.json", "");
  EXPECT_EQ(c.synthetic.style, synthetic::SceneStyle::World);
  EXPECT_EQ(c.synthetic.textures, synthetic::TextureSet::Photo);
  EXPECT_DOUBLE_EQ(c.synthetic.photoProbability, 0.5);
  EXPECT_EQ(c.synthetic.photoDir, "/photos");
  EXPECT_FALSE(c.synthetic.photosRequired);
  EXPECT_EQ(c.synthetic.views, 16);
  EXPECT_EQ(c.synthetic.objects, 5);
  EXPECT_EQ(c.synthetic.antialias, 2);
  EXPECT_EQ(c.synthetic.width, 256);
  EXPECT_EQ(c.synthetic.height, 192);
  EXPECT_DOUBLE_EQ(c.synthetic.translationMin, 0.1);
  EXPECT_DOUBLE_EQ(c.synthetic.translationMax, 0.45);
  EXPECT_DOUBLE_EQ(c.synthetic.objectSizeMin, 0.03);
  EXPECT_DOUBLE_EQ(c.synthetic.objectSizeMax, 0.2);
  EXPECT_EQ(c.synthetic.bushesMin, 1);
  EXPECT_EQ(c.synthetic.bushesMax, 3);
  EXPECT_EQ(c.synthetic.bushScaleMin, 1);
  EXPECT_EQ(c.synthetic.bushScaleMax, 2.5);
  EXPECT_EQ(c.synthetic.bushSharedTexture, 0.5);
  EXPECT_EQ(d.synthetic.bushesMin, 0);
  EXPECT_EQ(d.synthetic.bushesMax, 0);
  EXPECT_EQ(d.synthetic.bushScaleMin, 1);
  EXPECT_EQ(d.synthetic.bushScaleMax, 1);
  EXPECT_EQ(d.synthetic.bushSharedTexture, 0);
  const TrainingConfig back = parseTrainingConfig(toJson(c), "back", "");
  EXPECT_EQ(toJson(back), toJson(c));
  EXPECT_EQ(toJson(parseTrainingConfig(toJson(d), "back", "")), toJson(d));
  // A resumed run must keep its scenes.
  EXPECT_EQ(firstIncompatibleField(c, back), "");
  const std::vector<std::function<void(SyntheticConfig&)>> changes{
      [](SyntheticConfig& y) { y.style = synthetic::SceneStyle::Objects; },
      [](SyntheticConfig& y) { y.translationMax = 0.3; },
      [](SyntheticConfig& y) { y.objectSizeMax = 0.6; },
      [](SyntheticConfig& y) { y.bushesMax = 2; },
      [](SyntheticConfig& y) { y.bushScaleMax = 3; },
      [](SyntheticConfig& y) { y.bushSharedTexture = 1; }};
  for (size_t i = 0; i < changes.size(); ++i) {
    TrainingConfig other = c;
    changes[i](other.synthetic);
    EXPECT_EQ(firstIncompatibleField(c, other), "synthetic") << "change " << i;
  }
}

TEST(TrainConfig, SyntheticSectionBadFieldsAreNamed) {
  using test::expectError;
  auto parse = [](const std::string& section) {
    return [section] {
      parseTrainingConfig(R"({"network": "official-4l", "synthetic": )" + section + "}", "w.json",
                          "");
    };
  };
  // Each section, and what its error must name.
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases{
      {R"({"style": "wrold"})", {"w.json", "field \"synthetic.style\"", "'wrold'", "\"world\""}},
      {R"({"textures": "photos"})",
       {"w.json", "field \"synthetic.textures\"", "'photos'", "\"photo\""}},
      {R"({"textures": 3})",
       {"w.json", "field \"synthetic.textures\"", "is 3", "expected a string"}},
      {R"({"photo_probability": 1.5})", {"w.json", "\"synthetic.photo_probability\" = 1.5"}},
      {R"({"photos_required": "yes"})",
       {"w.json", "\"synthetic.photos_required\"", "\"yes\"", "true or false"}},
      {R"({"views": 1})", {"w.json", "\"synthetic.views\" = 1"}},
      {R"({"antialias": 0})", {"w.json", "\"synthetic.antialias\" = 0"}},
      {R"({"objects": -1})", {"w.json", "\"synthetic.objects\" = -1"}},
      {R"({"size": "250x190"})", {"w.json", "\"synthetic.size\"", "250x190", "multiples of 16"}},
      {R"({"size": "big"})", {"w.json", "\"synthetic.size\"", "'big'"}},
      {R"({"sky": true})", {"w.json", "sky"}},
      {R"({"translation": [0.3, 0.1]})",
       {"w.json", "\"synthetic.translation\" = [0.3, 0.1]", "low <= high"}},
      {R"({"translation": [0, 0.2]})", {"w.json", "\"synthetic.translation\""}},
      {R"({"translation": [0.1, 0.9]})",
       {"w.json", "\"synthetic.translation\" = [0.1, 0.9]", "0.5"}},
      {R"({"translation": 0.2})", {"w.json", "translation"}},
      {R"({"object_size": [0.2, 0.03]})",
       {"w.json", "\"synthetic.object_size\" = [0.2, 0.03]", "low <= high"}},
      {R"({"object_size": [0, 0.2]})", {"w.json", "\"synthetic.object_size\" = [0, 0.2]", "0.005"}},
      {R"({"object_size": [0.1, 1.5]})",
       {"w.json", "\"synthetic.object_size\" = [0.1, 1.5]", "x the image width"}},
      {R"({"object_size": 0.1})", {"w.json", "object_size"}},
      {R"({"bushes": [3, 1]})", {"w.json", "\"synthetic.bushes\" = [3, 1]", "low <= high"}},
      {R"({"bushes": [-1, 2]})", {"w.json", "\"synthetic.bushes\" = [-1, 2]"}},
      {R"({"bushes": [1, 51]})", {"w.json", "\"synthetic.bushes\" = [1, 51]", "50"}},
      {R"({"bushes": [1, 2.5]})",
       {"w.json", "\"synthetic.bushes[1]\" is 2.5", "expected an integer"}},
      // Integers that do not fit an int are named, not wrapped (2^32 + 2 would become 2).
      {R"({"bushes": [1, 4294967298]})",
       {"w.json", "\"synthetic.bushes[1]\" = 4294967298", "outside"}},
      {R"({"views": 4294967308})", {"w.json", "\"synthetic.views\" = 4294967308", "outside"}},
      {R"({"objects": 18446744073709551615})",
       {"w.json", "\"synthetic.objects\" = 18446744073709551615", "too large"}},
      {R"({"bushes": 2})", {"w.json", "bushes"}},
      {R"({"bush_scale": [3, 1]})", {"w.json", "\"synthetic.bush_scale\" = [3, 1]", "low <= high"}},
      {R"({"bush_scale": [0.1, 1]})", {"w.json", "\"synthetic.bush_scale\" = [0.1, 1]", "0.25"}},
      {R"({"bush_scale": [1, 5]})", {"w.json", "\"synthetic.bush_scale\" = [1, 5]", "4"}},
      {R"({"bush_scale": "big"})", {"w.json", "bush_scale", "[number, number]"}},
      {R"({"bush_shared_texture": 1.5})",
       {"w.json", "\"synthetic.bush_shared_texture\" = 1.5", "probability"}},
      {R"({"bush_shared_texture": "all"})", {"w.json", "bush_shared_texture", "expected a number"}},
      {R"("world")", {"w.json", "synthetic"}},
  };
  for (const auto& [section, parts] : cases) {
    SCOPED_TRACE(section);
    expectError(parse(section), parts);
  }
}

TEST(TrainConfig, ShippedWorldRecipe) {
  const TrainingConfig c = resolveTrainingConfig("tiny-world");
  EXPECT_EQ(c.network.name, "tiny");
  EXPECT_EQ(c.synthetic.style, synthetic::SceneStyle::World);
  EXPECT_EQ(c.synthetic.textures, synthetic::TextureSet::Photo);
  EXPECT_EQ(c.synthetic.width, 256);
  EXPECT_EQ(c.synthetic.height, 192);
  EXPECT_GT(c.sampling.window, 0);
  EXPECT_LT(c.sampling.window, c.synthetic.views); // windows of a longer path
  // The shipped tiny recipe keeps the scenes it was trained on.
  const TrainingConfig tiny = resolveTrainingConfig("tiny");
  EXPECT_EQ(tiny.synthetic.style, synthetic::SceneStyle::Objects);
  EXPECT_EQ(tiny.synthetic.textures, synthetic::TextureSet::Procedural);
}

// Every recipe in model/configs/training loads (its network file resolves) and round-trips;
// the wide-planes recipes of the long run and of its MPI-only baseline differ only in the
// network.
TEST(TrainConfig, EveryShippedRecipeLoads) {
  const std::filesystem::path dir = std::filesystem::path(SIMPLI_NETWORK_CONFIG_DIR) / "training";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json")
      continue;
    SCOPED_TRACE(entry.path().string());
    const TrainingConfig c = loadTrainingConfig(entry.path().string());
    EXPECT_FALSE(c.network.name.empty());
    EXPECT_GT(c.steps, 0);
    EXPECT_EQ(toJson(parseTrainingConfig(toJson(c), "round trip", "")), toJson(c));
    ++count;
  }
  EXPECT_GE(count, 10);
  const TrainingConfig simpli = resolveTrainingConfig("tiny-world-wide-planes");
  TrainingConfig mpi = resolveTrainingConfig("tiny-mpi-world-wide-planes");
  EXPECT_TRUE(mpi.network.mpiOnly);
  EXPECT_FALSE(simpli.network.mpiOnly);
  EXPECT_GT(mpi.weight("mpi_depth"), 0);
  mpi.network = simpli.network;
  EXPECT_EQ(toJson(mpi), toJson(simpli));
}

TEST(TrainLog, AppendsAndCutsBackOnResume) {
  const fs::path dir = tempDir("log");
  const std::string path = (dir / "log.csv").string();
  const std::vector<std::string> cols{"step", "l1", "total"};
  {
    TrainLog log(path, cols, -1);
    for (int s = 1; s <= 5; ++s)
      log.append({double(s), 0.1 * s, std::nan("")});
  }
  std::vector<std::string> header;
  auto rows = TrainLog::read(path, &header);
  EXPECT_EQ(header, cols);
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[2][1], 0.1 * 3); // 17 digits read back exactly
  EXPECT_TRUE(std::isnan(rows[2][2]));
  // A torn last line (crash mid-write) and a resume at step 3.
  {
    std::ofstream f(path, std::ios::app);
    f << "6,0.6";
  }
  {
    TrainLog log(path, cols, 3);
    log.append({4, 0.44, 1});
  }
  rows = TrainLog::read(path);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[3][0], 4);
  EXPECT_EQ(rows[3][1], 0.44);
  test::expectError(
      [&] {
        TrainLog(path, {"step", "other"}, 2);
      },
      {path, "header", "cannot resume"});
  fs::remove_all(dir);
}

} // namespace
} // namespace simpli::training

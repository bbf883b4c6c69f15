// `simpli eval DATA --weights W --config C`: PSNR / SSIM of novel views with the paper's
// protocol (central 90 % crop), mean +- std over R repeated samples, next to the nearest-source-
// view baseline on the same samples.
#include "commands.h"
#include "progress_bar.h"

#include <CLI/CLI.hpp>
#include <simpli/error.h>
#include <simpli/model/network/loader.h>
#include <simpli/model/training/train_config.h>
#include <simpli/model/training/train_eval.h>
#include <simpli/ocl/device.h>

#include <cstdio>
#include <memory>
#include <optional>

namespace simpli::app {

namespace {

struct EvalCliOptions {
  std::string data, weights, config, size, device, dtype = "f32";
  int repeats = 1, views = 4, novel = 4, window = 0, scenes = 1, corrections = -1;
  int64_t seed = 0;
};

void runEval(const EvalCliOptions& o) {
  if (o.repeats < 1)
    fail("--repeats ", o.repeats, ": must be >= 1");
  if (o.views < 1)
    fail("--views ", o.views, ": must be >= 1");
  if (o.novel < 1)
    fail("--novel ", o.novel, ": must be >= 1");
  if (o.window < 0)
    fail("--window ", o.window, ": must be >= 0");
  if (o.scenes < 1)
    fail("--scenes ", o.scenes, ": must be >= 1");
  if (o.seed < 0)
    fail("--seed ", o.seed, ": must be >= 0");
  if (o.dtype != "f32" && o.dtype != "f64")
    fail("--dtype '", o.dtype, "': expected f32 or f64");
  if (!o.device.empty()) {
    const auto [p, d] = ocl::Device::parseSelector(o.device, "--device");
    ocl::Device::select(p, d);
  }
  net::NetworkConfig config;
  if (!o.config.empty()) {
    config = train::loadNetworkOrTrainingConfig(o.config);
  } else {
    const std::optional<net::NetworkConfig> fromWeights = net::configFromWeights(o.weights);
    if (!fromWeights)
      fail("--config is required: ", o.weights, " carries no \"network_config\" metadata");
    config = *fromWeights;
  }
  train::DataOptions data;
  if (!o.size.empty())
    train::parseWidthHeight(o.size, "--size", data.width, data.height);
  auto source = train::openTrainingData(o.data, data);
  net::SimpliNetwork network(config, o.dtype == "f64" ? ocl::Dtype::F64 : ocl::Dtype::F32);
  network.parameters().load(o.weights);
  train::EvalOptions e;
  e.repeats = o.repeats;
  e.views = o.views;
  e.novelViews = o.novel;
  e.window = o.window;
  e.scenes = o.scenes;
  e.seed = uint64_t(o.seed);
  e.corrections = o.corrections;
  const uint64_t scenes = source->sceneCount() > 0 ? source->sceneCount() : uint64_t(o.scenes);
  ProgressBar bar("eval", int64_t(scenes) * o.repeats);
  const train::EvalResult r =
      train::evaluate(network, *source, e, [&](int done, int) { bar.update(done); });
  bar.finish();
  std::printf("evaluated %zu novel views (%s; %d sources, %d repeats, seed %lld; central 90%% "
              "crop)\n",
              r.model.size(), source->describe().c_str(), o.views, o.repeats,
              static_cast<long long>(o.seed));
  std::printf("  %-22s PSNR %6.2f +- %.2f dB   SSIM %.4f +- %.4f\n", "model", r.modelPsnr.mean,
              r.modelPsnr.std, r.modelSsim.mean, r.modelSsim.std);
  std::printf("  %-22s PSNR %6.2f +- %.2f dB   SSIM %.4f +- %.4f\n", "nearest source view",
              r.baselinePsnr.mean, r.baselinePsnr.std, r.baselineSsim.mean, r.baselineSsim.std);
}

} // namespace

void addEvalCommand(CLI::App& app) {
  auto opts = std::make_shared<EvalCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "PSNR / SSIM of novel views (paper protocol) against the nearest-source-view "
              "baseline");
  cmd->add_option("data", opts->data,
                  "A scene folder, a folder of scene folders, or synthetic[:SEED]")
      ->required();
  cmd->add_option("--weights", opts->weights, "Network weights (safetensors)")->required();
  cmd->add_option("--config", opts->config,
                  "Network config or training config JSON (default: the weights' "
                  "\"network_config\" metadata, which `simpli train` writes)");
  cmd->add_option("--repeats", opts->repeats, "Samples per scene")->capture_default_str();
  cmd->add_option("--views", opts->views, "Source views per sample")->capture_default_str();
  cmd->add_option("--novel", opts->novel, "Novel (held-out) views per sample")
      ->capture_default_str();
  cmd->add_option("--window", opts->window, "Frame window the views come from (0 = all)")
      ->capture_default_str();
  cmd->add_option("--scenes", opts->scenes, "Scenes to draw from synthetic data")
      ->capture_default_str();
  cmd->add_option("--seed", opts->seed, "Sampling seed")->capture_default_str();
  cmd->add_option("--corrections", opts->corrections, "MLI corrections to run (-1 = all)")
      ->capture_default_str();
  cmd->add_option("--size", opts->size, "Resize the images to WIDTHxHEIGHT (multiples of 16)");
  cmd->add_option("--dtype", opts->dtype, "f32 or f64")->capture_default_str();
  cmd->add_option("--device", opts->device, "OpenCL device p:d (see `simpli devices`)");
  cmd->callback([opts] { runEval(*opts); });
}

} // namespace simpli::app

// `simpli widen --weights W --out W2.safetensors [--factor 2] [--noise 0.01]`: a wider network
// that computes what W computes (network/widen.h), to train on from where W stopped. The output
// carries its config in its metadata ("network_config"), so infer, eval and `train
// --init-weights` read it like any other weights; --config-out also writes that config as JSON
// for a training config's "network". Outputs are written atomically; an existing file is
// replaced only with --force, and never the input weights.
#include "commands.h"
#include "output_file.h"

#include "simpli/error.h"
#include "simpli/model/io/files.h"
#include "simpli/model/network/loader.h"
#include "simpli/model/network/widen.h"
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

namespace simpli::app {
namespace {

struct WidenCliOptions {
  std::string weights, config, out, configOut;
  network::WidenOptions widen;
  bool force = false;
};

/// Throws a named error unless `path` may be written (output_file.h), and never for the input.
void checkOutputFile(const std::string& path, const std::string& flag, const WidenCliOptions& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(path, ec) && fs::exists(o.weights, ec) && fs::equivalent(path, o.weights, ec))
    fail(flag, " ", path, " is the input weights; refusing to replace them");
  app::checkOutputFile(path, flag, o.force, "give a file name");
}

void runWiden(const WidenCliOptions& o) {
  if (o.weights.empty())
    fail("--weights is required (the network to widen)");
  checkOutputFile(o.out, "--out", o);
  if (!o.configOut.empty())
    checkOutputFile(o.configOut, "--config-out", o);
  network::checkWidenOptions(o.widen); // before the weights are read
  const network::LoadedNetwork from = network::loadNetwork(o.config, o.weights, std::nullopt);
  const std::unique_ptr<network::SimpliNetwork> wide =
      network::widenNetwork(*from.network, o.widen);
  const std::string json = network::toJson(wide->config());
  wide->parameters().save(o.out, {{"network_config", json},
                                  {"widened_from", o.weights},
                                  {"widen_factor", std::to_string(o.widen.factor)},
                                  {"widen_noise", std::to_string(o.widen.noise)},
                                  {"widen_seed", std::to_string(o.widen.seed)}});
  if (!o.configOut.empty())
    io::writeFileAtomically(o.configOut, json.data(), json.size());
  std::printf(
      "widened %s (config %s, %lld parameters) x%d -> %s (config %s, %lld parameters)%s%s\n",
      o.weights.c_str(), from.network->config().name.c_str(),
      static_cast<long long>(from.network->parameters().count()), o.widen.factor, o.out.c_str(),
      wide->config().name.c_str(), static_cast<long long>(wide->parameters().count()),
      o.configOut.empty() ? "" : "; config -> ", o.configOut.c_str());
}

} // namespace

void addWidenCommand(CLI::App& app) {
  auto o = std::make_shared<WidenCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "widen", "A wider network computing the same function as the given weights (every "
               "internal width x factor), to train on from where they stopped");
  cmd->add_option("--weights", o->weights, "Weights to widen (safetensors)")->required();
  cmd->add_option("--config", o->config,
                  "Their network config (default: the weights' \"network_config\" metadata)");
  cmd->add_option("--out", o->out, "Widened weights to write (safetensors, with their config)")
      ->required();
  cmd->add_option("--config-out", o->configOut, "Also write the widened network config (JSON)");
  cmd->add_option("--factor", o->widen.factor, "Every internal width x this, 2 to 8")
      ->capture_default_str();
  cmd->add_option("--noise", o->widen.noise,
                  "Perturbation that lets the copies of a channel learn apart, x each weight "
                  "tensor's RMS (zero-sum over the copies: the function is kept), >= 0")
      ->capture_default_str();
  cmd->add_option("--seed", o->widen.seed, "Seed of the perturbation")->capture_default_str();
  cmd->add_flag("--force", o->force, "Replace existing output files (never the input weights)");
  cmd->callback([o] { runWiden(*o); });
}

} // namespace simpli::app

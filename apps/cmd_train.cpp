// `simpli train DATA... --config C --out RUN`: trains a SIMPLI network (model/training/). DATA is
// a scene folder, a folder of scene folders, or synthetic[:SEED]; several DATA (each optionally
// SPEC@WEIGHT) are mixed by weight (training/data.h). SIGINT / SIGTERM (any number of
// them, from the moment the command starts) finish the current step, write a checkpoint and exit
// with 130 / 143; `--resume` continues the run.
//
// Under an MPI launcher (`mpiexec -n K simpli train ...`, docs/parallel.md) the K ranks train one
// network data-parallel (training/trainer.h): rank 0 prints, logs and checkpoints; a signal to
// any rank stops all of them after the current step and one checkpoint, and every rank exits
// with the same code; an error on one rank ends the job with a message naming it (main.cpp).
#include "commands.h"
#include "progress_bar.h"
#include "stop_signals.h"

#include "simpli/error.h"
#include "simpli/model/io/staged_folder.h"
#include "simpli/model/parallel/communicator.h"
#include "simpli/model/training/monitor.h"
#include "simpli/model/training/snapshots.h"
#include "simpli/model/training/trainer.h"
#include "simpli/ocl/device.h"
#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace simpli::app {

namespace {

struct TrainCliOptions {
  std::vector<std::string> data;
  std::string config, out, vgg, size, device, initWeights;
  std::string validate, validateSize = "256x192";
  int64_t validateEvery = 100;
  int64_t keepWeightsEvery = 0;
  bool resume = false;
  int64_t steps = -1, checkpointEvery = -1;
  int64_t seed = -1;
  int samplesPerRank = 1;
  int testExitRank = -1; ///< testing: this rank dies (no MPI_Finalize) after its first step
};

/// Every rank's stop signal, agreed (collective): SIGTERM when any rank had one, else SIGINT
/// when any had it, and on how many ranks.
struct AgreedSignal {
  int signal = 0, ranks = 0;
};
AgreedSignal agreedSignal(parallel::Communicator& comm) {
  const int own = stopSignal();
  if (comm.size() == 1)
    return {own, own != 0 ? 1 : 0};
  std::vector<double> seen{own == SIGINT ? 1.0 : 0.0, own == SIGTERM ? 1.0 : 0.0};
  comm.allreduceSum(seen);
  const int signal = seen[1] > 0 ? SIGTERM : seen[0] > 0 ? SIGINT : 0;
  return {signal, int(seen[0] + seen[1])};
}

/// Throughput of the steps this process ran: samples per second and the all-reduce's share.
struct Throughput {
  int64_t steps = 0;
  int samples = 1;
  double ms = 0, allreduceMs = 0, exchangeMs = 0;
  void add(const training::StepReport& r) {
    // The first step of a process compiles the kernels: not a measure of the run's speed.
    if (++seen == 1)
      return;
    ++steps;
    samples = r.samples;
    ms += r.ms;
    allreduceMs += r.allreduceMs;
    exchangeMs += r.exchangeMs;
  }
  int64_t seen = 0;
};

void selectDevice(const std::string& text) {
  if (text.empty())
    return;
  const auto [p, d] = ocl::Device::parseSelector(text, "--device");
  ocl::Device::select(p, d);
}

int runTrain(const TrainCliOptions& o) {
  // First of all: a signal during start-up (device, data, network) is a stop request too, and
  // every later one is absorbed until the checkpoint is written (stop_signals.h).
  StopSignals signals;
  parallel::Communicator& comm = parallel::world();
  const bool root = comm.isRoot();
  if (o.samplesPerRank < 1)
    fail("--samples-per-rank ", o.samplesPerRank, ": must be >= 1");
  // A new run folder that cannot be written fails before the device and the data are opened.
  if (!o.resume && !o.out.empty())
    io::checkOutputLocation(o.out, "--out", /*createParents=*/true);
  selectDevice(o.device);
  training::TrainerOptions t;
  for (const std::string& d : o.data)
    t.data.push_back(training::parseDataSource(d));
  t.runDir = o.out;
  t.resume = o.resume;
  t.steps = o.steps;
  t.checkpointEvery = o.checkpointEvery;
  t.vggPath = o.vgg;
  t.initWeights = o.initWeights;
  t.samplesPerRank = o.samplesPerRank;
  if (!o.config.empty())
    t.dataOptions.configSource = "training config '" + o.config + "'";
  if (!o.size.empty())
    training::parseWidthHeight(o.size, "--size", t.dataOptions.width, t.dataOptions.height);
  if (o.seed >= 0)
    t.seed = uint64_t(o.seed);
  if (o.steps < -1)
    fail("--steps ", o.steps, ": must be >= 0");
  if (o.checkpointEvery == 0 || o.checkpointEvery < -1)
    fail("--checkpoint-every ", o.checkpointEvery, ": must be >= 1");
  if (o.keepWeightsEvery < 0)
    fail("--keep-weights-every ", o.keepWeightsEvery, ": must be >= 1 (or 0: keep none)");
  std::unique_ptr<training::TrainingConfig> config;
  if (!o.config.empty())
    config = std::make_unique<training::TrainingConfig>(training::resolveTrainingConfig(o.config));
  else if (!o.resume)
    fail("--config is required for a new run (a resumed run uses its own config.json)");

  std::unique_ptr<ProgressBar> bar;
  t.message = [&](const std::string& m) {
    if (bar)
      bar->message(m);
    else
      std::fprintf(stderr, "%s\n", m.c_str());
  };
  t.stopRequested = [] { return stopSignal() != 0; };
  Throughput speed;
  t.onStep = [&](const training::StepReport& r) {
    speed.add(r);
    if (r.step == 1 && comm.rank() == o.testExitRank)
      std::_Exit(3); // testing: a rank that dies without a word to MPI
    if (!bar)
      return;
    char detail[128];
    std::snprintf(detail, sizeof detail, "loss %.4f, l1 %.4f, lr %.3g, %.0f ms/step", r.total,
                  r.terms[0].second, r.lr, r.ms);
    bar->update(r.step, detail);
  };
  // Validation and the progress pictures are rank 0's (it owns the run folder).
  training::ValidationOptions v;
  v.scene = root ? o.validate : std::string();
  v.every = o.validateEvery;
  if (o.validateEvery < 1)
    fail("--validate-every ", o.validateEvery, ": must be >= 1");
  training::parseWidthHeight(o.validateSize, "--validate-size", v.width, v.height);
  training::TrainingMonitor monitor(o.out, v);
  training::Trainer* running = nullptr;            // set below; checkpoints happen only in run()
  std::unique_ptr<training::WeightSnapshots> kept; // rank 0's, made once the start step is known
  auto monitorStep = [&](int64_t step, bool force) {
    if (const auto s = monitor.update(running->validationNetwork(), step, force)) {
      char line[160];
      std::snprintf(line, sizeof line,
                    "validation at step %lld: %.2f dB / SSIM %.3f (nearest view %.2f dB)%s",
                    static_cast<long long>(step), s->psnr, s->ssim, s->nearestPsnr,
                    s->best ? ", the best so far: kept in best.safetensors" : "");
      t.message(line);
    }
  };
  t.onCheckpoint = [&](int64_t step) {
    if (!root)
      return;
    monitorStep(step, false);
    if (kept->due(step))
      t.message("kept the weights of step " + std::to_string(step) + " in " +
                kept->keep(running->validationNetwork(), step));
  };
  training::Trainer trainer(config.get(), t);
  running = &trainer;
  if (root) {
    kept = std::make_unique<training::WeightSnapshots>(o.out, o.keepWeightsEvery,
                                                       o.resume ? trainer.startStep() : 0);
    monitor.begin(o.resume ? trainer.startStep() : -1, trainer.config().sampling.referenceMargin);
    bar = std::make_unique<ProgressBar>("train", trainer.totalSteps(), trainer.startStep());
  }
  const training::Trainer::RunResult result = trainer.run();
  // A finished run is validated at its last step too (an interrupted one exits at once).
  if (root && !result.interrupted && monitor.validating() &&
      monitor.lastValidated() != result.steps)
    monitorStep(result.steps, true);
  if (bar)
    bar->finish();
  const AgreedSignal agreed = agreedSignal(comm);
  const int sig = agreed.signal;
  if (!root)
    return sig != 0 ? 128 + sig : 0;
  const std::string averaged =
      trainer.average() ? ", moving average " + o.out + "/weights_ema.safetensors" : "";
  std::printf("%s at step %lld of %lld; run folder %s (weights %s/weights.safetensors%s)\n",
              result.interrupted ? "stopped" : "finished", static_cast<long long>(result.steps),
              static_cast<long long>(trainer.totalSteps()), o.out.c_str(), o.out.c_str(),
              averaged.c_str());
  if (speed.steps > 0 && trainer.samplesPerStep() > 1)
    std::printf("throughput %.2f samples/s (%d rank(s) x %d sample(s) per step, %.0f ms per step "
                "over %lld steps after the first); all-reduce %.1f ms per step (%.1f%% of a "
                "step), whole gradient exchange %.1f ms (%.1f%%)\n",
                speed.samples * speed.steps * 1000.0 / speed.ms, comm.size(), o.samplesPerRank,
                speed.ms / speed.steps, static_cast<long long>(speed.steps),
                speed.allreduceMs / speed.steps, 100.0 * speed.allreduceMs / speed.ms,
                speed.exchangeMs / speed.steps, 100.0 * speed.exchangeMs / speed.ms);
  else if (speed.steps > 0)
    std::printf("throughput %.2f samples/s (1 sample per step, %.0f ms per step over %lld steps "
                "after the first)\n",
                speed.steps * 1000.0 / speed.ms, speed.ms / speed.steps,
                static_cast<long long>(speed.steps));
  std::fflush(stdout);
  if (sig != 0) {
    // Also when the signal came during the final checkpoint of a finished run: the caller
    // (timeout, a shell) asked the command to stop and learns that it did.
    const std::string where = comm.size() == 1 ? std::string()
                                               : " on " + std::to_string(agreed.ranks) + " of " +
                                                     std::to_string(comm.size()) + " ranks";
    std::fprintf(stderr, "simpli train: %s received%s; checkpoint written%s\n",
                 sig == SIGTERM ? "SIGTERM" : "SIGINT", where.c_str(),
                 result.interrupted ? ", resume with --resume" : " (the run had finished)");
    return 128 + sig;
  }
  return 0;
}

} // namespace

void addTrainCommand(CLI::App& app) {
  auto opts = std::make_shared<TrainCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "train", "Train a SIMPLI network on scenes (checkpointed, resumable; Ctrl-C stops "
               "cleanly after a checkpoint)");
  cmd->add_option("data", opts->data,
                  "A scene folder, a folder of scene folders, or synthetic[:SEED]; several "
                  "are mixed, each SPEC@WEIGHT drawn with its share of the weights (default 1)")
      ->required();
  cmd->add_option("--config", opts->config,
                  "Training config: a name (tiny, official-4l: model/configs/training/NAME.json, "
                  "else a network config with default settings) or a JSON file; optional "
                  "with --resume");
  cmd->add_option("--out", opts->out, "Run folder (new, or the run to continue with --resume)")
      ->required();
  cmd->add_flag("--resume", opts->resume, "Continue the run in --out from its last checkpoint");
  CLI::Option* steps =
      cmd->add_option("--steps", opts->steps, "Total steps of the run (default: the config's)");
  cmd->add_option("--checkpoint-every", opts->checkpointEvery,
                  "Steps between checkpoints (default: the config's)");
  cmd->add_option("--vgg", opts->vgg,
                  "VGG-19 weights (safetensors, torchvision key names) for the perceptual loss");
  cmd->add_option("--init-weights", opts->initWeights,
                  "Warm-start a new run from these weights (safetensors with every parameter of "
                  "the config's network, e.g. model/weights/default.safetensors for tiny-prior)");
  cmd->add_option("--size", opts->size,
                  "Resize the images to WIDTHxHEIGHT, e.g. 192x128 (multiples of 16)");
  cmd->add_option("--seed", opts->seed, "Seed of the network initialisation and sampling");
  cmd->add_option("--device", opts->device, "OpenCL device p:d (see `simpli devices`)");
  cmd->add_option("--validate", opts->validate,
                  "A scene folder scored at checkpoints (fixed sources and novel views): "
                  "RUN/val.csv, RUN/validation/step_N.png, and a panel in RUN/progress.png");
  cmd->add_option("--validate-every", opts->validateEvery,
                  "Steps between validations, checked at checkpoints (default 100)");
  cmd->add_option("--validate-size", opts->validateSize,
                  "Size of the validation images, WIDTHxHEIGHT (default 256x192)");
  cmd->add_option("--keep-weights-every", opts->keepWeightsEvery,
                  "Keep the weights (their moving average, if any) of every N-th step for good "
                  "in RUN/kept/step_N.safetensors, at the first checkpoint at or after each "
                  "multiple (default 0: none; checkpoints keep only the last steps)");
  cmd->add_option("--samples-per-rank", opts->samplesPerRank,
                  "Samples per step on each rank, their gradients averaged (gradient "
                  "accumulation; one rank with N equals N MPI ranks with 1; default 1)");
  // Testing only (hidden): the rank that dies after its first step, as a crash would.
  cmd->add_option("--test-exit-rank", opts->testExitRank)->group("");
  cmd->callback([opts, steps] {
    // -1 is the internal "the config's"; on the command line every negative is wrong.
    if (steps->count() > 0 && opts->steps < 0)
      fail("--steps ", opts->steps, ": must be >= 0");
    const int code = runTrain(*opts);
    if (code != 0) {
      std::fflush(nullptr);
      std::exit(code);
    }
  });
}

} // namespace simpli::app

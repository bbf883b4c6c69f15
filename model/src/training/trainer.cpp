// The training loop (trainer.h).
#include "simpli/model/training/trainer.h"

#include "simpli/error.h"
#include "simpli/model/io/files.h"
#include "simpli/model/training/checkpoint.h"
#include "simpli/model/training/losses.h"
#include "simpli/warning.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_shape.h"

#include <chrono>
#include <cmath>
#include <filesystem>

namespace simpli::training {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> logColumns() {
  std::vector<std::string> c{"step"};
  for (const std::string& t : lossTermNames())
    c.push_back(t);
  for (const char* extra : {"total", "lr", "grad_norm", "step_ms"})
    c.emplace_back(extra);
  return c;
}
} // namespace

uint64_t samplerSeed(uint64_t seed) {
  return seed ^ 0x5a3c9e17d2b4f601ULL;
}

ocl::Tensor imagesToTensor(const std::vector<io::Image>& images, ocl::Dtype dtype) {
  if (images.empty())
    fail("imagesToTensor: no images");
  const int H = images[0].height, W = images[0].width;
  std::vector<double> values;
  values.reserve(images.size() * 3 * size_t(H) * size_t(W));
  for (const io::Image& im : images) {
    if (im.width != W || im.height != H)
      fail("imagesToTensor: images of different sizes (", W, "x", H, " and ", im.width, "x",
           im.height, ")");
    values.insert(values.end(), im.data.begin(), im.data.end());
  }
  return ocl::Tensor::fromHost(values, {int64_t(images.size()), 3, H, W}, dtype);
}

Trainer::Trainer(const TrainingConfig* config, const TrainerOptions& options) : options_(options) {
  auto say = [&](const std::string& m) {
    if (options_.message)
      options_.message(m);
  };
  if (options_.runDir.empty())
    fail("trainer: no run folder given");
  const fs::path run(options_.runDir);
  const std::string configPath = (run / "config.json").string();
  std::optional<std::string> checkpoint;
  if (options_.resume) {
    if (!fs::is_directory(run))
      fail("--resume: run folder '", options_.runDir, "' does not exist");
    if (!fs::exists(configPath))
      fail("--resume: '", options_.runDir, "' has no config.json (not a training run folder)");
    config_ = loadTrainingConfig(configPath);
    if (options_.seed && *options_.seed != config_.seed)
      fail("--resume: seed ", *options_.seed, " differs from the run's seed ", config_.seed, " (",
           configPath, ")");
    if (config) {
      TrainingConfig given = *config;
      if (options_.seed)
        given.seed = *options_.seed;
      const std::string field = firstIncompatibleField(config_, given);
      if (!field.empty())
        fail("--resume: the given config differs from the run's ", configPath, " in field \"",
             field, "\" (only steps and checkpoint_every may change)");
      config_.steps = config->steps;
      config_.checkpointEvery = config->checkpointEvery;
    }
    checkpoint = latestCheckpoint(options_.runDir);
  } else {
    if (!config)
      fail("trainer: a new run needs a training config");
    config_ = *config;
    if (options_.seed)
      config_.seed = *options_.seed;
    std::error_code ec;
    if (fs::exists(run) && !fs::is_empty(run, ec))
      fail("run folder '", options_.runDir,
           "' already exists and is not empty; use --resume to continue it");
  }
  totalSteps_ = options_.steps >= 0 ? options_.steps : config_.steps;
  checkpointEvery_ =
      options_.checkpointEvery > 0 ? options_.checkpointEvery : config_.checkpointEvery;

  // Everything that can fail on bad input (data, VGG file) is checked before a new run
  // creates its folder, so a failed start leaves nothing behind.
  DataOptions dataOptions = options_.dataOptions;
  dataOptions.synthetic = config_.synthetic;
  if (options_.resume)
    dataOptions.configSource = configPath;
  data_ = openTrainingData(options_.data, dataOptions);
  data_->scene(0); // reads (and checks) the first scene
  if (!options_.vggPath.empty()) {
    // A file that is not VGG-19 weights is an error even when the loss is off.
    if (config_.weight("perceptual") > 0)
      vgg_ = Vgg19Features(options_.vggPath, config_.dtype);
    else
      Vgg19Features::check(options_.vggPath);
  }
  network_ = std::make_unique<network::SimpliNetwork>(config_.network, config_.dtype, config_.seed);
  if (!options_.initWeights.empty()) {
    if (options_.resume)
      fail("--init-weights '", options_.initWeights,
           "': a resumed run continues from its own checkpoint; warm-start a new run instead");
    const network::LoadReport r = network_->parameters().load(options_.initWeights);
    say("initial weights: " + options_.initWeights + " (" + std::to_string(r.loaded) + " tensors" +
        (r.unexpected.empty() ? std::string()
                              : ", " + std::to_string(r.unexpected.size()) + " unused") +
        ")");
  }
  generator_ = std::make_unique<generator::Generator>(*network_);
  const OptimizerConfig& o = config_.optimizer;
  adam_ = std::make_unique<ocl::Adam>(network_->parameters().parameters(), o.lr, o.beta1, o.beta2,
                                      o.eps);
  schedule_ = std::make_unique<ocl::ExponentialLr>(o.lr, o.gamma);
  sampler_ = std::make_unique<Sampler>(config_.sampling, samplerSeed(config_.seed));
  if (config_.emaDecay > 0)
    average_ = std::make_unique<ParameterAverage>(network_->parameters(), config_.emaDecay);

  if (!options_.resume) {
    std::error_code ec;
    fs::create_directories(run, ec);
    if (ec)
      fail("cannot create run folder '", options_.runDir, "': ", ec.message());
    const std::string text = toJson(config_);
    io::writeFileAtomically(configPath, text.data(), text.size());
  }
  if (checkpoint) {
    CheckpointData c = readCheckpoint(*checkpoint, network_->parameters());
    adam_->importState(c.adam);
    sampler_->random().setState(c.random);
    if (average_) {
      if (c.average.empty())
        fail(*checkpoint, ": no weights_ema.safetensors, but the run's ema_decay is ",
             config_.emaDecay);
      average_->setValues(c.average, *checkpoint + "/weights_ema.safetensors");
    }
    step_ = c.step;
    say("resumed from " + *checkpoint + " at step " + std::to_string(step_));
  } else if (options_.resume) {
    say("no checkpoint in " + options_.runDir + "; starting at step 0");
  }
  startStep_ = step_;
  log_ = std::make_unique<TrainLog>((run / "log.csv").string(), logColumns(),
                                    options_.resume ? step_ : -1);

  if (!options_.vggPath.empty()) {
    if (vgg_.loaded()) {
      say("perceptual loss: VGG-19 from " + options_.vggPath + ", weight " +
          std::to_string(config_.weight("perceptual")));
    } else {
      warn("VGG-19 weights ", options_.vggPath,
           ": the training config's loss_weights.perceptual is 0, so the perceptual loss is off "
           "and the file is not used (give the term a positive weight to train with it)");
    }
  } else {
    say("perceptual loss: off (no VGG-19 weights given; pass --vgg FILE to enable it)");
  }
  say("data: " + data_->describe() + "; network " + config_.network.name + ", " +
      std::to_string(network_->parameters().count()) + " parameters, " +
      (config_.dtype == ocl::Dtype::F64 ? "f64" : "f32"));
}

Trainer::~Trainer() = default;

StepReport Trainer::trainStep() {
  const auto t0 = std::chrono::steady_clock::now();
  const ocl::Dtype dtype = config_.dtype;
  const TrainingSample s = sampler_->draw(*data_);
  const ocl::Tensor images = imagesToTensor(s.sources, dtype);
  const ocl::Tensor clean = imagesToTensor(s.cleanSources, dtype);
  const ocl::Tensor targets = imagesToTensor(s.targets, dtype);

  adam_->zeroGrad();
  generator::GeneratorInput in;
  in.images = images;
  in.sources = s.sourceCameras;
  in.reference = s.reference;
  generator::GeneratorOptions go;
  go.corrections = config_.corrections;
  go.keepIntermediates = true;
  go.raster.maxFragments = config_.maxFragments;
  const generator::GeneratorOutput out = generator_->forward(in, go);
  std::vector<ocl::Tensor> colours, opacities;
  for (const scene::Camera& target : s.targetCameras) {
    const raster::RenderedLayers r =
        generator::renderNovelView(out, s.reference, target, go.raster);
    colours.push_back(ocl::unsqueeze(r.colour, 0));
    opacities.push_back(ocl::unsqueeze(r.opacity, 0));
  }
  const LossTerms losses =
      computeLosses(config_, out, ocl::concat(colours, 0), ocl::concat(opacities, 0), targets,
                    clean, vgg_.loaded() ? &vgg_ : nullptr);
  StepReport report;
  report.total = losses.total.item();
  if (losses.total.hasGradFn())
    losses.total.backward();
  const std::vector<ocl::Tensor>& params = adam_->parameters();
  report.gradNorm = ocl::clipGradNorm(params, config_.optimizer.clipGradNorm);
  report.lr = schedule_->lrAt(step_);
  if (std::isfinite(report.gradNorm) && std::isfinite(report.total)) {
    adam_->setLr(report.lr);
    adam_->step();
  } else {
    report.skipped = true;
    if (options_.message)
      options_.message("step " + std::to_string(step_ + 1) +
                       ": non-finite loss or gradient; no update made");
  }
  if (average_)
    average_->update(network_->parameters());
  ++step_;
  for (const std::string& t : lossTermNames())
    report.terms.emplace_back(t, losses.value(t));
  ocl::Device::current().finish();
  report.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  report.step = step_;

  std::vector<double> row{double(step_)};
  for (const auto& [name, v] : report.terms)
    row.push_back(v);
  row.insert(row.end(), {report.total, report.lr, report.gradNorm, report.ms});
  log_->append(row);
  return report;
}

std::string Trainer::saveCheckpoint() {
  CheckpointData c;
  c.step = step_;
  c.random = sampler_->random().state();
  c.adam = adam_->exportState();
  c.configJson = toJson(config_);
  if (average_)
    c.average = average_->values();
  return writeCheckpoint(options_.runDir, network_->parameters(), c);
}

Trainer::RunResult Trainer::run() {
  RunResult result;
  int64_t saved = step_ == startStep_ && step_ > 0 ? step_ : -1;
  int64_t done = 0;
  auto stop = [&] { return options_.stopRequested && options_.stopRequested(); };
  while (step_ < totalSteps_) {
    if (stop()) {
      result.interrupted = true;
      break;
    }
    const StepReport r = trainStep();
    if (options_.onStep)
      options_.onStep(r);
    if (options_.crashAfterSteps >= 0 && ++done >= options_.crashAfterSteps) {
      result.steps = step_;
      result.interrupted = true;
      return result; // a simulated kill: no checkpoint
    }
    if (step_ % checkpointEvery_ == 0) {
      saveCheckpoint();
      saved = step_;
    }
  }
  if (saved != step_) {
    const std::string dir = saveCheckpoint();
    if (options_.message)
      options_.message("checkpoint " + dir);
  }
  result.steps = step_;
  return result;
}

} // namespace simpli::training

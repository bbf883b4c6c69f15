// The training loop (trainer.h).
#include "simpli/model/training/trainer.h"
#include "simpli/model/network/loader.h"
#include "simpli/model/network/widen.h"

#include "simpli/error.h"
#include "simpli/model/io/files.h"
#include "simpli/model/training/checkpoint.h"
#include "simpli/model/training/losses.h"
#include "simpli/warning.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_shape.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

namespace simpli::training {
namespace {
namespace fs = std::filesystem;

// The loss terms in log.csv: the reference's always; the terms not in the reference (depth,
// mpi_depth, ssim) only when they are on, so that the logs of runs without them keep their
// columns (and resume).
std::vector<std::string> loggedTerms(const TrainingConfig& config) {
  std::vector<std::string> terms;
  for (const std::string& t : lossTermNames())
    if ((t != "depth" && t != "mpi_depth" && t != "ssim") || config.weight(t) > 0)
      terms.push_back(t);
  return terms;
}

std::vector<std::string> logColumns(const TrainingConfig& config) {
  std::vector<std::string> c{"step"};
  for (const std::string& t : loggedTerms(config))
    c.push_back(t);
  for (const char* extra : {"total", "lr", "grad_norm", "step_ms"})
    c.emplace_back(extra);
  return c;
}
} // namespace

ocl::Tensor inverseDepthTensor(const std::vector<std::vector<float>>& depths, int width, int height,
                               ocl::Dtype dtype) {
  std::vector<double> values;
  values.reserve(depths.size() * size_t(width) * size_t(height));
  for (const std::vector<float>& d : depths) {
    if (d.size() != size_t(width) * size_t(height))
      fail("inverseDepthTensor: ", d.size(), " depths for a ", width, "x", height, " view");
    for (float z : d)
      values.push_back(z > 0 && std::isfinite(z) ? 1.0 / z : 0.0);
  }
  return ocl::Tensor::fromHost(values, {int64_t(depths.size()), 1, height, width}, dtype);
}

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

std::vector<TrainRandom::State> sampleStreams(uint64_t seed, int count) {
  if (count < 1)
    fail("sampleStreams: ", count, " streams");
  std::vector<TrainRandom::State> streams;
  TrainRandom r(samplerSeed(seed));
  for (int s = 0; s < count; ++s) {
    if (s > 0)
      r.jump();
    streams.push_back(r.state());
  }
  return streams;
}

network::SimpliNetwork& Trainer::validationNetwork() {
  if (!average_)
    return *network_;
  if (!averaged_)
    averaged_ = std::make_unique<network::SimpliNetwork>(config_.network, config_.dtype, 0);
  average_->copyTo(averaged_->parameters());
  return *averaged_;
}

void Trainer::say(const std::string& message) const {
  if (options_.message && comm_->isRoot())
    options_.message(message);
}

std::optional<std::string> Trainer::openRunFolder(const TrainingConfig* config) {
  const fs::path run(options_.runDir);
  const std::string configPath = (run / "config.json").string();
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
    return latestCheckpoint(options_.runDir);
  }
  if (!config)
    fail("trainer: a new run needs a training config");
  config_ = *config;
  if (options_.seed)
    config_.seed = *options_.seed;
  std::error_code ec;
  if (fs::exists(run) && !fs::is_empty(run, ec))
    fail("run folder '", options_.runDir,
         "' already exists and is not empty; use --resume to continue it");
  return std::nullopt;
}

Trainer::Trainer(const TrainingConfig* config, const TrainerOptions& options) : options_(options) {
  comm_ = options_.communicator ? options_.communicator : &parallel::world();
  if (options_.runDir.empty())
    fail("trainer: no run folder given");
  if (options_.samplesPerRank < 1)
    fail("trainer: samples per rank ", options_.samplesPerRank, ": must be >= 1");
  const bool root = comm_->isRoot();
  const fs::path run(options_.runDir);
  const std::string configPath = (run / "config.json").string();
  std::optional<std::string> checkpoint;
  if (root)
    checkpoint = openRunFolder(config);
  shareConfig();
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
    if (root) { // the other ranks receive rank 0's weights
      // Weights of the same network without the level-0 photo prior (their metadata says so):
      // the prior's input channel starts at zero weight.
      const std::optional<network::NetworkConfig> stored =
          network::configFromWeights(options_.initWeights);
      const bool addPrior = config_.network.lvl0PhotoPrior && stored && !stored->lvl0PhotoPrior;
      network::LoadReport r;
      try {
        r = addPrior ? network::loadWithoutLvl0Prior(*network_, options_.initWeights)
                     : network_->parameters().load(options_.initWeights);
      } catch (const Error& e) {
        // Name both networks: the usual cause is weights of another config (e.g. the shipped
        // tiny-prior weights for a tiny recipe).
        if (stored && stored->name != config_.network.name)
          fail("--init-weights '", options_.initWeights, "' holds a network of config '",
               stored->name, "', the training config's network is '", config_.network.name, "' (",
               e.what(), ")");
        throw;
      }
      say("initial weights: " + options_.initWeights + " (" + std::to_string(r.loaded) +
          " tensors" +
          (r.unexpected.empty() ? std::string()
                                : ", " + std::to_string(r.unexpected.size()) + " unused") +
          (addPrior ? "; the level-0 photo prior's input starts at zero weight" : "") + ")");
    }
  }
  generator_ = std::make_unique<generator::Generator>(*network_);
  const OptimizerConfig& o = config_.optimizer;
  adam_ = std::make_unique<ocl::Adam>(network_->parameters().parameters(), o.lr, o.beta1, o.beta2,
                                      o.eps);
  schedule_ = std::make_unique<ocl::ExponentialLr>(o.lr, o.gamma, o.warmupSteps);
  const int streams = samplesPerStep();
  for (int j = 0; j < options_.samplesPerRank; ++j)
    samplers_.emplace_back(config_.sampling, samplerSeed(config_.seed));
  if (streams > 1)
    exchange_ = std::make_unique<GradientExchange>(adam_->parameters(), lossTermNames().size() + 2);
  if (config_.emaDecay > 0 && root)
    average_ = std::make_unique<ParameterAverage>(network_->parameters(), config_.emaDecay);

  std::vector<TrainRandom::State> streamStates;
  if (root) {
    if (!options_.resume) {
      std::error_code ec;
      fs::create_directories(run, ec);
      if (ec)
        fail("cannot create run folder '", options_.runDir, "': ", ec.message());
      const std::string text = toJson(config_);
      io::writeFileAtomically(configPath, text.data(), text.size());
    }
    streamStates = sampleStreams(config_.seed, streams);
    if (checkpoint) {
      CheckpointData c = readCheckpoint(*checkpoint, network_->parameters());
      adam_->importState(c.adam);
      resumeStreams(c, streamStates);
      if (average_ && c.average.empty()) {
        // ema_decay was turned on in the run's config.json after this checkpoint: the average
        // starts at the checkpoint's weights, as a new run's starts at its initial ones.
        average_ = std::make_unique<ParameterAverage>(network_->parameters(), config_.emaDecay);
        say("moving average (ema_decay " + std::to_string(config_.emaDecay) + "): " + *checkpoint +
            " has none; it starts at the checkpoint's weights");
      } else if (average_) {
        average_->setValues(c.average, *checkpoint + "/weights_ema.safetensors");
      }
      step_ = c.step;
      say("resumed from " + *checkpoint + " at step " + std::to_string(step_));
    } else if (options_.resume) {
      say("no checkpoint in " + options_.runDir + "; starting at step 0");
    }
  }
  shareStartState(streamStates);
  startStep_ = step_;
  if (root)
    log_ = std::make_unique<TrainLog>((run / "log.csv").string(), logColumns(config_),
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
  if (streams > 1)
    say("data-parallel: " + std::to_string(comm_->size()) + " rank(s) x " +
        std::to_string(options_.samplesPerRank) + " sample(s) per step (" + comm_->describe() +
        "); one all-reduce of " + std::to_string(exchange_->bytes()) + " bytes per step");
}

Trainer::~Trainer() = default;

Trainer::SampleLoss Trainer::sampleLoss(Sampler& sampler) {
  const ocl::Dtype dtype = config_.dtype;
  const TrainingSample s = sampler.draw(*data_);
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
  go.fusedAggregation = options_.fusedAggregation;
  go.raster.maxFragments = config_.maxFragments;
  const generator::GeneratorOutput out = generator_->forward(in, go);
  std::vector<ocl::Tensor> colours, opacities, depths;
  for (const scene::Camera& target : s.targetCameras) {
    const raster::RenderedLayers r =
        generator::renderNovelView(out, s.reference, target, go.raster);
    colours.push_back(ocl::unsqueeze(r.colour, 0));
    opacities.push_back(ocl::unsqueeze(r.opacity, 0));
    depths.push_back(ocl::unsqueeze(r.depth, 0));
  }
  ocl::Tensor inverseDepth; // only when the depth term is on and the data knows the depth
  if (config_.weight("depth") > 0 && !s.targetDepths.empty())
    inverseDepth =
        inverseDepthTensor(s.targetDepths, s.targets[0].width, s.targets[0].height, dtype);
  std::unique_ptr<PlaneTargets> planes; // likewise for the level-0 plane term
  if (config_.weight("mpi_depth") > 0 && !s.sourceDepths.empty()) {
    const ocl::Tensor& w = out.level0SourceWeights;
    planes = std::make_unique<PlaneTargets>(planeTargets(
        out.planeDepths, s.reference, s.sourceCameras, s.sourceDepths, s.cleanSources[0].width,
        s.cleanSources[0].height, int(w.size(3)), int(w.size(4))));
  }
  const ocl::Tensor novelOpacity = ocl::concat(opacities, 0);
  const LossTerms losses = computeLosses(
      config_, out, ocl::concat(colours, 0), novelOpacity, targets, clean,
      vgg_.loaded() ? &vgg_ : nullptr,
      inverseDepth.defined() ? ocl::concat(depths, 0) : ocl::Tensor(), inverseDepth, planes.get());
  SampleLoss result;
  result.total = losses.total.item();
  if (losses.total.hasGradFn())
    losses.total.backward();
  for (const std::string& t : lossTermNames())
    result.terms.push_back(losses.value(t));
  return result;
}

StepReport Trainer::trainStep() {
  using Clock = std::chrono::steady_clock;
  auto msSince = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  const auto t0 = Clock::now();
  const std::vector<ocl::Tensor>& params = adam_->parameters();
  const std::vector<std::string>& names = lossTermNames();
  StepReport report;
  report.samples = samplesPerStep();
  std::vector<double> terms;
  if (!exchange_) {
    const SampleLoss l = sampleLoss(samplers_[0]);
    report.total = l.total;
    terms = l.terms;
  } else {
    // Scalars: the loss terms, the total, and (several ranks) this rank's stop request, which
    // the sum turns into "some rank asked".
    const bool ranks = comm_->size() > 1;
    const bool stop = ranks && options_.stopRequested && options_.stopRequested();
    double exchangeMs = 0;
    for (size_t j = 0; j < samplers_.size(); ++j) {
      SampleLoss l = sampleLoss(samplers_[j]);
      l.terms.push_back(l.total);
      l.terms.push_back(j == 0 && stop ? 1.0 : 0.0);
      const auto te = Clock::now();
      exchange_->add(params, l.terms);
      exchangeMs += msSince(te);
    }
    const auto te = Clock::now();
    exchange_->reduce(*comm_);
    report.allreduceMs = msSince(te);
    std::vector<double> sums = exchange_->scalars();
    exchange_->applyMean(params, report.samples);
    report.exchangeMs = exchangeMs + msSince(te);
    report.stopAgreed = sums.back() > 0;
    sums.pop_back();
    report.total = sums.back() / report.samples;
    sums.pop_back();
    for (double v : sums)
      terms.push_back(v / report.samples);
  }
  report.gradNorm = ocl::clipGradNorm(params, config_.optimizer.clipGradNorm);
  report.lr = schedule_->lrAt(step_);
  if (std::isfinite(report.gradNorm) && std::isfinite(report.total)) {
    adam_->setLr(report.lr);
    adam_->step();
  } else {
    report.skipped = true;
    say("step " + std::to_string(step_ + 1) + ": non-finite loss or gradient; no update made");
  }
  if (average_)
    average_->update(network_->parameters());
  ++step_;
  for (size_t i = 0; i < names.size(); ++i)
    report.terms.emplace_back(names[i], terms[i]);
  ocl::Device::current().finish();
  report.ms = msSince(t0);
  report.step = step_;

  if (log_) {
    const std::vector<std::string> logged = loggedTerms(config_);
    std::vector<double> row{double(step_)};
    for (const auto& [name, v] : report.terms)
      if (std::find(logged.begin(), logged.end(), name) != logged.end())
        row.push_back(v);
    row.insert(row.end(), {report.total, report.lr, report.gradNorm, report.ms});
    log_->append(row);
  }
  return report;
}

std::string Trainer::saveCheckpoint() {
  const std::vector<TrainRandom::State> streams = gatherStreams();
  if (!comm_->isRoot())
    return checkpointDir(options_.runDir, step_);
  CheckpointData c;
  c.step = step_;
  c.random = streams.at(0);
  if (streams.size() > 1)
    c.streams = streams;
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
    // One rank polls here; several agree on a stop in the step's all-reduce (trainStep).
    if (comm_->size() == 1 && stop()) {
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
    if (r.stopAgreed) {
      result.interrupted = step_ < totalSteps_;
      break; // the checkpoint below
    }
    if (step_ % checkpointEvery_ == 0) {
      saveCheckpoint();
      saved = step_;
      if (options_.onCheckpoint)
        options_.onCheckpoint(step_);
    }
  }
  if (saved != step_) {
    const std::string dir = saveCheckpoint();
    say("checkpoint " + dir);
    if (options_.onCheckpoint)
      options_.onCheckpoint(step_);
  }
  result.steps = step_;
  return result;
}

} // namespace simpli::training

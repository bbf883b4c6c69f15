#pragma once
// The training loop (spec §8.2): per step one sample (training/sampler.h), the
// generator's forward pass with the intermediate source renders, the novel views rendered with
// the final layers, the losses (training/losses.h), backward, global gradient-norm clipping,
// Adam with lr0 * gamma^step, the weights' moving average when ema_decay > 0
// (training/average.h), a CSV row (training/log.h) and, every checkpoint_every steps and when
// stopping early, an atomic checkpoint (training/checkpoint.h).
//
// Run folder: a new run needs a folder that does not exist or is empty; --resume continues the
// run in it from its newest checkpoint (or from step 0 when it has none) with the run's own
// config.json. A resumed run repeats exactly the computation of an uninterrupted one: the
// weights, Adam moments and step counts, the LR step and the sampler's random state are all
// restored, and nothing else carries state between steps. (Whether the float results are then
// bit-identical depends on the device: see tests/model/training/test_train_resume.cpp.)
#include "simpli/model/generator/generator.h"
#include "simpli/model/network/network.h"
#include "simpli/model/training/average.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/data.h"
#include "simpli/model/training/log.h"
#include "simpli/model/training/sampler.h"
#include "simpli/model/training/vgg.h"

#include "simpli/ocl/optim.h"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace simpli::training {

struct StepReport {
  int64_t step = 0; ///< 1-based: the number of optimiser steps done after this one
  std::vector<std::pair<std::string, double>> terms; ///< every lossTermNames() term (NaN: off)
  double total = 0, lr = 0, gradNorm = 0, ms = 0;
  bool skipped = false; ///< non-finite gradients: no update was made
};

struct TrainerOptions {
  std::string data;   ///< scene folder(s) or "synthetic[:seed]"
  std::string runDir; ///< the run folder
  bool resume = false;
  int64_t steps = -1;           ///< total steps of the run; -1 = the config's
  int64_t checkpointEvery = -1; ///< -1 = the config's
  std::string vggPath;          ///< VGG-19 weights for the perceptual loss; empty = off
  /// A new run starts from these weights (safetensors, every parameter of the config's
  /// network) instead of a random initialisation; empty = random. Not with `resume`.
  std::string initWeights;
  DataOptions dataOptions;
  std::optional<uint64_t> seed; ///< overrides the config's seed (a new run only)
  /// Polled between steps; true stops the run after a checkpoint.
  std::function<bool()> stopRequested;
  std::function<void(const StepReport&)> onStep;
  /// After every checkpoint, with the step it holds (validation, progress pictures).
  std::function<void(int64_t step)> onCheckpoint;
  std::function<void(const std::string&)> message; ///< informational lines
  /// Testing: after this many steps of this process the loop stops without a checkpoint
  /// (simulates a kill); -1 = never.
  int64_t crashAfterSteps = -1;
};

class Trainer {
public:
  /// Sets up (or resumes) the run. `config` may be null when resuming (the run's config.json
  /// is used; when given it must agree with it except for steps / checkpoint_every).
  Trainer(const TrainingConfig* config, const TrainerOptions& options);
  ~Trainer();

  int64_t step() const { return step_; }
  int64_t totalSteps() const { return totalSteps_; }
  int64_t startStep() const { return startStep_; }
  const TrainingConfig& config() const { return config_; }
  network::SimpliNetwork& network() { return *network_; }
  /// The weights' moving average; null when ema_decay is 0.
  const ParameterAverage* average() const { return average_.get(); }
  const std::string& runDir() const { return options_.runDir; }

  /// One optimiser step on a freshly drawn sample.
  StepReport trainStep();
  /// Writes a checkpoint of the current state; returns its folder.
  std::string saveCheckpoint();

  struct RunResult {
    int64_t steps = 0;        ///< step counter at the end
    bool interrupted = false; ///< stopped by stopRequested before totalSteps
  };
  /// Trains up to totalSteps(), checkpointing every checkpoint_every steps, on stop and at the
  /// end.
  RunResult run();

private:
  TrainingConfig config_;
  TrainerOptions options_;
  std::unique_ptr<TrainingData> data_;
  std::unique_ptr<network::SimpliNetwork> network_;
  std::unique_ptr<generator::Generator> generator_;
  std::unique_ptr<ocl::Adam> adam_;
  std::unique_ptr<ocl::ExponentialLr> schedule_;
  std::unique_ptr<Sampler> sampler_;
  std::unique_ptr<ParameterAverage> average_;
  std::unique_ptr<TrainLog> log_;
  Vgg19Features vgg_;
  int64_t step_ = 0, startStep_ = 0, totalSteps_ = 0, checkpointEvery_ = 1;
};

/// Images [-1, 1] -> one tensor [n, 3, H, W] in `dtype`.
ocl::Tensor imagesToTensor(const std::vector<io::Image>& images, ocl::Dtype dtype);

/// Depth maps (height x width camera z, 0 = no surface) -> [n, 1, H, W] of 1 / z (0 where no
/// surface), the form depthLoss takes.
ocl::Tensor inverseDepthTensor(const std::vector<std::vector<float>>& depths, int width, int height,
                               ocl::Dtype dtype);

/// The sampler seed of a run seeded with `seed` (distinct from the network's initialisation).
uint64_t samplerSeed(uint64_t seed);

} // namespace simpli::training

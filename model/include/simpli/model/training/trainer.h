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
// bit-identical depends on the device: see tests/model/training/test_trainer.cpp.)
//
// Data-parallel (docs/parallel.md): with K ranks (parallel/communicator.h, e.g. `mpiexec -n K
// simpli train`) and L samples per rank, every step draws K x L samples from K x L sample
// streams, stream s = rank * L + j being the sampler seed's random state jumped s times
// (TrainRandom::jump, 2^128 draws apart: streams never overlap; stream 0 is the one stream of a
// plain run, so K = L = 1 is exactly the serial trainer). Each rank runs its L samples' forward
// and backward passes, their gradients (with the loss terms and the stop flag) are summed in one
// all-reduce (training/gradient_exchange.h) and divided by K x L, and every rank then makes the
// same clipped Adam step. So K ranks with L = 1 equal one rank with L = K, up to the order of the
// MPI library's additions (exactly with two ranks and a deterministic device). Rank 0 alone owns
// the run folder: it checks and creates it, reads config.json and the checkpoint, writes the log
// and the checkpoints; the config, the weights, the Adam state and the streams' states go from
// it to the other ranks at the start. A stop request (stopRequested on any rank) is agreed in
// the step's all-reduce: that step completes on every rank, then all stop after one checkpoint.
#include "simpli/model/generator/generator.h"
#include "simpli/model/network/network.h"
#include "simpli/model/parallel/communicator.h"
#include "simpli/model/training/average.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/data.h"
#include "simpli/model/training/gradient_exchange.h"
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

struct CheckpointData;

struct StepReport {
  int64_t step = 0; ///< 1-based: the number of optimiser steps done after this one
  std::vector<std::pair<std::string, double>> terms; ///< every lossTermNames() term (NaN: off)
  double total = 0, lr = 0, gradNorm = 0, ms = 0;
  bool skipped = false; ///< non-finite gradients: no update was made
  int samples = 1;      ///< samples averaged in this step (ranks x samples per rank)
  /// With more than one sample: the all-reduce (which includes waiting for the slowest rank)
  /// and the whole exchange (gradient downloads, all-reduce, uploads), ms.
  double allreduceMs = 0, exchangeMs = 0;
  bool stopAgreed = false; ///< several ranks: some rank asked to stop during this step
};

struct TrainerOptions {
  /// Scene folder(s), "synthetic[:seed]", or several of them mixed by weight (data.h).
  std::vector<DataSource> data;
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
  /// Polled between steps (one rank) or at each step's all-reduce (several ranks, agreed);
  /// true stops the run after a checkpoint.
  std::function<bool()> stopRequested;
  std::function<void(const StepReport&)> onStep;
  /// After every checkpoint, with the step it holds (validation, progress pictures).
  std::function<void(int64_t step)> onCheckpoint;
  std::function<void(const std::string&)> message; ///< informational lines
  /// Testing: after this many steps of this process the loop stops without a checkpoint
  /// (simulates a kill); -1 = never.
  int64_t crashAfterSteps = -1;
  /// The ranks that train together; null = parallel::world(). Every rank constructs its
  /// Trainer with the same options and calls run() (or the same trainStep / saveCheckpoint
  /// sequence): they are collective.
  parallel::Communicator* communicator = nullptr;
  /// Samples each rank draws and averages per step (gradient accumulation), >= 1.
  int samplesPerRank = 1;
  /// The generator's fused view aggregation, forward and backward
  /// (GeneratorOptions::fusedAggregation); false = the composed ops, the baseline of
  /// `simpli bench train --baseline composed`.
  bool fusedAggregation = true;
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
  /// The network validation scores: with a moving average (ema_decay > 0, rank 0) a second
  /// network holding the average's current values (refreshed on every call), else network().
  network::SimpliNetwork& validationNetwork();
  /// The weights' moving average; null when ema_decay is 0, and on ranks other than 0.
  const ParameterAverage* average() const { return average_.get(); }
  /// Samples averaged per step: ranks x samples per rank (= sample streams).
  int samplesPerStep() const { return comm_->size() * options_.samplesPerRank; }
  parallel::Communicator& communicator() const { return *comm_; }
  const std::string& runDir() const { return options_.runDir; }

  /// One optimiser step on freshly drawn samples (collective).
  StepReport trainStep();
  /// Writes a checkpoint of the current state (collective: rank 0 writes it with every rank's
  /// stream states); returns its folder.
  std::string saveCheckpoint();

  struct RunResult {
    int64_t steps = 0;        ///< step counter at the end
    bool interrupted = false; ///< stopped by stopRequested before totalSteps
  };
  /// Trains up to totalSteps(), checkpointing every checkpoint_every steps, on stop and at the
  /// end.
  RunResult run();

private:
  /// Rank 0: the run's config and folder (checked, created); returns the checkpoint to resume.
  std::optional<std::string> openRunFolder(const TrainingConfig* config);
  /// Rank 0's config on every rank (trainer_ranks.cpp).
  void shareConfig();
  /// Rank 0's weights, Adam state, step and every stream's state on every rank; each keeps its
  /// own streams (trainer_ranks.cpp).
  void shareStartState(const std::vector<TrainRandom::State>& streams);
  /// Every rank's stream states on rank 0, in stream order (trainer_ranks.cpp).
  std::vector<TrainRandom::State> gatherStreams();
  /// The checkpoint's stream states into `streams` (this run's fresh ones); says what happens
  /// when the checkpoint has another number of streams (trainer_ranks.cpp).
  void resumeStreams(const CheckpointData& checkpoint, std::vector<TrainRandom::State>& streams);
  /// The loss terms of one sample, its backward pass done (gradients accumulated).
  struct SampleLoss {
    std::vector<double> terms; ///< lossTermNames() order, NaN = off
    double total = 0;
  };
  SampleLoss sampleLoss(Sampler& sampler);
  void say(const std::string& message) const;

  parallel::Communicator* comm_ = nullptr;
  TrainingConfig config_;
  TrainerOptions options_;
  std::unique_ptr<TrainingData> data_;
  std::unique_ptr<network::SimpliNetwork> network_;
  std::unique_ptr<network::SimpliNetwork> averaged_; ///< validationNetwork()'s, made on first use
  std::unique_ptr<generator::Generator> generator_;
  std::unique_ptr<ocl::Adam> adam_;
  std::unique_ptr<ocl::ExponentialLr> schedule_;
  std::vector<Sampler> samplers_;              ///< this rank's streams rank * L .. rank * L + L - 1
  std::unique_ptr<GradientExchange> exchange_; ///< with more than one sample per step
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

/// The initial states of sample streams 0 .. count - 1 of a run seeded with `seed`: stream 0 is
/// TrainRandom(samplerSeed(seed)), stream s is it jumped s times.
std::vector<TrainRandom::State> sampleStreams(uint64_t seed, int count);

} // namespace simpli::training

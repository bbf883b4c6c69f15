#pragma once
// What a training run shows while it runs (issue 10): RUN/progress.png, the loss curve (every
// step's total loss and its moving average) and, with a validation scene, the validation PSNR
// against the nearest-source-view baseline; RUN/val.csv with the scores; and
// RUN/validation/step_NNNNNNNN.png, ground truth | render | error x4 | nearest source view of
// the first validation view; RUN/best.safetensors, the weights of the best validation so far
// (a run's validation score peaks and drifts, and checkpoints keep only the last steps).
// Validation uses the protocol of training/eval.h on fixed samples
// (the same sources and targets every time, so the curve shows the network, not the draw).
#include "simpli/model/network/network.h"
#include "simpli/model/training/data.h"
#include "simpli/model/training/log.h"

#include <cstdint>
#include <memory>
#include <string>

namespace simpli::training {

struct ValidationOptions {
  std::string scene;   ///< a scene folder; empty = no validation (loss curve only)
  int64_t every = 100; ///< steps between validations (checked at checkpoints)
  int width = 256, height = 192;
  int views = 5, novelViews = 2, repeats = 1;
  uint64_t seed = 0;
};

struct ValidationScore {
  int64_t step = 0;
  double psnr = 0, ssim = 0, nearestPsnr = 0, nearestSsim = 0;
  bool best = false; ///< the highest PSNR of the run so far: its weights are in bestWeightsPath()
};

class TrainingMonitor {
public:
  /// Opens the validation scene (throws simpli::Error naming it when it is unreadable or has
  /// too few views), before the run folder exists, so that a bad scene leaves nothing behind.
  TrainingMonitor(std::string runDir, ValidationOptions options);
  ~TrainingMonitor();

  /// Once the run folder exists: opens val.csv; a resumed run (resumeStep >= 0) keeps it up to
  /// that step, and knows its best score from best.safetensors' step and that step's row.
  /// Validations widen the reference camera by `referenceMargin` (the run's
  /// sampling.reference_margin): the network is scored the way it is trained.
  void begin(int64_t resumeStep, double referenceMargin = 0.0);

  /// Called after the checkpoint of `step`: validates when `every` steps have passed since the
  /// last validation (or `force`), then redraws progress.png. Returns the new score, if any.
  std::unique_ptr<ValidationScore> update(network::SimpliNetwork& network, int64_t step,
                                          bool force = false);

  /// The step of the last validation (-1: none yet in this process or the resumed run).
  int64_t lastValidated() const { return lastValidated_; }
  bool validating() const { return log_ != nullptr; }

  /// RUN/best.safetensors: weights with "step" and "network_config" metadata, like a
  /// checkpoint's, so that `simpli eval --weights` and `simpli infer --weights` take them.
  static std::string bestWeightsPath(const std::string& runDir);

  /// Writes RUN/progress.png from RUN/log.csv and RUN/val.csv (also usable on a finished run).
  static void drawProgress(const std::string& runDir);

private:
  std::string runDir_;
  ValidationOptions options_;
  std::unique_ptr<TrainingData> data_;
  std::unique_ptr<TrainLog> log_;
  int64_t lastValidated_ = -1;
  double referenceMargin_ = 0.0; ///< begin()'s
  std::unique_ptr<ValidationScore> best_;
};

} // namespace simpli::training

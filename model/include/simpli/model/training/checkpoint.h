#pragma once
// Training checkpoints. A run folder holds
//   config.json                 the training config (self-contained)
//   log.csv                     per-step log (training/log.h)
//   weights.safetensors         the latest checkpoint's network parameters (reference key
//                               names; what `simpli infer --weights` loads)
//   weights_ema.safetensors     their moving average (with ema_decay > 0; also loadable)
//   checkpoints/step_NNNNNNNN/  one folder per checkpoint:
//       weights.safetensors     network parameters
//       optimizer.safetensors   Adam moments "m.<param>" / "v.<param>" (F64, exact copies)
//       weights_ema.safetensors the weights' moving average (F64; with ema_decay > 0 only)
//       state.json              step, Adam step counts, sampler random state(s), the config
// A checkpoint folder is written completely under checkpoints/.tmp-step_NNNNNNNN-<pid> and then
// renamed into place: the rename is the commit, so a crash at any point leaves every
// step_NNNNNNNN folder complete. The newest complete folder is the one a resume uses; after a
// successful write older ones beyond `keep` and stale temporaries are removed (the previous
// good checkpoint is never removed before the new one is committed).
#include "simpli/model/io/safetensors.h"
#include "simpli/model/network/parameter_store.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/random.h"

#include "simpli/ocl/optim.h"

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace simpli::training {

struct CheckpointData {
  int64_t step = 0;            ///< optimiser steps done (= the LR schedule's step)
  TrainRandom::State random{}; ///< the sampler's state after those steps (stream 0)
  /// Data-parallel runs: every sample stream's state, in stream order (streams[0] == random);
  /// empty for a run with one stream. state.json field "sample_streams".
  std::vector<TrainRandom::State> streams;
  ocl::Adam::State adam;
  std::string configJson; ///< toJson(config) of the run
  /// The weights' moving average by parameter name (training/average.h); empty = none.
  std::map<std::string, io::HostTensor<double>> average;
};

struct CheckpointWriteOptions {
  int keep = 2; ///< complete checkpoints kept (>= 1)
  /// Testing: throw simpli::Error after this many files of the new checkpoint were written
  /// (simulates a crash mid-write); -1 = never.
  int failAfterFiles = -1;
};

/// The metadata every weights file of a run carries (a checkpoint's, best.safetensors): "format"
/// "simpli-weights", "step", and "network_config" (the network section's JSON, omitted when
/// empty) so that `simpli infer --weights` needs no --config.
std::map<std::string, std::string> weightsMetadata(int64_t step,
                                                   const std::string& networkConfigJson);

/// checkpoints/step_NNNNNNNN under `runDir`.
std::string checkpointDir(const std::string& runDir, int64_t step);

/// Writes a checkpoint of `store` and `data` (see the header comment); returns its folder.
std::string writeCheckpoint(const std::string& runDir, const network::ParameterStore& store,
                            const CheckpointData& data, const CheckpointWriteOptions& options = {});

/// The newest complete checkpoint folder of a run, if any.
std::optional<std::string> latestCheckpoint(const std::string& runDir);

/// Reads a checkpoint folder: loads the weights into `store` (every parameter must be present
/// with its shape) and returns the rest; the Adam state is matched to the store's parameter
/// order by name; the moving average is read when the folder has one. Throws simpli::Error
/// naming the file and field on any problem.
CheckpointData readCheckpoint(const std::string& dir, network::ParameterStore& store);

} // namespace simpli::training

#pragma once
// Weights a run keeps for good: RUN/kept/step_NNNNNNNN.safetensors, the network's weights (the
// moving average when the run keeps one) at every N-th step (`simpli train --keep-weights-every
// N`). Checkpoints keep only a run's last steps and best.safetensors only its best validation,
// but comparing runs at equal steps (the A/B runs of issue 10) needs the weights of chosen steps
// long after they passed; kept inside the run folder, they travel with it.
#include "simpli/model/network/network.h"

#include <cstdint>
#include <string>

namespace simpli::training {

class WeightSnapshots {
public:
  /// `every` steps between kept weights (0 = none); a resumed run passes its start step, so
  /// that the multiple it already kept is not kept again.
  WeightSnapshots(std::string runDir, int64_t every, int64_t startStep);

  /// Whether the checkpoint of `step` keeps its weights: `step` reached a multiple of `every`
  /// that no kept step reached (the first checkpoint at or after each multiple keeps them).
  bool due(int64_t step) const;

  /// Writes `network`'s weights as those of `step` (atomically) and returns the file.
  std::string keep(const network::SimpliNetwork& network, int64_t step);

  /// RUN/kept/step_NNNNNNNN.safetensors.
  static std::string path(const std::string& runDir, int64_t step);

private:
  std::string runDir_;
  int64_t every_ = 0;
  int64_t lastMultiple_ = 0; ///< step / every of the last kept (or start) step
};

} // namespace simpli::training

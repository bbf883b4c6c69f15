#pragma once
// Optimisers and learning-rate schedules for training (reference §8.2: Adam, betas 0.9/0.999,
// eps 1e-8, ExponentialLR stepped every iteration).
#include "simpli/ocl/tensor.h"

#include <cstdint>
#include <vector>

namespace simpli::ocl {

/// Adam / AdamW with PyTorch's update (torch.optim.Adam / AdamW, amsgrad off):
///   t += 1;  Adam: g += weightDecay * p;  AdamW (decoupled): p *= 1 - lr * weightDecay;
///   m = lerp(m, g, 1 - beta1);  v = beta2 * v + (1 - beta2) * g^2;
///   p -= lr / (1 - beta1^t) * m / (sqrt(v) / sqrt(1 - beta2^t) + eps).
/// One fused kernel per parameter. Like PyTorch, a parameter without a gradient is skipped and
/// keeps its own step count; its moments are created at its first step.
class Adam {
public:
  /// Moments and step count of one parameter; m and v are empty before its first step.
  struct ParamState {
    int64_t step = 0;
    std::vector<double> m, v;
  };
  /// Everything needed to resume bit-for-bit (values are exact copies: float -> double -> float
  /// round-trips exactly).
  struct State {
    int64_t steps = 0; ///< calls of step()
    std::vector<ParamState> params;
  };

  Adam(std::vector<Tensor> parameters, double lr, double beta1 = 0.9, double beta2 = 0.999,
       double eps = 1e-8, double weightDecay = 0.0, bool decoupled = false);

  /// One update of every parameter that has a gradient.
  void step();
  /// Zeroes every parameter's gradient (kept allocated).
  void zeroGrad();

  double lr() const { return lr_; }
  void setLr(double lr);
  /// Number of step() calls so far (restored by importState).
  int64_t steps() const { return steps_; }
  const std::vector<Tensor>& parameters() const { return params_; }

  State exportState() const;
  /// Throws simpli::Error naming the parameter index and sizes when the state does not fit.
  void importState(const State& state);

private:
  std::vector<Tensor> params_;
  std::vector<Tensor> m_, v_; ///< undefined until the parameter's first step
  std::vector<int64_t> paramSteps_;
  double lr_, beta1_, beta2_, eps_, weightDecay_;
  bool decoupled_;
  int64_t steps_ = 0;
};

/// A learning rate as a function of the iteration (0 = the first optimiser step).
class LrSchedule {
public:
  virtual ~LrSchedule() = default;
  /// Throws simpli::Error for a negative step.
  virtual double lrAt(int64_t step) const = 0;
};

class ConstantLr : public LrSchedule {
public:
  explicit ConstantLr(double lr);
  double lrAt(int64_t step) const override;

private:
  double lr_;
};

/// lr0 * gamma^step: PyTorch's ExponentialLR stepped after every iteration (the reference
/// uses gamma = 0.999994 on lr0 = 3e-4).
class ExponentialLr : public LrSchedule {
public:
  /// lr0 * gamma^step, times (step + 1) / warmupSteps for step < warmupSteps (a linear warm-up:
  /// Adam's first updates, before its moment estimates settle, are ~lr per weight whatever the
  /// gradient, which shakes a network warm-started from trained weights).
  ExponentialLr(double lr0, double gamma, int64_t warmupSteps = 0);
  double lrAt(int64_t step) const override;

private:
  double lr0_, gamma_;
  int64_t warmup_;
};

/// Linear warm-up lrMax * (step + 1) / warmupSteps for step < warmupSteps, then cosine
/// annealing from lrMax to lrMin over the remaining totalSteps - warmupSteps steps
/// (PyTorch's CosineAnnealingLR with T_max = totalSteps - warmupSteps), lrMin afterwards.
class CosineLr : public LrSchedule {
public:
  CosineLr(double lrMax, int64_t totalSteps, double lrMin = 0.0, int64_t warmupSteps = 0);
  double lrAt(int64_t step) const override;

private:
  double lrMax_, lrMin_;
  int64_t total_, warmup_;
};

} // namespace simpli::ocl

#include "simpli/error.h"
#include "simpli/ocl/optim.h"

#include <cmath>

namespace simpli::ocl {
namespace {
void checkStep(const char* schedule, int64_t step) {
  if (step < 0)
    fail(schedule, ": step ", step, " is negative");
}
} // namespace

ConstantLr::ConstantLr(double lr) : lr_(lr) {
  if (!(lr >= 0.0))
    fail("ConstantLr: learning rate ", lr, " must be >= 0");
}

double ConstantLr::lrAt(int64_t step) const {
  checkStep("ConstantLr", step);
  return lr_;
}

ExponentialLr::ExponentialLr(double lr0, double gamma, int64_t warmupSteps)
    : lr0_(lr0), gamma_(gamma), warmup_(warmupSteps) {
  if (!(lr0 >= 0.0))
    fail("ExponentialLr: learning rate ", lr0, " must be >= 0");
  if (!(gamma > 0.0 && gamma <= 1.0))
    fail("ExponentialLr: gamma ", gamma, " must be in (0, 1]");
  if (warmupSteps < 0)
    fail("ExponentialLr: warm-up steps ", warmupSteps, " must be >= 0");
}

double ExponentialLr::lrAt(int64_t step) const {
  checkStep("ExponentialLr", step);
  // The closed form: PyTorch's recursive lr *= gamma drifts by ~step ulps, irrelevant here.
  const double lr = lr0_ * std::pow(gamma_, static_cast<double>(step));
  return step < warmup_ ? lr * static_cast<double>(step + 1) / static_cast<double>(warmup_) : lr;
}

CosineLr::CosineLr(double lrMax, int64_t totalSteps, double lrMin, int64_t warmupSteps)
    : lrMax_(lrMax), lrMin_(lrMin), total_(totalSteps), warmup_(warmupSteps) {
  if (!(lrMax >= 0.0) || !(lrMin >= 0.0) || lrMin > lrMax)
    fail("CosineLr: learning rates max ", lrMax, ", min ", lrMin, " must satisfy 0 <= min <= max");
  if (warmupSteps < 0 || totalSteps <= warmupSteps)
    fail("CosineLr: total steps ", totalSteps, " must exceed the warm-up steps ", warmupSteps,
         " (>= 0)");
}

double CosineLr::lrAt(int64_t step) const {
  checkStep("CosineLr", step);
  if (step < warmup_)
    return lrMax_ * static_cast<double>(step + 1) / static_cast<double>(warmup_);
  if (step >= total_)
    return lrMin_;
  const double progress =
      static_cast<double>(step - warmup_) / static_cast<double>(total_ - warmup_);
  const double pi = std::acos(-1.0);
  return lrMin_ + 0.5 * (lrMax_ - lrMin_) * (1.0 + std::cos(pi * progress));
}

} // namespace simpli::ocl

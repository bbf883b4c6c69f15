#include "simpli/ocl/optim.h"

#include "simpli/error.h"
#include "simpli/ocl/launch.h"

#include <cmath>

namespace simpli::ocl {

Adam::Adam(std::vector<Tensor> parameters, double lr, double beta1, double beta2, double eps,
           double weightDecay, bool decoupled)
    : params_(std::move(parameters)), lr_(lr), beta1_(beta1), beta2_(beta2), eps_(eps),
      weightDecay_(weightDecay), decoupled_(decoupled) {
  // The same bounds as torch.optim.Adam.
  if (!(lr >= 0.0))
    fail("Adam: learning rate ", lr, " must be >= 0");
  if (!(beta1 >= 0.0 && beta1 < 1.0))
    fail("Adam: beta1 ", beta1, " must be in [0, 1)");
  if (!(beta2 >= 0.0 && beta2 < 1.0))
    fail("Adam: beta2 ", beta2, " must be in [0, 1)");
  if (!(eps >= 0.0))
    fail("Adam: eps ", eps, " must be >= 0");
  if (!(weightDecay >= 0.0))
    fail("Adam: weight decay ", weightDecay, " must be >= 0");
  for (std::size_t i = 0; i < params_.size(); ++i) {
    if (!params_[i].defined())
      fail("Adam: parameter ", i, " is undefined");
    checkedInt(params_[i].numel(), "Adam");
  }
  m_.resize(params_.size());
  v_.resize(params_.size());
  paramSteps_.assign(params_.size(), 0);
}

void Adam::setLr(double lr) {
  if (!(lr >= 0.0))
    fail("Adam: learning rate ", lr, " must be >= 0");
  lr_ = lr;
}

void Adam::step() {
  for (std::size_t i = 0; i < params_.size(); ++i) {
    Tensor& p = params_[i];
    Tensor g = p.grad();
    if (!g.defined() || p.numel() == 0)
      continue;
    if (g.shape() != p.shape() || g.dtype() != p.dtype())
      fail("Adam: gradient ", g.describe(), " of parameter ", i, " does not match ", p.describe());
    if (!m_[i].defined()) {
      m_[i] = Tensor::zeros(p.shape(), p.dtype());
      v_[i] = Tensor::zeros(p.shape(), p.dtype());
    }
    const int64_t t = ++paramSteps_[i];
    const double bc1 = 1.0 - std::pow(beta1_, static_cast<double>(t));
    const double bc2 = 1.0 - std::pow(beta2_, static_cast<double>(t));
    const double decay = decoupled_ ? 1.0 - lr_ * weightDecay_ : 1.0;
    const double coupled = decoupled_ ? 0.0 : weightDecay_;
    const int n = static_cast<int>(p.numel());
    Launch("optim", "adam_step", p.dtype())
        .arg(n)
        .real(decay)
        .real(coupled)
        .real(1.0 - beta1_)
        .real(beta2_)
        .real(1.0 - beta2_)
        .real(lr_ / bc1)
        .real(std::sqrt(bc2))
        .real(eps_)
        .arg(p)
        .arg(g)
        .arg(m_[i])
        .arg(v_[i])
        .run(n);
  }
  ++steps_;
}

void Adam::zeroGrad() {
  for (auto& p : params_)
    p.zeroGrad();
}

Adam::State Adam::exportState() const {
  State s;
  s.steps = steps_;
  s.params.resize(params_.size());
  for (std::size_t i = 0; i < params_.size(); ++i) {
    s.params[i].step = paramSteps_[i];
    if (m_[i].defined()) {
      s.params[i].m = m_[i].toVector();
      s.params[i].v = v_[i].toVector();
    }
  }
  return s;
}

void Adam::importState(const State& state) {
  if (state.steps < 0)
    fail("Adam state: step count ", state.steps, " is negative");
  if (state.params.size() != params_.size())
    fail("Adam state: has ", state.params.size(), " parameter entries, the optimiser has ",
         params_.size());
  for (std::size_t i = 0; i < params_.size(); ++i) {
    const ParamState& ps = state.params[i];
    const auto n = static_cast<std::size_t>(params_[i].numel());
    if (ps.step < 0)
      fail("Adam state: parameter ", i, " has a negative step count ", ps.step);
    const bool empty = ps.m.empty() && ps.v.empty();
    if (!empty && (ps.m.size() != n || ps.v.size() != n))
      fail("Adam state: parameter ", i, " ", params_[i].describe(), " has moments of ", ps.m.size(),
           " and ", ps.v.size(), " values, expected ", n);
    if (empty && ps.step > 0 && n > 0)
      fail("Adam state: parameter ", i, " has step ", ps.step, " but no moments");
  }
  // Validated: now apply (no partial import on error).
  steps_ = state.steps;
  for (std::size_t i = 0; i < params_.size(); ++i) {
    const ParamState& ps = state.params[i];
    paramSteps_[i] = ps.step;
    if (ps.m.empty() && ps.v.empty()) {
      m_[i] = Tensor();
      v_[i] = Tensor();
      continue;
    }
    m_[i] = Tensor::fromHost(ps.m, params_[i].shape(), params_[i].dtype());
    v_[i] = Tensor::fromHost(ps.v, params_[i].shape(), params_[i].dtype());
  }
}

} // namespace simpli::ocl

#pragma once
// Reverse-mode autograd. Each op that has an input requiring gradients records a Node: the
// inputs it needs gradients for and a closure that maps the output gradient to input
// gradients. backward() walks the nodes in reverse topological order (the tape), summing
// gradients that meet. With gradients disabled (NoGradGuard, inference) no node is recorded,
// so intermediates are freed as soon as the last handle to them dies.
#include "simpli/ocl/tensor.h"

#include <functional>
#include <string>
#include <vector>

namespace simpli::ocl {

struct Node {
  std::string name;           ///< op name, for error messages and debugging
  std::vector<Tensor> inputs; ///< inputs of the op (undefined entries need no gradient)
  /// gradOutput -> one gradient per input (undefined where not needed).
  std::function<std::vector<Tensor>(const Tensor& gradOutput)> backward;
};

class GradMode {
public:
  static bool enabled();
  static void setEnabled(bool enabled);
};

/// Disables recording within a scope (inference).
class NoGradGuard {
public:
  NoGradGuard() : previous_(GradMode::enabled()) { GradMode::setEnabled(false); }
  ~NoGradGuard() { GradMode::setEnabled(previous_); }
  NoGradGuard(const NoGradGuard&) = delete;
  NoGradGuard& operator=(const NoGradGuard&) = delete;

private:
  bool previous_;
};

/// True when gradients are enabled and any of the inputs requires them.
bool needsGrad(const std::vector<Tensor>& inputs);

/// Attaches a node to `output` when needsGrad(inputs). `backward` receives the output
/// gradient and returns one gradient per input (same order; may be undefined for inputs
/// that need none). Returns `output` for chaining.
Tensor record(const char* name, Tensor output, const std::vector<Tensor>& inputs,
              std::function<std::vector<Tensor>(const Tensor& gradOutput)> backward);

/// Scales all gradients so that their global L2 norm is at most maxNorm; returns the norm
/// before clipping. Parameters without a gradient are ignored.
double clipGradNorm(const std::vector<Tensor>& parameters, double maxNorm);

} // namespace simpli::ocl

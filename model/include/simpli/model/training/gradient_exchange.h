#pragma once
// What the samples of one data-parallel training step share (trainer.h), packed into one flat
// buffer so that a step costs ONE all-reduce however many tensors the network has:
//   [ every parameter's gradient, flattened in parameter order (zeros where it has none)
//   | one "has a gradient" count per parameter
//   | the step's scalars (loss terms, total, stop flags: the caller's) ]
// in the parameters' dtype (f32 runs exchange floats, f64 runs doubles). Each local sample adds
// its gradients on the host in sample order, the communicator sums over the ranks, and
// applyMean() writes sum / samples back as every parameter's gradient. A parameter gets a
// gradient when any sample had one (counted, so every rank makes the same choice), and keeps
// none when no sample did, as the optimiser then skips it on every rank.
//
// Why this makes K ranks equal one rank doing K samples: with two ranks an MPI sum is a + b on
// both, the same floats as the host's a + b; with more ranks the library's order of additions
// may differ in the last bits (communicator.h).
#include "simpli/model/parallel/communicator.h"

#include "simpli/ocl/tensor.h"

#include <cstddef>
#include <vector>

namespace simpli::training {

class GradientExchange {
public:
  /// For `parameters` (their gradients' layout) and `scalars` extra values per step.
  GradientExchange(const std::vector<ocl::Tensor>& parameters, std::size_t scalars);

  /// Adds the current gradients of `parameters` (same layout as at construction) and
  /// `scalars` to this step's sums; the first call of a step starts them.
  void add(const std::vector<ocl::Tensor>& parameters, const std::vector<double>& scalars);
  /// Sums the buffer over the ranks of `comm` (one all-reduce). Every rank adds the same
  /// number of samples before (add() at least once).
  void reduce(parallel::Communicator& comm);
  /// Writes the summed gradients divided by `samples` into the parameters' gradients (see the
  /// header comment for parameters without one) and starts a new step.
  void applyMean(const std::vector<ocl::Tensor>& parameters, int samples);
  /// The summed scalars of the step (valid after reduce(), until applyMean()).
  std::vector<double> scalars() const;

  /// Elements in the buffer (gradients + counts + scalars).
  std::size_t size() const { return total_; }
  std::size_t bytes() const { return total_ * (f64_ ? 8 : 4); }

private:
  template <typename T>
  void addTo(std::vector<T>& sum, const std::vector<ocl::Tensor>& params,
             const std::vector<double>& scalars);
  template <typename T>
  void applyFrom(const std::vector<T>& sum, const std::vector<ocl::Tensor>& params, int samples);

  std::vector<std::size_t> offsets_; ///< per parameter, into the gradient part
  std::size_t gradients_ = 0, scalarCount_ = 0, total_ = 0;
  bool f64_ = false;
  bool started_ = false; ///< a sample was added since the last applyMean()
  std::vector<float> f32Sum_;
  std::vector<double> f64Sum_;
};

} // namespace simpli::training

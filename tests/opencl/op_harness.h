#pragma once
// One harness for every device op (in the spirit of ggml's test-backend-ops):
//  * forward: the op runs in float32 on the device on fresh random inputs and is compared
//    with a plain C++ double-precision reference;
//  * backward: the op runs in float64 on the device; its analytic gradient (autograd) of
//    L = sum(out * W), W random, is compared with central finite differences of L.
// Buffers are poisoned (NaN) while the op runs, so elements it forgets to write show.
#include "simpli/ocl/tensor.h"

#include <functional>
#include <string>
#include <vector>

namespace simpli::test {

using ocl::Shape;
using ocl::Tensor;
using HostInputs = std::vector<std::vector<double>>;

struct OpCase {
  std::string name;
  std::vector<Shape> inputShapes;
  /// The device op under test.
  std::function<Tensor(const std::vector<Tensor>&)> device;
  /// The double-precision CPU reference: inputs (row-major) -> output (row-major).
  std::function<std::vector<double>(const HostInputs&)> reference;
  double low = -2.0, high = 2.0; ///< input range for random values
  /// Optional: adjust the random inputs (e.g. keep them away from kinks or make them > 0).
  std::function<void(HostInputs&)> prepare;
  double forwardTolerance = 1e-5;   ///< max |f32 - ref| / max |ref|
  double gradientTolerance = 1e-6;  ///< max |analytic - numeric| / max |numeric|
  std::vector<bool> differentiable; ///< per input; default: all
  int maxGradientProbes = 48;       ///< finite-difference probes per input (random subset)
  double step = 1e-6;               ///< finite-difference step (relative to max(1, |x|))
  uint64_t seed = 1234;
};

struct OpReport {
  double forwardError = 0.0;
  double gradientError = 0.0;
};

/// Random host inputs for a case (seeded), after `prepare`.
HostInputs makeInputs(const OpCase& c);
/// Runs both checks with GoogleTest assertions; returns the measured errors.
OpReport checkOp(const OpCase& c);
/// max |a - b| / max(max |b|, floor); NaN anywhere -> +inf.
double relativeError(const std::vector<double>& actual, const std::vector<double>& expected,
                     double floor = 1e-30);
/// Uploads host inputs as device tensors.
std::vector<Tensor> upload(const HostInputs& inputs, const std::vector<Shape>& shapes,
                           ocl::Dtype dtype, bool requireGrad);

/// Turns buffer poisoning on for the lifetime of the guard.
class PoisonGuard {
public:
  PoisonGuard();
  ~PoisonGuard();
};

} // namespace simpli::test

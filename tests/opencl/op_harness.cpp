#include "op_harness.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace simpli::test {

PoisonGuard::PoisonGuard() {
  ocl::Device::current().pool().setPoison(true);
}
PoisonGuard::~PoisonGuard() {
  ocl::Device::current().pool().setPoison(false);
}

double relativeError(const std::vector<double>& actual, const std::vector<double>& expected,
                     double floor) {
  if (actual.size() != expected.size())
    return std::numeric_limits<double>::infinity();
  double maxRef = floor, maxDiff = 0.0;
  for (std::size_t i = 0; i < actual.size(); ++i) {
    if (!std::isfinite(actual[i]) && !(actual[i] == expected[i]))
      return std::numeric_limits<double>::infinity();
    maxRef = std::max(maxRef, std::fabs(expected[i]));
    if (actual[i] != expected[i]) // equal infinities are equal
      maxDiff = std::max(maxDiff, std::fabs(actual[i] - expected[i]));
  }
  return maxDiff / maxRef;
}

HostInputs makeInputs(const OpCase& c) {
  std::mt19937_64 rng(c.seed);
  std::uniform_real_distribution<double> dist(c.low, c.high);
  HostInputs inputs;
  for (const auto& shape : c.inputShapes) {
    std::vector<double> v(static_cast<std::size_t>(ocl::numelOf(shape)));
    for (auto& x : v)
      x = dist(rng);
    inputs.push_back(std::move(v));
  }
  if (c.prepare)
    c.prepare(inputs);
  return inputs;
}

std::vector<Tensor> upload(const HostInputs& inputs, const std::vector<Shape>& shapes,
                           ocl::Dtype dtype, bool requireGrad) {
  std::vector<Tensor> out;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    Tensor t = Tensor::fromHost(inputs[i], shapes[i], dtype);
    if (requireGrad)
      t.setRequiresGrad(true);
    out.push_back(t);
  }
  return out;
}

namespace {

double weightedSum(const std::vector<double>& out, const std::vector<double>& w) {
  double s = 0.0;
  for (std::size_t i = 0; i < out.size(); ++i)
    s += out[i] * w[i];
  return s;
}

} // namespace

OpReport checkOp(const OpCase& c) {
  OpReport report;
  SCOPED_TRACE("op case: " + c.name);
  const HostInputs inputs = makeInputs(c);
  const std::vector<double> expected = c.reference(inputs);

  // Forward in float32, poisoned buffers.
  {
    PoisonGuard poison;
    ocl::NoGradGuard noGrad;
    Tensor out = c.device(upload(inputs, c.inputShapes, ocl::Dtype::F32, false));
    if (static_cast<std::size_t>(out.numel()) != expected.size()) {
      ADD_FAILURE() << "output " << out.describe() << " vs reference with " << expected.size()
                    << " elements";
      return report;
    }
    report.forwardError = relativeError(out.toVector(), expected);
    EXPECT_LE(report.forwardError, c.forwardTolerance) << "float32 forward vs double reference";
  }
  // Forward in float64 must match the reference to near machine precision too.
  {
    PoisonGuard poison;
    ocl::NoGradGuard noGrad;
    Tensor out = c.device(upload(inputs, c.inputShapes, ocl::Dtype::F64, false));
    EXPECT_LE(relativeError(out.toVector(), expected), 1e-10) << "float64 forward vs reference";
  }

  // Backward in float64 against central finite differences of L = sum(out * W).
  std::vector<bool> diff = c.differentiable;
  diff.resize(c.inputShapes.size(), c.differentiable.empty());
  if (std::none_of(diff.begin(), diff.end(), [](bool b) { return b; }))
    return report;
  std::mt19937_64 rng(c.seed ^ 0x5eedULL);
  std::uniform_real_distribution<double> wdist(-1.0, 1.0);
  std::vector<double> w(expected.size());
  for (auto& x : w)
    x = wdist(rng);

  std::vector<Tensor> leaves;
  {
    PoisonGuard poison;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      Tensor t = Tensor::fromHost(inputs[i], c.inputShapes[i], ocl::Dtype::F64);
      if (diff[i])
        t.setRequiresGrad(true);
      leaves.push_back(t);
    }
    Tensor out = c.device(leaves);
    Tensor weights = Tensor::fromHost(w, out.shape(), ocl::Dtype::F64);
    ocl::sumAll(ocl::mul(out, weights)).backward();
  }

  auto lossAt = [&](const HostInputs& in) {
    ocl::NoGradGuard noGrad;
    Tensor out = c.device(upload(in, c.inputShapes, ocl::Dtype::F64, false));
    return weightedSum(out.toVector(), w);
  };

  double maxDiff = 0.0, maxRef = 1e-12;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (!diff[i])
      continue;
    Tensor g = leaves[i].grad();
    if (!g.defined()) {
      ADD_FAILURE() << "no gradient reached input " << i;
      return report;
    }
    const std::vector<double> analytic = g.toVector();
    std::vector<std::size_t> probe(inputs[i].size());
    std::iota(probe.begin(), probe.end(), 0);
    std::shuffle(probe.begin(), probe.end(), rng);
    probe.resize(std::min<std::size_t>(probe.size(), c.maxGradientProbes));
    for (std::size_t k : probe) {
      HostInputs plus = inputs, minus = inputs;
      const double h = c.step * std::max(1.0, std::fabs(inputs[i][k]));
      plus[i][k] += h;
      minus[i][k] -= h;
      const double numeric = (lossAt(plus) - lossAt(minus)) / (2 * h);
      EXPECT_TRUE(std::isfinite(analytic[k])) << "input " << i << " element " << k;
      maxDiff = std::max(maxDiff, std::fabs(numeric - analytic[k]));
      maxRef = std::max({maxRef, std::fabs(numeric), std::fabs(analytic[k])});
    }
  }
  report.gradientError = maxDiff / maxRef;
  EXPECT_LE(report.gradientError, c.gradientTolerance)
      << "float64 backward vs central finite differences";
  return report;
}

} // namespace simpli::test

// Normalisation layers: layerNormTotal (SIMPLI's per-sample norm, unbiased std, eps outside the
// square root) and the standard last-axis layerNorm, through the harness, plus hand-computed
// values, constant inputs, large offsets, a full-size sample and bad use.
#include "op_harness.h"
#include "test_support.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_norm.h"
#include "simpli/ocl/ops_reduce.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;

namespace {

// Plain double reference of the reference implementation's LayerNormTotal.
std::vector<double> layerNormTotalRef(const std::vector<double>& x,
                                      const std::vector<double>& gamma,
                                      const std::vector<double>& beta, const Shape& shape,
                                      double eps) {
  const int64_t N = shape[0], C = shape[1];
  const int64_t M = ocl::numelOf(shape) / N, inner = M / C;
  std::vector<double> y(x.size());
  for (int64_t n = 0; n < N; ++n) {
    const double* p = x.data() + n * M;
    double mean = 0.0;
    for (int64_t i = 0; i < M; ++i)
      mean += p[i];
    mean /= static_cast<double>(M);
    double ss = 0.0;
    for (int64_t i = 0; i < M; ++i)
      ss += (p[i] - mean) * (p[i] - mean);
    const double s = std::sqrt(ss / static_cast<double>(M - 1));
    for (int64_t i = 0; i < M; ++i) {
      const int64_t c = i / inner;
      y[n * M + i] = gamma[c] * (p[i] - mean) / (s + eps) + beta[c];
    }
  }
  return y;
}

std::vector<double> layerNormRef(const std::vector<double>& x, const std::vector<double>& w,
                                 const std::vector<double>& b, double eps) {
  const std::size_t D = w.size(), rows = x.size() / D;
  std::vector<double> y(x.size());
  for (std::size_t r = 0; r < rows; ++r) {
    const double* p = x.data() + r * D;
    double mean = 0.0, ss = 0.0;
    for (std::size_t d = 0; d < D; ++d)
      mean += p[d];
    mean /= static_cast<double>(D);
    for (std::size_t d = 0; d < D; ++d)
      ss += (p[d] - mean) * (p[d] - mean);
    const double rstd = 1.0 / std::sqrt(ss / static_cast<double>(D) + eps);
    for (std::size_t d = 0; d < D; ++d)
      y[r * D + d] = (p[d] - mean) * rstd * w[d] + b[d];
  }
  return y;
}

} // namespace

TEST(LayerNormTotal, AgainstReferenceAndFiniteDifferences) {
  WorstErrors worst{"LayerNormTotal.AgainstReferenceAndFiniteDifferences"};
  // 4-D and 5-D, size-1 dims, odd sizes, the 2-element minimum, and rows long enough to span
  // many blocks (multi-block statistics and backward sums).
  const Shape shapes[] = {{2, 3, 4, 5},    {1, 1, 1, 2},    {3, 1, 5, 1},   {1, 4, 1, 7},
                          {2, 3, 2, 3, 4}, {1, 2, 1, 1, 3}, {2, 3, 37, 41}, {1, 2, 300, 301}};
  for (const auto& shape : shapes) {
    const Shape cshape{shape[1]};
    OpCase c;
    c.name = "layerNormTotal " + ocl::toString(shape);
    c.inputShapes = {shape, cshape, cshape};
    c.device = [](const std::vector<ocl::Tensor>& in) {
      return ocl::layerNormTotal(in[0], in[1], in[2]);
    };
    c.reference = [shape](const HostInputs& in) {
      return layerNormTotalRef(in[0], in[1], in[2], shape, 1e-5);
    };
    c.prepare = [](HostInputs& in) {
      for (auto& x : in[0])
        x = 3.0 * x + 1.5; // a non-zero mean
    };
    c.maxGradientProbes = ocl::numelOf(shape) > 10000 ? 12 : 32;
    worst.add(checkOp(c));
  }
}

TEST(LayerNormTotal, HandComputedUnbiasedStd) {
  // x = [1, 2 | 3, 4] as [N=1, C=2, 2, 1]: mean 2.5, unbiased variance
  // (1.5^2 + 0.5^2 + 0.5^2 + 1.5^2) / 3 = 5 / 3, s = sqrt(5 / 3) = 1.2909944487358056.
  // (The biased estimator, GroupNorm(1)'s, would give sqrt(5 / 4) = 1.118.)
  const double s = 1.2909944487358056, eps = 1e-5;
  const std::vector<double> gamma = {2.0, 3.0}, beta = {0.5, -1.0};
  const std::vector<double> expected = {2.0 * -1.5 / (s + eps) + 0.5, 2.0 * -0.5 / (s + eps) + 0.5,
                                        3.0 * 0.5 / (s + eps) - 1.0, 3.0 * 1.5 / (s + eps) - 1.0};
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    auto x = ocl::Tensor::fromHost(std::vector<double>{1, 2, 3, 4}, {1, 2, 2, 1}, dtype);
    auto g = ocl::Tensor::fromHost(gamma, {2}, dtype);
    auto b = ocl::Tensor::fromHost(beta, {2}, dtype);
    const auto y = ocl::layerNormTotal(x, g, b).toVector();
    for (std::size_t i = 0; i < 4; ++i)
      EXPECT_NEAR(y[i], expected[i], dtype == Dtype::F32 ? 1e-6 : 1e-14) << i;
  }
}

TEST(LayerNormTotal, ConstantInputGivesBetaAndFiniteGradients) {
  // 0.1 is not representable: a one-pass sum / M would not reproduce it exactly. The large
  // 5-D case spans many blocks of the statistics pass.
  const Shape shapes[] = {{2, 3, 4, 5}, {1, 4, 3, 50, 60}, {3, 1, 1, 2}};
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    for (const auto& shape : shapes) {
      for (double value : {0.0, 0.1, -3.7e3}) {
        SCOPED_TRACE(ocl::toString(shape) + " value " + std::to_string(value));
        const int64_t C = shape[1];
        auto x = ocl::Tensor::full(shape, value, dtype).setRequiresGrad(true);
        auto gamma = ocl::Tensor::uniform({C}, 0.0, 1.0, 7, dtype).setRequiresGrad(true);
        auto beta = ocl::Tensor::uniform({C}, -1.0, 1.0, 8, dtype).setRequiresGrad(true);
        ocl::Tensor y = ocl::layerNormTotal(x, gamma, beta);
        const auto yv = y.toVector(), bv = beta.toVector();
        const int64_t inner = ocl::numelOf(shape) / (shape[0] * C);
        for (std::size_t i = 0; i < yv.size(); ++i)
          ASSERT_EQ(yv[i], bv[(i / inner) % C]) << "element " << i;
        auto w = ocl::Tensor::uniform(shape, -1.0, 1.0, 9, dtype);
        ocl::sumAll(ocl::mul(y, w)).backward();
        for (const auto& t : {x, gamma, beta})
          for (double v : t.grad().toVector())
            ASSERT_TRUE(std::isfinite(v));
        // dgamma = sum g * xhat = 0 for xhat = 0.
        for (double v : gamma.grad().toVector())
          EXPECT_EQ(v, 0.0);
      }
    }
  }
}

TEST(LayerNormTotal, LargeOffsetKeepsFloatPrecision) {
  // Values 1e4 + N(0, 1): a naive E[x^2] - E[x]^2 in float would lose every digit.
  const Shape shape{2, 3, 40, 50};
  std::mt19937_64 rng(5);
  std::normal_distribution<double> dist(0.0, 1.0);
  std::vector<double> x(static_cast<std::size_t>(ocl::numelOf(shape)));
  for (auto& v : x)
    v = static_cast<float>(1e4 + dist(rng)); // float-representable, same input for both
  const std::vector<double> gamma = {1.0, 0.5, 2.0}, beta = {0.0, 0.1, -0.2};
  const auto expected = layerNormTotalRef(x, gamma, beta, shape, 1e-5);
  auto y = ocl::layerNormTotal(ocl::Tensor::fromHost(x, shape, Dtype::F32),
                               ocl::Tensor::fromHost(gamma, {3}, Dtype::F32),
                               ocl::Tensor::fromHost(beta, {3}, Dtype::F32));
  // float inputs near 1e4 carry ~1e-3 absolute noise in each difference: error ~1e-4 of y.
  EXPECT_LE(relativeError(y.toVector(), expected), 2e-4);
}

TEST(LayerNormTotal, FullSizeLevelZeroVolume) {
  // The reference's level-0 3-D block normalises a whole 12 x 41 x 96 x 128 volume per sample.
  const Shape shape{1, 12, 41, 96, 128};
  auto x = ocl::Tensor::normal(shape, 0.3, 2.0, 11, Dtype::F32).setRequiresGrad(true);
  auto gamma = ocl::Tensor::uniform({12}, 0.0, 1.0, 12, Dtype::F32).setRequiresGrad(true);
  auto beta = ocl::Tensor::uniform({12}, -1.0, 1.0, 13, Dtype::F32).setRequiresGrad(true);
  ocl::layerNormTotal(x, gamma, beta).toVector(); // warm-up (kernel compilation)
  const auto t0 = std::chrono::steady_clock::now();
  ocl::Tensor y = ocl::layerNormTotal(x, gamma, beta);
  ocl::Device::current().finish();
  const auto t1 = std::chrono::steady_clock::now();
  y.backward(ocl::Tensor::ones(shape, Dtype::F32));
  ocl::Device::current().finish();
  const auto t2 = std::chrono::steady_clock::now();
  std::printf("layerNormTotal %s: forward %.1f ms, backward %.1f ms\n",
              ocl::toString(shape).c_str(),
              std::chrono::duration<double, std::milli>(t1 - t0).count(),
              std::chrono::duration<double, std::milli>(t2 - t1).count());
  const auto expected =
      layerNormTotalRef(x.toVector(), gamma.toVector(), beta.toVector(), shape, 1e-5);
  EXPECT_LE(relativeError(y.toVector(), expected), 1e-5);
  // With an all-ones output gradient, dbeta_c is the element count per channel.
  const double perChannel = 41.0 * 96 * 128;
  for (double v : beta.grad().toVector())
    EXPECT_NEAR(v, perChannel, perChannel * 1e-6);
  // The float gradients agree with the same computation in double.
  auto x64 = ocl::Tensor::fromHost(x.toVector(), shape, Dtype::F64).setRequiresGrad(true);
  auto gamma64 = ocl::Tensor::fromHost(gamma.toVector(), {12}, Dtype::F64).setRequiresGrad(true);
  auto beta64 = ocl::Tensor::fromHost(beta.toVector(), {12}, Dtype::F64);
  ocl::layerNormTotal(x64, gamma64, beta64).backward(ocl::Tensor::ones(shape, Dtype::F64));
  EXPECT_LE(relativeError(x.grad().toVector(), x64.grad().toVector()), 1e-5);
  EXPECT_LE(relativeError(gamma.grad().toVector(), gamma64.grad().toVector()), 1e-5);
}

TEST(LayerNorm, AgainstReferenceAndFiniteDifferences) {
  WorstErrors worst{"LayerNorm.AgainstReferenceAndFiniteDifferences"};
  const Shape shapes[] = {{1, 1}, {7}, {3, 5}, {2, 1, 4, 9}, {4, 1}, {300, 16}};
  for (const auto& shape : shapes) {
    const Shape dshape{shape.back()};
    OpCase c;
    c.name = "layerNorm " + ocl::toString(shape);
    c.inputShapes = {shape, dshape, dshape};
    c.device = [](const std::vector<ocl::Tensor>& in) {
      return ocl::layerNorm(in[0], in[1], in[2]);
    };
    c.reference = [](const HostInputs& in) { return layerNormRef(in[0], in[1], in[2], 1e-6); };
    c.prepare = [](HostInputs& in) {
      for (auto& x : in[0])
        x = 2.0 * x - 0.7;
    };
    c.maxGradientProbes = 24;
    worst.add(checkOp(c));
  }
}

TEST(LayerNorm, ConstantRowGivesBiasAndFiniteGradients) {
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    auto x = ocl::Tensor::full({3, 6}, 0.1, dtype).setRequiresGrad(true);
    auto w = ocl::Tensor::uniform({6}, 0.5, 1.5, 3, dtype).setRequiresGrad(true);
    auto b = ocl::Tensor::uniform({6}, -1.0, 1.0, 4, dtype).setRequiresGrad(true);
    ocl::Tensor y = ocl::layerNorm(x, w, b);
    const auto yv = y.toVector(), bv = b.toVector();
    for (std::size_t i = 0; i < yv.size(); ++i)
      EXPECT_EQ(yv[i], bv[i % 6]);
    ocl::sumAll(ocl::mul(y, ocl::Tensor::uniform({3, 6}, -1, 1, 5, dtype))).backward();
    for (const auto& t : {x, w, b})
      for (double v : t.grad().toVector())
        EXPECT_TRUE(std::isfinite(v));
  }
}

TEST(Norm, BadUseThrowsNamingOpAndShapes) {
  auto x = ocl::Tensor::zeros({2, 3, 4, 5});
  auto c3 = ocl::Tensor::ones({3});
  auto c4 = ocl::Tensor::ones({4});
  expectError([&] { ocl::layerNormTotal(x, c4, c3); },
              {"layerNormTotal", "gamma", "f32[4]", "[3]", "f32[2, 3, 4, 5]"});
  expectError([&] { ocl::layerNormTotal(x, c3, c4); }, {"layerNormTotal", "beta"});
  expectError([&] { ocl::layerNormTotal(x, ocl::Tensor::ones({3}, Dtype::F64), c3); },
              {"layerNormTotal", "dtype"});
  expectError([&] { ocl::layerNormTotal(ocl::Tensor::zeros({5}), c3, c3); },
              {"layerNormTotal", "f32[5]", "rank"});
  expectError(
      [&] {
        ocl::layerNormTotal(ocl::Tensor::zeros({3, 1, 1, 1}), ocl::Tensor::ones({1}),
                            ocl::Tensor::ones({1}));
      },
      {"layerNormTotal", "at least 2"});
  expectError([&] { ocl::layerNormTotal(x, c3, c3, 0.0); }, {"layerNormTotal", "eps"});
  EXPECT_THROW(ocl::layerNormTotal(x, ocl::Tensor(), c3), Error);
  EXPECT_THROW(ocl::layerNormTotal(ocl::Tensor::zeros({0, 3, 2}), c3, c3), Error);

  auto rows = ocl::Tensor::zeros({4, 5});
  expectError([&] { ocl::layerNorm(rows, c4, ocl::Tensor::ones({5})); },
              {"layerNorm", "weight", "f32[4]", "[5]"});
  expectError([&] { ocl::layerNorm(rows, ocl::Tensor::ones({5}), c3); },
              {"layerNorm", "bias", "f32[3]"});
  EXPECT_THROW(
      ocl::layerNorm(ocl::Tensor::zeros({0, 5}), ocl::Tensor::ones({5}), ocl::Tensor::ones({5})),
      Error);
}

TEST(Norm, GradientsOnlyForInputsThatRequireThem) {
  // Parameters only (x is data), then x only: each gradient equals the all-inputs run's.
  const Shape shape{2, 3, 5, 7};
  for (bool total : {true, false}) {
    const Shape pshape = total ? Shape{3} : Shape{7};
    auto run = [&](bool gx, bool gp) {
      auto x = ocl::Tensor::normal(shape, 0.5, 2.0, 21, Dtype::F64);
      auto g = ocl::Tensor::uniform(pshape, 0.2, 1.0, 22, Dtype::F64);
      auto b = ocl::Tensor::uniform(pshape, -1.0, 1.0, 23, Dtype::F64);
      x.setRequiresGrad(gx);
      g.setRequiresGrad(gp);
      b.setRequiresGrad(gp);
      auto y = total ? ocl::layerNormTotal(x, g, b) : ocl::layerNorm(x, g, b);
      ocl::sumAll(ocl::mul(y, ocl::Tensor::uniform(shape, -1, 1, 24, Dtype::F64))).backward();
      return std::vector<ocl::Tensor>{x.grad(), g.grad(), b.grad()};
    };
    const auto all = run(true, true), params = run(false, true), input = run(true, false);
    EXPECT_FALSE(params[0].defined());
    EXPECT_FALSE(input[1].defined());
    EXPECT_FALSE(input[2].defined());
    EXPECT_EQ(params[1].toVector(), all[1].toVector());
    EXPECT_EQ(params[2].toVector(), all[2].toVector());
    EXPECT_EQ(input[0].toVector(), all[0].toVector());
  }
}

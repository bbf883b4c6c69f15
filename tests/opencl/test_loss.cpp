// Losses through the harness (odd shapes, size-1 dims, rows spanning many blocks), hand values,
// and bad use.
#include "op_harness.h"
#include "test_support.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_loss.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;

namespace {

std::vector<double> maskedL1Ref(const HostInputs& in, const Shape& s, int64_t maskChannels) {
  const int64_t N = s[0], C = s[1], L = s[2] * s[3];
  double total = 0.0;
  for (int64_t n = 0; n < N; ++n)
    for (int64_t c = 0; c < C; ++c) {
      const int64_t mrow = n * maskChannels + (maskChannels == 1 ? 0 : c);
      double num = 0.0, den = 0.0;
      for (int64_t i = 0; i < L; ++i) {
        const double m = in[2][mrow * L + i];
        num += std::fabs(in[0][(n * C + c) * L + i] - in[1][(n * C + c) * L + i]) * m;
        den += m;
      }
      total += num / (den + 1e-6);
    }
  return {total / static_cast<double>(N * C)};
}

// Sum over image pairs of f(difference) along H and W, for x [..., H, W].
std::pair<double, double> gradSums(const std::vector<double>& x, const Shape& s, bool square) {
  const int64_t H = s[s.size() - 2], W = s.back();
  const int64_t images = static_cast<int64_t>(x.size()) / (H * W);
  double sy = 0.0, sx = 0.0;
  auto f = [square](double d) { return square ? d * d : std::fabs(d); };
  for (int64_t b = 0; b < images; ++b)
    for (int64_t i = 0; i < H; ++i)
      for (int64_t j = 0; j < W; ++j) {
        const double v = x[(b * H + i) * W + j];
        if (i + 1 < H)
          sy += f(x[(b * H + i + 1) * W + j] - v);
        if (j + 1 < W)
          sx += f(x[(b * H + i) * W + j + 1] - v);
      }
  return {sy, sx};
}

double totalVariationRef(const std::vector<double>& x, const Shape& s) {
  const int64_t H = s[s.size() - 2], W = s.back();
  const double images = static_cast<double>(x.size()) / static_cast<double>(H * W);
  const auto [sy, sx] = gradSums(x, s, false);
  const double py = images * (H - 1) * W, px = images * H * (W - 1);
  return (py > 0 ? sy / py : 0.0) + (px > 0 ? sx / px : 0.0);
}

double smoothLayersRef(const std::vector<double>& x, const Shape& s) {
  const auto [sy, sx] = gradSums(x, s, true);
  return std::sqrt(sy + sx + 1e-6) / static_cast<double>(x.size());
}

// 1 - SSIM as the metric defines it: per image plane, "valid" Gaussian-window moments, the SSIM
// map's mean; then the mean over planes. Direct 2-D windows (not separable) in double.
double ssimLossRef(const HostInputs& in, const Shape& s, const ocl::SsimOptions& o) {
  const int64_t planes = s[0] * s[1], H = s[2], W = s[3], n = o.windowSize, r = n / 2;
  std::vector<double> g(static_cast<size_t>(n));
  double gs = 0.0;
  for (int64_t i = 0; i < n; ++i)
    gs += g[size_t(i)] = std::exp(-double((i - r) * (i - r)) / (2.0 * o.sigma * o.sigma));
  const double c1 = (o.k1 * o.dataRange) * (o.k1 * o.dataRange);
  const double c2 = (o.k2 * o.dataRange) * (o.k2 * o.dataRange);
  double total = 0.0;
  for (int64_t p = 0; p < planes; ++p) {
    const double* x = in[0].data() + p * H * W;
    const double* y = in[1].data() + p * H * W;
    double sum = 0.0;
    for (int64_t i = 0; i + n <= H; ++i)
      for (int64_t j = 0; j + n <= W; ++j) {
        double mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
        for (int64_t u = 0; u < n; ++u)
          for (int64_t v = 0; v < n; ++v) {
            const double w = g[size_t(u)] * g[size_t(v)] / (gs * gs);
            const double a = x[(i + u) * W + j + v], b = y[(i + u) * W + j + v];
            mx += w * a, my += w * b, xx += w * a * a, yy += w * b * b, xy += w * a * b;
          }
        sum += (2 * mx * my + c1) * (2 * (xy - mx * my) + c2) /
               ((mx * mx + my * my + c1) * (xx - mx * mx + yy - my * my + c2));
      }
    total += sum / double((H - n + 1) * (W - n + 1));
  }
  return 1.0 - total / double(planes);
}

const Shape kPointwiseShapes[] = {{1}, {7}, {2, 3, 1, 5}, {3, 1001}, {2, 3, 64, 67}};

} // namespace

TEST(Loss, L1AndMseAgainstReference) {
  WorstErrors worst{"Loss.L1AndMseAgainstReference"};
  for (bool mse : {false, true}) {
    for (const auto& shape : kPointwiseShapes) {
      OpCase c;
      c.name = std::string(mse ? "mseLoss " : "l1Loss ") + ocl::toString(shape);
      c.inputShapes = {shape, shape};
      c.device = [mse](const std::vector<ocl::Tensor>& in) {
        return mse ? ocl::mseLoss(in[0], in[1]) : ocl::l1Loss(in[0], in[1]);
      };
      c.reference = [mse](const HostInputs& in) {
        double s = 0.0;
        for (std::size_t i = 0; i < in[0].size(); ++i) {
          const double d = in[0][i] - in[1][i];
          s += mse ? d * d : std::fabs(d);
        }
        return std::vector<double>{s / static_cast<double>(in[0].size())};
      };
      c.prepare = [](HostInputs& in) {
        // a - b away from 0 (the kink of |.|): b = a - d with |d| >= 0.05.
        for (std::size_t i = 0; i < in[0].size(); ++i) {
          double d = in[1][i] - in[0][i];
          if (std::fabs(d) < 0.05)
            d = d >= 0 ? d + 0.05 : d - 0.05;
          in[1][i] = in[0][i] + d;
        }
      };
      c.maxGradientProbes = 16;
      // Each element moves a mean over up to 25k elements by ~1e-5 of the loss: a larger step
      // keeps the difference quotient above round-off; it is exact here (|.| is linear away
      // from its kink, the square is quadratic).
      c.step = 1e-3;
      worst.add(checkOp(c));
    }
  }
}

TEST(Loss, MaskedL1AgainstReference) {
  WorstErrors worst{"Loss.MaskedL1AgainstReference"};
  struct MaskCase {
    Shape pred;
    int64_t maskChannels;
  };
  const MaskCase cases[] = {{{2, 3, 4, 5}, 1}, {{2, 3, 4, 5}, 3}, {{1, 1, 1, 1}, 1},
                            {{3, 1, 2, 7}, 1}, {{1, 2, 1, 9}, 2}, {{2, 3, 33, 47}, 1}};
  for (const auto& mc : cases) {
    const Shape maskShape{mc.pred[0], mc.maskChannels, mc.pred[2], mc.pred[3]};
    OpCase c;
    c.name = "maskedL1 " + ocl::toString(mc.pred) + " mask " + ocl::toString(maskShape);
    c.inputShapes = {mc.pred, mc.pred, maskShape};
    c.device = [](const std::vector<ocl::Tensor>& in) {
      return ocl::maskedL1(in[0], in[1], in[2]);
    };
    c.reference = [mc](const HostInputs& in) { return maskedL1Ref(in, mc.pred, mc.maskChannels); };
    c.prepare = [](HostInputs& in) {
      for (std::size_t i = 0; i < in[0].size(); ++i) {
        double d = in[1][i] - in[0][i];
        if (std::fabs(d) < 0.05)
          d = d >= 0 ? d + 0.05 : d - 0.05;
        in[1][i] = in[0][i] + d;
      }
      for (auto& m : in[2])
        m = (m + 2.0) / 4.0 + 0.05; // opacities in [0.05, 1.05)
    };
    c.maxGradientProbes = 16;
    worst.add(checkOp(c));
  }
}

TEST(Loss, MaskedL1HandValueAndEmptyMask) {
  // One image, one channel, 2 pixels: |1 - 0| * 1 + |2 - 5| * 0.5 = 2.5; Z = 1.5 + 1e-6.
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    auto p = ocl::Tensor::fromHost(std::vector<double>{1, 2}, {1, 1, 1, 2}, dtype);
    auto t = ocl::Tensor::fromHost(std::vector<double>{0, 5}, {1, 1, 1, 2}, dtype);
    auto m = ocl::Tensor::fromHost(std::vector<double>{1, 0.5}, {1, 1, 1, 2}, dtype);
    EXPECT_NEAR(ocl::maskedL1(p, t, m).item(), 2.5 / (1.5 + 1e-6), 1e-6);
    // An all-zero mask gives 0 (no NaN), thanks to the + 1e-6.
    auto z = ocl::Tensor::zeros({1, 1, 1, 2}, dtype);
    EXPECT_EQ(ocl::maskedL1(p, t, z).item(), 0.0);
  }
}

TEST(Loss, TotalVariationAgainstReference) {
  WorstErrors worst{"Loss.TotalVariationAgainstReference"};
  const Shape shapes[] = {{4, 5}, {2, 3, 4, 5}, {1, 7}, {6, 1}, {1, 1}, {2, 37, 61}};
  for (const auto& shape : shapes) {
    OpCase c;
    c.name = "totalVariation " + ocl::toString(shape);
    c.inputShapes = {shape};
    c.device = [](const std::vector<ocl::Tensor>& in) { return ocl::totalVariation(in[0]); };
    c.reference = [shape](const HostInputs& in) {
      return std::vector<double>{totalVariationRef(in[0], shape)};
    };
    // Neighbour differences away from 0: a ramp plus small noise.
    c.prepare = [shape](HostInputs& in) {
      const int64_t W = shape.back();
      for (std::size_t i = 0; i < in[0].size(); ++i)
        in[0][i] =
            0.3 * static_cast<double>(i % W) + 0.7 * static_cast<double>(i / W) + 0.05 * in[0][i];
    };
    c.maxGradientProbes = 24;
    worst.add(checkOp(c));
  }
}

TEST(Loss, SmoothLayersAgainstReference) {
  WorstErrors worst{"Loss.SmoothLayersAgainstReference"};
  const Shape shapes[] = {{1, 1, 4, 5}, {2, 3, 5, 7}, {1, 2, 1, 6}, {1, 1, 1, 1}, {2, 2, 30, 41}};
  for (const auto& shape : shapes) {
    OpCase c;
    c.name = "smoothLayersLoss " + ocl::toString(shape);
    c.inputShapes = {shape};
    c.device = [](const std::vector<ocl::Tensor>& in) { return ocl::smoothLayersLoss(in[0]); };
    c.reference = [shape](const HostInputs& in) {
      return std::vector<double>{smoothLayersRef(in[0], shape)};
    };
    c.maxGradientProbes = 24;
    worst.add(checkOp(c));
  }
}

TEST(Loss, SmoothLayersOfConstantDepthIsFiniteWithZeroGradient) {
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    auto d = ocl::Tensor::full({1, 2, 3, 4}, 2.5, dtype).setRequiresGrad(true);
    ocl::Tensor loss = ocl::smoothLayersLoss(d);
    EXPECT_NEAR(loss.item(), std::sqrt(1e-6) / 24.0, 1e-9);
    loss.backward();
    for (double g : d.grad().toVector())
      EXPECT_EQ(g, 0.0);
  }
}

TEST(Loss, SsimAgainstReference) {
  WorstErrors worst{"Loss.SsimAgainstReference"};
  struct SsimCase {
    Shape shape;
    ocl::SsimOptions options;
  };
  const SsimCase cases[] = {{{1, 1, 11, 11}, {}},
                            {{2, 3, 13, 17}, {}},
                            {{1, 2, 24, 31}, {7, 1.0, 2.0, 0.01, 0.03}},
                            {{3, 1, 5, 9}, {3, 0.8, 1.0, 0.05, 0.1}},
                            {{1, 1, 4, 6}, {1, 1.5, 1.0, 0.01, 0.03}}};
  for (const auto& sc : cases) {
    OpCase c;
    c.name =
        "ssimLoss " + ocl::toString(sc.shape) + " window " + std::to_string(sc.options.windowSize);
    c.inputShapes = {sc.shape, sc.shape};
    c.device = [o = sc.options](const std::vector<ocl::Tensor>& in) {
      return ocl::ssimLoss(in[0], in[1], o);
    };
    c.reference = [sc](const HostInputs& in) {
      return std::vector<double>{ssimLossRef(in, sc.shape, sc.options)};
    };
    // b = a blurred a little plus noise: a pair with SSIM well inside (0, 1), not only noise.
    c.prepare = [](HostInputs& in) {
      for (std::size_t i = 0; i < in[0].size(); ++i)
        in[1][i] = 0.6 * in[0][i] + 0.2 * in[0][i > 0 ? i - 1 : i] + 0.1 * in[1][i];
    };
    c.maxGradientProbes = 24;
    // Cancellation in E[x^2] - E[x]^2 costs float32 digits: the forward is a mean of ratios of
    // such differences.
    c.forwardTolerance = 1e-4;
    worst.add(checkOp(c));
  }
}

TEST(Loss, SsimHandValues) {
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    // float32: the variances E[x^2] - E[x]^2 of a constant image cancel to ~1e-8 against C2 =
    // 9e-4 in the contrast term.
    const double tol = dtype == Dtype::F32 ? 1e-4 : 1e-12;
    // Identical images: SSIM 1, loss 0, and a maximum, so a zero gradient.
    auto a = ocl::Tensor::normal({1, 3, 12, 14}, 0.5, 0.2, 7, dtype).setRequiresGrad(true);
    ocl::Tensor same = ocl::ssimLoss(a, a.detach());
    EXPECT_NEAR(same.item(), 0.0, tol);
    same.backward();
    for (double g : a.grad().toVector())
      EXPECT_NEAR(g, 0.0, dtype == Dtype::F32 ? 1e-4 : 1e-10);
    // Constant images u and v: no variance, SSIM = (2uv + C1) / (u^2 + v^2 + C1).
    auto u = ocl::Tensor::full({1, 1, 11, 11}, 0.25, dtype);
    auto v = ocl::Tensor::full({1, 1, 11, 11}, 0.75, dtype);
    const double c1 = 1e-4;
    EXPECT_NEAR(ocl::ssimLoss(u, v).item(),
                1.0 - (2 * 0.25 * 0.75 + c1) / (0.25 * 0.25 + 0.75 * 0.75 + c1), tol);
    // Anti-correlated images of equal mean and variance: SSIM = (C2 - 2 s^2) / (2 s^2 + C2) < 0.
    std::vector<double> p(121), q(121);
    for (size_t i = 0; i < p.size(); ++i) {
      p[i] = 0.5 + ((i % 2) ? 0.1 : -0.1);
      q[i] = 1.0 - p[i];
    }
    auto pt = ocl::Tensor::fromHost(p, {1, 1, 11, 11}, dtype);
    auto qt = ocl::Tensor::fromHost(q, {1, 1, 11, 11}, dtype);
    EXPECT_GT(ocl::ssimLoss(pt, qt).item(), 1.5);
  }
}

TEST(Loss, BadUseThrowsNamingLossAndShapes) {
  auto a = ocl::Tensor::zeros({2, 3});
  auto b = ocl::Tensor::zeros({3, 2});
  expectError([&] { ocl::l1Loss(a, b); }, {"l1Loss", "f32[2, 3]", "f32[3, 2]"});
  expectError(
      [&] {
        ocl::mseLoss(a, ocl::Tensor::zeros({2, 3}, Dtype::F64));
      },
      {"mseLoss", "dtype"});
  EXPECT_THROW(ocl::l1Loss(ocl::Tensor(), a), Error);
  EXPECT_THROW(ocl::l1Loss(ocl::Tensor::zeros({0}), ocl::Tensor::zeros({0})), Error);

  auto p = ocl::Tensor::zeros({2, 3, 4, 5});
  expectError(
      [&] {
        ocl::maskedL1(p, ocl::Tensor::zeros({2, 3, 4, 6}), p);
      },
      {"maskedL1", "f32[2, 3, 4, 5]", "f32[2, 3, 4, 6]"});
  expectError(
      [&] {
        ocl::maskedL1(p, p, ocl::Tensor::zeros({2, 2, 4, 5}));
      },
      {"maskedL1", "mask", "f32[2, 2, 4, 5]"});
  expectError(
      [&] {
        ocl::maskedL1(p, p, ocl::Tensor::zeros({2, 1, 5, 4}));
      },
      {"maskedL1", "mask", "f32[2, 1, 5, 4]"});
  expectError(
      [&] {
        ocl::maskedL1(ocl::Tensor::zeros({3, 4, 5}), ocl::Tensor::zeros({3, 4, 5}), p);
      },
      {"maskedL1", "f32[3, 4, 5]", "[N, C, H, W]"});

  expectError(
      [&] {
        ocl::ssimLoss(p, ocl::Tensor::zeros({2, 3, 4, 6}));
      },
      {"ssimLoss", "f32[2, 3, 4, 5]", "f32[2, 3, 4, 6]"});
  expectError([&] { ocl::ssimLoss(p, p); }, {"ssimLoss", "f32[2, 3, 4, 5]", "11 x 11 window"});
  expectError([&] { ocl::ssimLoss(p, p, {4}); }, {"ssimLoss", "window size 4"});
  expectError([&] { ocl::ssimLoss(p, p, {3, 0.0}); }, {"ssimLoss", "sigma 0"});
  expectError([&] { ocl::ssimLoss(p, p, {3, 1.0, -1.0}); }, {"ssimLoss", "data range -1"});
  expectError(
      [&] {
        ocl::ssimLoss(ocl::Tensor::zeros({3, 4, 5}), ocl::Tensor::zeros({3, 4, 5}));
      },
      {"ssimLoss", "f32[3, 4, 5]", "[N, C, H, W]"});

  expectError([&] { ocl::totalVariation(ocl::Tensor::zeros({5})); }, {"totalVariation", "f32[5]"});
  expectError(
      [&] {
        ocl::smoothLayersLoss(ocl::Tensor::zeros({3, 4, 5}));
      },
      {"smoothLayersLoss", "f32[3, 4, 5]", "[B, L, H, W]"});
}

TEST(Loss, GradientsOnlyForInputsThatRequireThem) {
  // The usual training case: the prediction needs a gradient, target and mask are data.
  const Shape shape{2, 3, 6, 9};
  auto run = [&](bool all) {
    auto p = ocl::Tensor::normal(shape, 0.0, 1.0, 31, Dtype::F64).setRequiresGrad(true);
    auto t = ocl::Tensor::normal(shape, 0.0, 1.0, 32, Dtype::F64).setRequiresGrad(all);
    auto m = ocl::Tensor::uniform({2, 1, 6, 9}, 0.0, 1.0, 33, Dtype::F64).setRequiresGrad(all);
    ocl::add(ocl::add(ocl::maskedL1(p, t, m), ocl::l1Loss(p, t)), ocl::mseLoss(t, p)).backward();
    EXPECT_EQ(t.grad().defined(), all);
    EXPECT_EQ(m.grad().defined(), all);
    return p.grad().toVector();
  };
  EXPECT_EQ(run(false), run(true));
}

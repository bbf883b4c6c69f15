// The training losses of §8.1 against plain double references on small random inputs.
#include "support/expect_error.h"

#include "simpli/model/metrics/image_quality.h"
#include "simpli/model/training/losses.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace simpli::training {
namespace {

struct HostT {
  std::vector<int64_t> shape;
  std::vector<double> v;
  int64_t numel() const {
    int64_t n = 1;
    for (int64_t d : shape)
      n *= d;
    return n;
  }
};

HostT randomT(std::vector<int64_t> shape, double lo, double hi, std::mt19937& g) {
  HostT t{std::move(shape), {}};
  std::uniform_real_distribution<double> d(lo, hi);
  t.v.resize(size_t(t.numel()));
  for (double& x : t.v)
    x = d(g);
  return t;
}
ocl::Tensor dev(const HostT& t, ocl::Dtype dtype) {
  return ocl::Tensor::fromHost(t.v, t.shape, dtype);
}

// Masked L1 per (n, c) mean; pred/target [N,C,H,W], mask [N,1,H,W].
double maskedL1Ref(const HostT& p, const HostT& t, const HostT& m) {
  const int64_t N = p.shape[0], C = p.shape[1], HW = p.shape[2] * p.shape[3];
  double total = 0;
  for (int64_t n = 0; n < N; ++n)
    for (int64_t c = 0; c < C; ++c) {
      double s = 0, z = 0;
      for (int64_t i = 0; i < HW; ++i) {
        const double w = m.v[size_t(n * HW + i)];
        s += std::abs(p.v[size_t((n * C + c) * HW + i)] - t.v[size_t((n * C + c) * HW + i)]) * w;
        z += w;
      }
      total += s / (z + 1e-6);
    }
  return total / double(N * C);
}

double l1Ref(const HostT& a, const HostT& b) {
  double s = 0;
  for (size_t i = 0; i < a.v.size(); ++i)
    s += std::abs(a.v[i] - b.v[i]);
  return s / double(a.v.size());
}

HostT nearestHalf(const HostT& x) {
  const int64_t N = x.shape[0], C = x.shape[1], H = x.shape[2], W = x.shape[3];
  HostT y{{N, C, H / 2, W / 2}, {}};
  for (int64_t nc = 0; nc < N * C; ++nc)
    for (int64_t i = 0; i < H / 2; ++i)
      for (int64_t j = 0; j < W / 2; ++j)
        y.v.push_back(x.v[size_t((nc * H + 2 * i) * W + 2 * j)]);
  return y;
}

double smoothRef(const HostT& D) { // [L, H, W]
  const int64_t L = D.shape[0], H = D.shape[1], W = D.shape[2];
  double s = 0;
  for (int64_t l = 0; l < L; ++l)
    for (int64_t i = 0; i < H; ++i)
      for (int64_t j = 0; j < W; ++j) {
        const double d = D.v[size_t((l * H + i) * W + j)];
        if (i + 1 < H)
          s += std::pow(D.v[size_t((l * H + i + 1) * W + j)] - d, 2);
        if (j + 1 < W)
          s += std::pow(D.v[size_t((l * H + i) * W + j + 1)] - d, 2);
      }
  return std::sqrt(s + 1e-6) / double(L * H * W);
}

TEST(TrainLosses, MatchDoubleReference) {
  std::mt19937 g(5);
  const int64_t N = 3, V = 2, L = 4, H = 10, W = 14;
  const HostT colour = randomT({N, 3, H, W}, -1, 1, g), target = randomT({N, 3, H, W}, -1, 1, g);
  const HostT opacity = randomT({N, 1, H, W}, 0, 1, g), clean = randomT({V, 3, H, W}, -1, 1, g);
  const HostT r0 = randomT({V, 3, H / 2, W / 2}, -1, 1, g);
  std::vector<HostT> r;
  for (int k = 0; k < 3; ++k)
    r.push_back(randomT({V, 3, H, W}, -1, 1, g));
  const HostT depth = randomT({L, H, W}, 1, 30, g);

  TrainingConfig cfg;
  cfg.lossWeights["smooth_layers"] = 0.5;
  cfg.lossWeights["intermediate_loss_2_l1"] = 0.0; // weight 0: computed, not in the total
  std::map<std::string, double> ref;
  ref["l1"] = maskedL1Ref(colour, target, opacity);
  ref["intermediate_loss_0_l1"] = l1Ref(r0, nearestHalf(clean));
  for (int k = 0; k < 3; ++k)
    ref["intermediate_loss_" + std::to_string(k + 1) + "_l1"] = l1Ref(r[size_t(k)], clean);
  ref["smooth_layers"] = smoothRef(depth);
  double refTotal = 0;
  for (const auto& [k, v] : ref)
    refTotal += cfg.weight(k) * v;

  for (ocl::Dtype dtype : {ocl::Dtype::F32, ocl::Dtype::F64}) {
    const double tol = dtype == ocl::Dtype::F32 ? 1e-5 : 1e-12;
    generator::GeneratorOutput out;
    out.depth = dev(depth, dtype);
    out.intermediateSourceRenders.push_back(dev(r0, dtype));
    for (const HostT& x : r)
      out.intermediateSourceRenders.push_back(dev(x, dtype));
    const LossTerms terms = computeLosses(cfg, out, dev(colour, dtype), dev(opacity, dtype),
                                          dev(target, dtype), dev(clean, dtype), nullptr);
    EXPECT_EQ(terms.terms.size(), 6u);
    for (const auto& [k, v] : ref)
      EXPECT_NEAR(terms.value(k), v, tol * std::abs(v)) << k;
    EXPECT_TRUE(std::isnan(terms.value("perceptual")));
    EXPECT_NEAR(terms.total.item(), refTotal, tol * refTotal);
  }
}

// The ssim term is one minus the evaluation metric on the same images: training lowers exactly
// what the SSIM column of `simpli eval` reports (before the central crop).
TEST(TrainLosses, SsimTermIsOneMinusTheMetric) {
  std::mt19937 g(23);
  const int64_t N = 2, H = 19, W = 26;
  HostT colour = randomT({N, 3, H, W}, -1, 1, g);
  const HostT noise = randomT({N, 3, H, W}, -0.3, 0.3, g);
  HostT target = colour; // a related pair: SSIM well inside (0, 1)
  for (size_t i = 0; i < target.v.size(); ++i)
    target.v[i] = std::clamp(0.7 * colour.v[i] + noise.v[i], -1.0, 1.0);
  double metricMean = 0;
  for (int64_t n = 0; n < N; ++n) {
    metrics::MetricImage a(int(W), int(H), 3), b(int(W), int(H), 3);
    for (int c = 0; c < 3; ++c)
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          const size_t k = size_t(((n * 3 + c) * H + y) * W + x);
          a.at(y, x, c) = float((colour.v[k] + 1) / 2);
          b.at(y, x, c) = float((target.v[k] + 1) / 2);
          // The metric reads float pixels: give the loss the same values.
          colour.v[k] = 2.0 * double(a.at(y, x, c)) - 1.0;
          target.v[k] = 2.0 * double(b.at(y, x, c)) - 1.0;
        }
    metricMean += metrics::ssim(a, b) / double(N);
  }
  EXPECT_GT(metricMean, 0.2);
  EXPECT_LT(metricMean, 0.9);
  EXPECT_NEAR(
      ssimLossOfSignedImages(dev(colour, ocl::Dtype::F64), dev(target, ocl::Dtype::F64)).item(),
      1.0 - metricMean, 1e-12);
  // In computeLosses: only when its weight is positive, and then in the total.
  TrainingConfig cfg;
  generator::GeneratorOutput out;
  out.depth = dev(randomT({4, H, W}, 1, 30, g), ocl::Dtype::F64);
  const HostT opacity = randomT({N, 1, H, W}, 0, 1, g), clean = randomT({1, 3, H, W}, -1, 1, g);
  auto losses = [&] {
    return computeLosses(cfg, out, dev(colour, ocl::Dtype::F64), dev(opacity, ocl::Dtype::F64),
                         dev(target, ocl::Dtype::F64), dev(clean, ocl::Dtype::F64), nullptr);
  };
  const LossTerms off = losses();
  EXPECT_TRUE(std::isnan(off.value("ssim")));
  cfg.lossWeights["ssim"] = 0.5;
  const LossTerms on = losses();
  EXPECT_NEAR(on.value("ssim"), 1.0 - metricMean, 1e-12);
  EXPECT_NEAR(on.total.item() - off.total.item(), 0.5 * (1.0 - metricMean), 1e-12);
}

// depthLoss = sum over known pixels of A |log((D + eps) / (A + eps)) - log z|, divided by their
// count.
TEST(TrainLosses, DepthLossMatchesDoubleReferenceAndFiniteDifferences) {
  std::mt19937 g(17);
  const HostT D = randomT({2, 1, 3, 4}, 0.5, 6.0, g);
  // (D / A spans about 0.5 .. 120 and 1 / z 0.1 .. 1: errors of both signs.)
  const HostT A = randomT({2, 1, 3, 4}, 0.05, 1.0, g);
  HostT inv = randomT({2, 1, 3, 4}, 0.1, 1.0, g);
  for (size_t k = 0; k < inv.v.size(); k += 5)
    inv.v[k] = 0; // no surface: not counted
  auto reference = [&](const HostT& d, const HostT& a) {
    double s = 0;
    int n = 0;
    for (size_t k = 0; k < d.v.size(); ++k)
      if (inv.v[k] > 0) {
        s += a.v[k] * std::abs(std::log((d.v[k] + 1e-6) / (a.v[k] + 1e-6)) + std::log(inv.v[k]));
        ++n;
      }
    return s / n;
  };
  ocl::Tensor d = dev(D, ocl::Dtype::F64), a = dev(A, ocl::Dtype::F64);
  d.setRequiresGrad(true);
  a.setRequiresGrad(true);
  const ocl::Tensor loss = depthLoss(d, a, dev(inv, ocl::Dtype::F64));
  EXPECT_NEAR(loss.item(), reference(D, A), 1e-12);
  loss.backward();
  const std::vector<double> gd = d.grad().toVector(), ga = a.grad().toVector();
  const double h = 1e-6;
  for (size_t k = 0; k < D.v.size(); ++k) {
    HostT dp = D, dm = D, ap = A, am = A;
    dp.v[k] += h;
    dm.v[k] -= h;
    ap.v[k] += h;
    am.v[k] -= h;
    EXPECT_NEAR(gd[k], (reference(dp, A) - reference(dm, A)) / (2 * h), 1e-6) << "D " << k;
    EXPECT_NEAR(ga[k], (reference(D, ap) - reference(D, am)) / (2 * h), 1e-6) << "A " << k;
  }
  // A render at the true depth with full opacity costs nothing (up to eps), and so does a
  // transparent one (A = D = 0); with no known pixel the loss is 0.
  HostT exact = A, ones = A, zeros = A;
  for (size_t k = 0; k < exact.v.size(); ++k)
    exact.v[k] = inv.v[k] > 0 ? 1.0 / inv.v[k] : 3.0;
  std::fill(ones.v.begin(), ones.v.end(), 1.0);
  std::fill(zeros.v.begin(), zeros.v.end(), 0.0);
  EXPECT_NEAR(
      depthLoss(dev(exact, ocl::Dtype::F64), dev(ones, ocl::Dtype::F64), dev(inv, ocl::Dtype::F64))
          .item(),
      0.0, 1e-5);
  EXPECT_EQ(
      depthLoss(dev(zeros, ocl::Dtype::F64), dev(zeros, ocl::Dtype::F64), dev(inv, ocl::Dtype::F64))
          .item(),
      0.0);
  HostT none = inv;
  std::fill(none.v.begin(), none.v.end(), 0.0);
  EXPECT_EQ(depthLoss(dev(D, ocl::Dtype::F64), dev(A, ocl::Dtype::F64), dev(none, ocl::Dtype::F64))
                .item(),
            0.0);
  test::expectError(
      [&] {
        depthLoss(dev(D, ocl::Dtype::F64), dev(A, ocl::Dtype::F64),
                  ocl::Tensor::zeros({2, 1, 3, 3}, ocl::Dtype::F64));
      },
      {"depthLoss", "one shape"});
}

TEST(TrainLosses, NearestResizeIsPyTorchsDefault) {
  // 5 -> 3: floor(dst * 5 / 3) = 0, 1, 3.
  std::vector<double> v(10);
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = double(i);
  const ocl::Tensor x = ocl::Tensor::fromHost(v, {2, 5}, ocl::Dtype::F64);
  const std::vector<double> y = resizeNearest(x, 1, 3).toVector();
  EXPECT_EQ(y, (std::vector<double>{0, 1, 3}));
}

TEST(TrainLosses, BadIntermediateShapeNamesIt) {
  TrainingConfig cfg;
  generator::GeneratorOutput out;
  out.depth = ocl::Tensor::ones({2, 4, 4});
  out.intermediateSourceRenders.push_back(ocl::Tensor::zeros({3, 3, 2, 2}));
  const ocl::Tensor c = ocl::Tensor::zeros({1, 3, 4, 4}), o = ocl::Tensor::ones({1, 1, 4, 4});
  test::expectError(
      [&] {
        computeLosses(cfg, out, c, o, c, ocl::Tensor::zeros({2, 3, 4, 4}), nullptr);
      },
      {"intermediate render 0", "f32[3, 3, 2, 2]", "f32[2, 3, 4, 4]"});
}

} // namespace
} // namespace simpli::training

// ViewAttention::aggregate (the fused inference kernel) against the composed form written out
// in double: ViewAttention::forward on the [samples | weight] tokens, then the weighted mean and
// variance over the views, for view counts 1 .. 16, channel and hidden sizes other than the
// official ones, views with zero weight, large logits, and float32 against float64.
#include "support/expect_error.h"

#include "simpli/model/network/attention.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"

#include <gtest/gtest.h>

#include <cmath>

namespace simpli::network {
namespace {

using ocl::Dtype;
using ocl::Tensor;

// Outputs of the pool's fresh buffers are NaN, so an unwritten element fails the comparison.
struct PoisonScope {
  PoisonScope() { ocl::Device::current().pool().setPoison(true); }
  ~PoisonScope() { ocl::Device::current().pool().setPoison(false); }
};

struct Case {
  int V, S, C, hidden, h, w;
  double logitScale; // multiplies the projection weights: large values saturate the softmax
};

// Random weights with some views masked out per pixel, normalised like the generator's
// w_v = m_v / (sum_v m_v + 1e-7).
std::vector<double> viewWeights(const Case& k, uint64_t seed) {
  const std::vector<double> u =
      Tensor::uniform({k.V, k.S, 1, k.h, k.w}, 0, 1, seed, Dtype::F64).toVector();
  const int64_t per = int64_t(k.S) * k.h * k.w;
  std::vector<double> m(u.size());
  for (std::size_t i = 0; i < u.size(); ++i)
    m[i] = u[i] < 0.3 ? 0.0 : 1.0;
  std::vector<double> w(u.size());
  for (int64_t p = 0; p < per; ++p) {
    double total = 0;
    for (int v = 0; v < k.V; ++v)
      total += m[v * per + p];
    for (int v = 0; v < k.V; ++v)
      w[v * per + p] = m[v * per + p] / (total + 1e-7);
  }
  return w;
}

// The composed form in double: tokens [S*h*w, V, C + 1] through forward(), then mean / var.
std::vector<double> composed(const ViewAttention& va, const Case& k,
                             const std::vector<double>& samples, const std::vector<double>& w) {
  const int64_t hw = int64_t(k.h) * k.w, N = k.S * hw;
  std::vector<double> tokens(std::size_t(N * k.V * (k.C + 1)));
  for (int v = 0; v < k.V; ++v)
    for (int s = 0; s < k.S; ++s)
      for (int64_t p = 0; p < hw; ++p) {
        double* t = &tokens[std::size_t(((s * hw + p) * k.V + v) * (k.C + 1))];
        for (int c = 0; c < k.C; ++c)
          t[c] = samples[std::size_t(((v * k.S + s) * k.C + c) * hw + p)];
        t[k.C] = w[std::size_t((v * k.S + s) * hw + p)];
      }
  const std::vector<double> y =
      va.forward(Tensor::fromHost(tokens, {N, k.V, k.C + 1}, Dtype::F64)).toVector();
  std::vector<double> out(std::size_t(k.S * 4 * k.C * hw));
  for (int s = 0; s < k.S; ++s)
    for (int64_t p = 0; p < hw; ++p)
      for (int c = 0; c < k.C; ++c) {
        auto x = [&](int v) { return samples[std::size_t(((v * k.S + s) * k.C + c) * hw + p)]; };
        auto a = [&](int v) { return y[std::size_t(((s * hw + p) * k.V + v) * k.C + c)]; };
        auto wt = [&](int v) { return w[std::size_t((v * k.S + s) * hw + p)]; };
        double m = 0, ma = 0, var = 0, vara = 0;
        for (int v = 0; v < k.V; ++v) {
          m += wt(v) * x(v);
          ma += wt(v) * a(v);
        }
        for (int v = 0; v < k.V; ++v) {
          var += wt(v) * (x(v) - m) * (x(v) - m);
          vara += wt(v) * (a(v) - ma) * (a(v) - ma);
        }
        const std::size_t base = std::size_t(s * 4 * k.C * hw + p);
        out[base + std::size_t(c * hw)] = m;
        out[base + std::size_t((k.C + c) * hw)] = var;
        out[base + std::size_t((2 * k.C + c) * hw)] = ma;
        out[base + std::size_t((3 * k.C + c) * hw)] = vara;
      }
  return out;
}

void scaleProjections(const ParameterStore& store, double factor) {
  for (const char* name : {"a.w_qs.weight", "a.w_ks.weight"}) {
    Tensor t = store.get(name);
    std::vector<double> v = t.toVector();
    for (double& x : v)
      x *= factor;
    t.copyFromHost(v);
  }
  // Non-trivial LayerNorm affine parameters (the defaults are 1 and 0).
  Tensor lw = store.get("a.layer_norm.weight"), lb = store.get("a.layer_norm.bias");
  std::vector<double> wv(std::size_t(lw.numel())), bv(wv.size());
  for (std::size_t i = 0; i < wv.size(); ++i) {
    wv[i] = 0.5 + 0.25 * double(i % 5);
    bv[i] = 0.1 * double(i % 3) - 0.1;
  }
  lw.copyFromHost(wv);
  lb.copyFromHost(bv);
}

void checkCase(const Case& k) {
  SCOPED_TRACE("V " + std::to_string(k.V) + ", S " + std::to_string(k.S) + ", C " +
               std::to_string(k.C) + ", hidden " + std::to_string(k.hidden) + ", logit scale " +
               std::to_string(k.logitScale));
  ocl::NoGradGuard noGrad;
  PoisonScope poison;
  ParameterStore s64(Dtype::F64, 7), s32(Dtype::F32, 7);
  const ViewAttention a64(s64, "a", k.C, k.hidden), a32(s32, "a", k.C, k.hidden);
  scaleProjections(s64, k.logitScale);
  scaleProjections(s32, k.logitScale);
  const std::vector<double> samples =
      Tensor::uniform({k.V, k.S, k.C, k.h, k.w}, -1, 1, 11, Dtype::F64).toVector();
  const std::vector<double> w = viewWeights(k, 12);
  const std::vector<double> want = composed(a64, k, samples, w);
  const ocl::Shape sShape{k.V, k.S, k.C, k.h, k.w}, wShape{k.V, k.S, 1, k.h, k.w};
  const Tensor got64 = a64.aggregate(Tensor::fromHost(samples, sShape, Dtype::F64),
                                     Tensor::fromHost(w, wShape, Dtype::F64));
  const Tensor got32 = a32.aggregate(Tensor::fromHost(samples, sShape, Dtype::F32),
                                     Tensor::fromHost(w, wShape, Dtype::F32));
  ASSERT_EQ(got64.shape(), (ocl::Shape{k.S, 4 * k.C, k.h, k.w}));
  const std::vector<double> g64 = got64.toVector(), g32 = got32.toVector();
  double e64 = 0, e32 = 0, scale = 0;
  for (std::size_t i = 0; i < want.size(); ++i) {
    ASSERT_TRUE(std::isfinite(g64[i]) && std::isfinite(g32[i])) << "element " << i;
    e64 = std::max(e64, std::abs(g64[i] - want[i]));
    e32 = std::max(e32, std::abs(g32[i] - want[i]));
    scale = std::max(scale, std::abs(want[i]));
  }
  EXPECT_GT(scale, 0.1); // the comparison is not between zeros
  EXPECT_LT(e64, 1e-12 * std::max(1.0, k.logitScale));
  EXPECT_LT(e32, 2e-5 * std::max(1.0, k.logitScale));
}

TEST(ViewAggregation, FusedMatchesComposedInDouble) {
  checkCase({8, 4, 6, 16, 5, 7, 1});   // the official sizes
  checkCase({1, 2, 6, 16, 3, 4, 1});   // one view: variance 0, attention = identity weights
  checkCase({3, 1, 3, 5, 6, 5, 1});    // other channel and hidden sizes
  checkCase({16, 2, 6, 16, 4, 3, 1});  // the most views the numerics table uses
  checkCase({5, 2, 6, 16, 4, 4, 300}); // large logits: the softmax saturates, stays finite
}

TEST(ViewAggregation, RefusesWhatItCannotDo) {
  ParameterStore store(Dtype::F64, 3);
  const ViewAttention va(store, "a", 6, 16);
  const Tensor samples = Tensor::uniform({4, 2, 6, 3, 3}, -1, 1, 1, Dtype::F64);
  const Tensor weights = Tensor::uniform({4, 2, 1, 3, 3}, 0, 1, 2, Dtype::F64);
  {
    ocl::NoGradGuard noGrad;
    test::expectError(
        [&] {
          va.aggregate(Tensor::zeros({4, 2, 5, 3, 3}, Dtype::F64), weights);
        },
        {"ViewAttention::aggregate", "samples", "[V, S, 6, h, w]"});
    test::expectError(
        [&] {
          va.aggregate(samples, Tensor::zeros({4, 2, 1, 3, 2}, Dtype::F64));
        },
        {"ViewAttention::aggregate", "weights", "f64[4, 2, 1, 3, 3]"});
    test::expectError([&] { va.aggregate(samples.to(Dtype::F32), weights.to(Dtype::F32)); },
                      {"ViewAttention::aggregate", "f32[4, 2, 6, 3, 3]", "f64"});
    const int tooMany = ViewAttention::kMaxFusedViews + 1;
    test::expectError(
        [&] {
          va.aggregate(Tensor::zeros({tooMany, 1, 6, 1, 1}, Dtype::F64),
                       Tensor::zeros({tooMany, 1, 1, 1, 1}, Dtype::F64));
        },
        {"ViewAttention::aggregate", std::to_string(tooMany) + " views"});
  }
  // The parameters require gradients and recording is on: training must use the composed form.
  test::expectError([&] { va.aggregate(samples, weights); },
                    {"ViewAttention::aggregate", "gradient", "forward only"});
}

} // namespace
} // namespace simpli::network

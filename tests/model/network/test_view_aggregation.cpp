// ViewAttention::aggregate (the fused kernels) against the composed form written out in double:
// ViewAttention::forward on the [samples | weight] tokens, then the weighted mean and variance
// over the views, for view counts 1 .. 16, channel and hidden sizes other than the official
// ones, views with zero weight, large logits, and float32 against float64. Its backward
// against the composed form's autograd (every input and parameter) and central differences.
#include "support/expect_error.h"

#include "simpli/model/network/attention.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_reshape.h"
#include "simpli/ocl/ops_shape.h"

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
}

// ---- gradients --------------------------------------------------------------------------

// The composed form as autograd ops (generator/mli_corrections.cpp's composedAggregation).
Tensor composedOps(const ViewAttention& va, const Tensor& samples, const Tensor& weights) {
  const int64_t V = samples.size(0), S = samples.size(1), C = samples.size(2);
  const int64_t h = samples.size(3), w = samples.size(4);
  auto meanVar = [&](const Tensor& x) {
    const Tensor mean = ocl::sum(ocl::mul(x, weights), 0);
    const Tensor centred = ocl::sub(x, ocl::unsqueeze(mean, 0));
    return std::vector<Tensor>{mean, ocl::sum(ocl::mul(ocl::square(centred), weights), 0)};
  };
  const Tensor tokens = ocl::reshape(
      ocl::permute(ocl::concat({samples, weights}, 2), {1, 3, 4, 0, 2}), {S * h * w, V, C + 1});
  const Tensor perView =
      ocl::permute(ocl::reshape(va.forward(tokens), {S, h, w, V, C}), {3, 0, 4, 1, 2});
  std::vector<Tensor> parts = meanVar(samples);
  for (const Tensor& t : meanVar(perView))
    parts.push_back(t);
  return ocl::concat(parts, 1);
}

// The gradients of sum(out * probe) for the samples, the weights and every parameter.
struct Gradients {
  std::vector<std::vector<double>> values;
  std::vector<std::string> names;
};

Gradients gradients(ParameterStore& store, const ViewAttention& va, const Case& k,
                    const std::vector<double>& samples, const std::vector<double>& w,
                    const std::vector<double>& probe, bool fused) {
  store.zeroGrad();
  Tensor x = Tensor::fromHost(samples, {k.V, k.S, k.C, k.h, k.w}, Dtype::F64);
  Tensor wt = Tensor::fromHost(w, {k.V, k.S, 1, k.h, k.w}, Dtype::F64);
  x.setRequiresGrad();
  wt.setRequiresGrad();
  const Tensor out = fused ? va.aggregate(x, wt) : composedOps(va, x, wt);
  ocl::sumAll(ocl::mul(out, Tensor::fromHost(probe, out.shape(), Dtype::F64))).backward();
  Gradients g;
  g.values = {x.grad().toVector(), wt.grad().toVector()};
  g.names = {"samples", "weights"};
  for (const std::string& name : store.names()) {
    g.values.push_back(store.get(name).grad().toVector());
    g.names.push_back(name);
  }
  return g;
}

double maxAbs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v)
    m = std::max(m, std::abs(x));
  return m;
}

// Samples, view weights and the probe that weighs the outputs (the objective sum(out * probe)).
struct GradientInputs {
  std::vector<double> samples, weights, probe;
};

GradientInputs randomInputs(const Case& k, uint64_t seed) {
  return {Tensor::uniform({k.V, k.S, k.C, k.h, k.w}, -1, 1, seed, Dtype::F64).toVector(),
          viewWeights(k, seed + 1),
          Tensor::uniform({k.S, 4 * k.C, k.h, k.w}, -1, 1, seed + 2, Dtype::F64).toVector()};
}

void checkGradients(const Case& k) {
  SCOPED_TRACE("V " + std::to_string(k.V) + ", S " + std::to_string(k.S) + ", C " +
               std::to_string(k.C) + ", " + std::to_string(k.h) + "x" + std::to_string(k.w) +
               ", logit scale " + std::to_string(k.logitScale));
  PoisonScope poison;
  ParameterStore store(Dtype::F64, 7);
  const ViewAttention va(store, "a", k.C, k.hidden);
  scaleProjections(store, k.logitScale);
  const GradientInputs in = randomInputs(k, 11);
  const std::vector<double>&samples = in.samples, &w = in.weights, &probe = in.probe;
  const Gradients want = gradients(store, va, k, samples, w, probe, false);
  const Gradients got = gradients(store, va, k, samples, w, probe, true);
  ASSERT_EQ(got.values.size(), want.values.size());
  for (std::size_t i = 0; i < want.values.size(); ++i) {
    SCOPED_TRACE("gradient of " + want.names[i]);
    ASSERT_EQ(got.values[i].size(), want.values[i].size());
    const double scale = maxAbs(want.values[i]);
    // Every input and parameter is reached, but for one view the softmax is constant: no
    // gradient reaches the query and key projections (in either form).
    const bool unreached =
        k.V == 1 && (want.names[i] == "a.w_qs.weight" || want.names[i] == "a.w_ks.weight");
    EXPECT_GT(scale, unreached ? -1.0 : 1e-3);
    double err = 0;
    for (std::size_t j = 0; j < want.values[i].size(); ++j) {
      ASSERT_TRUE(std::isfinite(got.values[i][j])) << "element " << j;
      err = std::max(err, std::abs(got.values[i][j] - want.values[i][j]));
    }
    EXPECT_LT(err, 1e-11 * std::max(1.0, scale));
  }
}

TEST(ViewAggregation, FusedGradientsMatchComposedAutograd) {
  checkGradients({4, 3, 6, 16, 5, 7, 1}); // 35 pixels: items of 16 pixels with a partial one
  checkGradients({1, 2, 6, 16, 3, 4, 1}); // one view
  checkGradients({3, 1, 3, 5, 6, 5, 1});  // other channel and hidden sizes
  checkGradients({8, 1, 6, 16, 9, 8, 1}); // the official view count, 72 pixels
  checkGradients({5, 2, 6, 16, 4, 4, 6}); // sharp softmax
}

// The fused backward against central differences of the fused forward, for samples, weights
// and the attention's parameters (a few elements of each).
TEST(ViewAggregation, FusedGradientsMatchFiniteDifferences) {
  PoisonScope poison;
  const Case k{3, 2, 6, 16, 4, 5, 1};
  ParameterStore store(Dtype::F64, 5);
  const ViewAttention va(store, "a", k.C, k.hidden);
  scaleProjections(store, 1);
  const GradientInputs in = randomInputs(k, 21);
  const std::vector<double>&samples = in.samples, &w = in.weights, &probe = in.probe;
  const Gradients g = gradients(store, va, k, samples, w, probe, true);
  auto objective = [&](const std::vector<double>& x, const std::vector<double>& wt) {
    ocl::NoGradGuard noGrad;
    const std::vector<double> out =
        va.aggregate(Tensor::fromHost(x, {k.V, k.S, k.C, k.h, k.w}, Dtype::F64),
                     Tensor::fromHost(wt, {k.V, k.S, 1, k.h, k.w}, Dtype::F64))
            .toVector();
    double total = 0;
    for (std::size_t i = 0; i < out.size(); ++i)
      total += out[i] * probe[i];
    return total;
  };
  const double eps = 1e-6;
  auto check = [&](const std::string& what, double analytic, double plus, double minus) {
    const double numeric = (plus - minus) / (2 * eps);
    EXPECT_NEAR(analytic, numeric, 1e-6 * std::max(1.0, std::abs(numeric))) << what;
  };
  for (std::size_t i : {0ul, 17ul, 100ul, samples.size() - 1}) {
    std::vector<double> p = samples, m = samples;
    p[i] += eps;
    m[i] -= eps;
    check("samples " + std::to_string(i), g.values[0][i], objective(p, w), objective(m, w));
  }
  for (std::size_t i : {1ul, 20ul, w.size() - 2}) {
    std::vector<double> p = w, m = w;
    p[i] += eps;
    m[i] -= eps;
    check("weights " + std::to_string(i), g.values[1][i], objective(samples, p),
          objective(samples, m));
  }
  for (std::size_t n = 0; n < store.names().size(); ++n) {
    Tensor param = store.get(store.names()[n]);
    const std::vector<double> base = param.toVector();
    for (std::size_t i : {std::size_t(0), base.size() / 2, base.size() - 1}) {
      std::vector<double> shifted = base;
      shifted[i] = base[i] + eps;
      param.copyFromHost(shifted);
      const double plus = objective(samples, w);
      shifted[i] = base[i] - eps;
      param.copyFromHost(shifted);
      const double minus = objective(samples, w);
      param.copyFromHost(base);
      check(store.names()[n] + " " + std::to_string(i), g.values[2 + n][i], plus, minus);
    }
  }
}

} // namespace
} // namespace simpli::network

// The fused small-sequence attention op against a double-precision reference and finite
// differences, with per-sequence and shared queries, channel counts across the kernel's
// 16-channel tiles, one key, large logits and bad use.
#include "op_harness.h"
#include "test_support.h"

#include "simpli/ocl/ops_attention.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace simpli;
using namespace simpli::test;

namespace {

struct AttentionDims {
  int64_t N, nq, nk, d, dv;
  bool sharedQ;
};

std::vector<double> attentionRef(const HostInputs& in, const AttentionDims& s, double scale) {
  const auto &q = in[0], &k = in[1], &v = in[2];
  std::vector<double> out(static_cast<std::size_t>(s.N * s.nq * s.dv), 0.0);
  for (int64_t n = 0; n < s.N; ++n)
    for (int64_t i = 0; i < s.nq; ++i) {
      const double* qi = q.data() + (s.sharedQ ? i : n * s.nq + i) * s.d;
      std::vector<double> score(static_cast<std::size_t>(s.nk));
      double m = -std::numeric_limits<double>::infinity();
      for (int64_t j = 0; j < s.nk; ++j) {
        double dot = 0;
        for (int64_t c = 0; c < s.d; ++c)
          dot += qi[c] * k[(n * s.nk + j) * s.d + c];
        score[j] = scale * dot;
        m = std::max(m, score[j]);
      }
      double sum = 0;
      for (auto& e : score)
        sum += (e = std::exp(e - m));
      for (int64_t j = 0; j < s.nk; ++j)
        for (int64_t c = 0; c < s.dv; ++c)
          out[(n * s.nq + i) * s.dv + c] += score[j] / sum * v[(n * s.nk + j) * s.dv + c];
    }
  return out;
}

OpCase attentionCase(const AttentionDims& s, double scale) {
  OpCase c;
  c.name = "attention N" + std::to_string(s.N) + " nq" + std::to_string(s.nq) + " nk" +
           std::to_string(s.nk) + " d" + std::to_string(s.d) + " dv" + std::to_string(s.dv) +
           (s.sharedQ ? " shared q" : "");
  c.inputShapes = {
      s.sharedQ ? Shape{s.nq, s.d} : Shape{s.N, s.nq, s.d}, {s.N, s.nk, s.d}, {s.N, s.nk, s.dv}};
  c.device = [scale](const std::vector<ocl::Tensor>& in) {
    return ocl::attention(in[0], in[1], in[2], scale);
  };
  c.reference = [s, scale](const HostInputs& in) { return attentionRef(in, s, scale); };
  c.maxGradientProbes = 24;
  return c;
}

} // namespace

TEST(Attention, AgainstReferenceAndFiniteDifferences) {
  WorstErrors worst{"Attention.AgainstReferenceAndFiniteDifferences"};
  const AttentionDims cases[] = {
      {5, 8, 8, 16, 6, false},  // view attention: V tokens attend to each other
      {7, 4, 41, 10, 10, true}, // anchored ray attention: shared anchors pool 41 planes
      {3, 3, 5, 33, 17, false}, // channels across two and a half 16-channel tiles
      {2, 1, 1, 1, 1, false},   // one key: the output is that key's value
      {1, 2, 3, 4, 19, true},
      {2, 3, 32, 4, 5, false},  // the most keys whose weights stay in registers (ATT_MAXK)
      {2, 3, 33, 4, 5, false}}; // one more: the recomputing path
  for (const auto& s : cases)
    worst.add(checkOp(attentionCase(s, 1.0 / std::sqrt(double(s.d)))));
}

TEST(Attention, LargeLogitsGiveFiniteHardAttention) {
  // Scores of +-1e4 and more: the softmax subtracts the maximum, so the output is the value of
  // the best-matching key instead of NaN.
  const ocl::Tensor q = ocl::Tensor::fromHost(std::vector<double>{1e3, 0}, {1, 1, 2});
  const ocl::Tensor k =
      ocl::Tensor::fromHost(std::vector<double>{-1e3, 0, 1e3, 0, 0, 5}, {1, 3, 2});
  const ocl::Tensor v = ocl::Tensor::fromHost(std::vector<double>{-7, 3, 11}, {1, 3, 1});
  const auto out = ocl::attention(q, k, v, 1.0).toVector();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0], 3.0, 1e-6);
}

TEST(Attention, BadUseThrowsNamingOpAndShapes) {
  using ocl::Tensor;
  const Tensor q = Tensor::zeros({2, 3, 4}), k = Tensor::zeros({2, 5, 4}),
               v = Tensor::zeros({2, 5, 6});
  expectError(
      [&] {
        ocl::attention(Tensor::zeros({2, 3, 5}), k, v, 1.0);
      },
      {"attention", "f32[2, 3, 5]", "f32[2, 5, 4]"});
  expectError(
      [&] {
        ocl::attention(q, k, Tensor::zeros({2, 4, 6}), 1.0);
      },
      {"attention", "f32[2, 4, 6]"});
  expectError([&] { ocl::attention(q, Tensor::zeros({5, 4}), v, 1.0); }, {"attention"});
  expectError(
      [&] {
        ocl::attention(q, k, Tensor::zeros({2, 5, 6}, ocl::Dtype::F64), 1.0);
      },
      {"attention", "dtypes"});
  expectError([&] { ocl::attention(q, k, v, std::nan("")); }, {"attention", "scale"});
  expectError([&] { ocl::attention(Tensor::zeros({2, 0, 4}), k, v, 1.0); }, {"attention", "empty"});
}

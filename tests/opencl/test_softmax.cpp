// Softmax and log-sum-exp through the harness (every axis position, size-1 axes), extremes
// (logits of +-1e4 and +-1e30 stay finite and give the right one-hot) and bad use.
#include "op_harness.h"
#include "test_support.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_softmax.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;

namespace {

struct Split {
  int64_t outer = 1, n = 1, inner = 1;
};

Split splitAt(const Shape& s, int axis) {
  const int a = axis < 0 ? axis + static_cast<int>(s.size()) : axis;
  Split r;
  for (int d = 0; d < a; ++d)
    r.outer *= s[d];
  r.n = s[a];
  for (std::size_t d = a + 1; d < s.size(); ++d)
    r.inner *= s[d];
  return r;
}

std::vector<double> softmaxRef(const std::vector<double>& x, const Shape& s, int axis) {
  const Split sp = splitAt(s, axis);
  std::vector<double> y(x.size());
  for (int64_t o = 0; o < sp.outer; ++o)
    for (int64_t i = 0; i < sp.inner; ++i) {
      auto at = [&](int64_t k) { return (o * sp.n + k) * sp.inner + i; };
      double m = -std::numeric_limits<double>::infinity(), sum = 0.0;
      for (int64_t k = 0; k < sp.n; ++k)
        m = std::max(m, x[at(k)]);
      for (int64_t k = 0; k < sp.n; ++k)
        sum += std::exp(x[at(k)] - m);
      for (int64_t k = 0; k < sp.n; ++k)
        y[at(k)] = std::exp(x[at(k)] - m) / sum;
    }
  return y;
}

std::vector<double> logSumExpRef(const std::vector<double>& x, const Shape& s, int axis) {
  const Split sp = splitAt(s, axis);
  std::vector<double> out(static_cast<std::size_t>(sp.outer * sp.inner));
  for (int64_t o = 0; o < sp.outer; ++o)
    for (int64_t i = 0; i < sp.inner; ++i) {
      double m = -std::numeric_limits<double>::infinity(), sum = 0.0;
      for (int64_t k = 0; k < sp.n; ++k)
        m = std::max(m, x[(o * sp.n + k) * sp.inner + i]);
      for (int64_t k = 0; k < sp.n; ++k)
        sum += std::exp(x[(o * sp.n + k) * sp.inner + i] - m);
      out[o * sp.inner + i] = m + std::log(sum);
    }
  return out;
}

const std::pair<Shape, int> kCases[] = {{{1}, 0},          {{5}, 0},           {{3, 4}, 0},
                                        {{3, 4}, 1},       {{3, 4}, -1},       {{2, 1, 3, 4}, 1},
                                        {{2, 3, 1, 5}, 2}, {{2, 3, 4, 5}, -1}, {{2, 3, 4, 5}, -3},
                                        {{7, 1}, -1},      {{4, 130}, 1}};

} // namespace

TEST(Softmax, AgainstReferenceAndFiniteDifferences) {
  WorstErrors worst{"Softmax.AgainstReferenceAndFiniteDifferences"};
  for (const auto& [shape, axis] : kCases) {
    OpCase c;
    c.name = "softmax " + ocl::toString(shape) + " axis " + std::to_string(axis);
    c.inputShapes = {shape};
    c.low = -4.0;
    c.high = 4.0;
    c.device = [axis = axis](const std::vector<ocl::Tensor>& in) {
      return ocl::softmax(in[0], axis);
    };
    c.reference = [shape = shape, axis = axis](const HostInputs& in) {
      return softmaxRef(in[0], shape, axis);
    };
    c.maxGradientProbes = 24;
    worst.add(checkOp(c));
  }
}

TEST(Softmax, LogSumExpAgainstReferenceAndFiniteDifferences) {
  WorstErrors worst{"Softmax.LogSumExpAgainstReferenceAndFiniteDifferences"};
  for (bool keepdim : {false, true}) {
    for (const auto& [shape, axis] : kCases) {
      OpCase c;
      c.name = "logSumExp " + ocl::toString(shape) + " axis " + std::to_string(axis) +
               (keepdim ? " keepdim" : "");
      c.inputShapes = {shape};
      c.low = -4.0;
      c.high = 4.0;
      c.device = [axis = axis, keepdim](const std::vector<ocl::Tensor>& in) {
        ocl::Tensor out = ocl::logSumExp(in[0], axis, keepdim);
        Shape expected = in[0].shape();
        const int a = axis < 0 ? axis + in[0].dim() : axis;
        if (keepdim)
          expected[a] = 1;
        else
          expected.erase(expected.begin() + a);
        EXPECT_EQ(out.shape(), expected);
        return out;
      };
      c.reference = [shape = shape, axis = axis](const HostInputs& in) {
        return logSumExpRef(in[0], shape, axis);
      };
      c.maxGradientProbes = 24;
      worst.add(checkOp(c));
    }
  }
}

TEST(Softmax, ExtremeLogitsStayFiniteAndOneHot) {
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    for (double big : {1e4, 1e30}) {
      // Rows: the winner in different positions, losers at -big, 0 or +big / 2.
      const std::vector<double> logits = {big,  -big, 0.0,  -big,       // winner 0
                                          -big, -big, -big, big,        // winner 3
                                          0.0,  big,  -big, big / 2.0}; // winner 1
      const int winner[] = {0, 3, 1};
      // Contiguous slices (axis 1 of [3, 4]) and strided ones (axis 0 of the transpose).
      for (bool strided : {false, true}) {
        SCOPED_TRACE("logit magnitude " + std::to_string(big) + (strided ? " strided" : " rows"));
        std::vector<double> data = logits;
        if (strided)
          for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 4; ++k)
              data[k * 3 + r] = logits[r * 4 + k];
        const Shape shape = strided ? Shape{4, 3} : Shape{3, 4};
        const int axis = strided ? 0 : 1;
        auto at = [strided](int r, int k) { return strided ? k * 3 + r : r * 4 + k; };
        auto x = ocl::Tensor::fromHost(data, shape, dtype).setRequiresGrad(true);
        ocl::Tensor y = ocl::softmax(x, axis);
        const auto yv = y.toVector();
        for (int r = 0; r < 3; ++r)
          for (int k = 0; k < 4; ++k) {
            ASSERT_TRUE(std::isfinite(yv[at(r, k)]));
            EXPECT_EQ(yv[at(r, k)], k == winner[r] ? 1.0 : 0.0) << r << "," << k;
          }
        ocl::Tensor lse = ocl::logSumExp(x, axis);
        const auto lv = lse.toVector();
        for (int r = 0; r < 3; ++r) {
          ASSERT_TRUE(std::isfinite(lv[r]));
          EXPECT_NEAR(lv[r], big, big * 1e-7);
        }
        // Gradients are finite too.
        ocl::Tensor w = ocl::Tensor::uniform(shape, -1, 1, 3, dtype);
        ocl::add(ocl::sumAll(ocl::mul(y, w)), ocl::sumAll(lse)).backward();
        for (double g : x.grad().toVector())
          ASSERT_TRUE(std::isfinite(g));
      }
    }
  }
}

TEST(Softmax, EqualLogitsGiveUniformAndLogN) {
  auto x = ocl::Tensor::full({2, 5}, 1e4, Dtype::F32);
  for (double v : ocl::softmax(x, -1).toVector())
    EXPECT_FLOAT_EQ(v, 0.2);
  for (double v : ocl::logSumExp(x, -1).toVector())
    EXPECT_NEAR(v, 1e4 + std::log(5.0), 1e-3);
}

TEST(Softmax, InfiniteMaximumInLogSumExp) {
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<double> data = {-inf, -inf, 1.0, inf};
  // Rows layout ([2, 2], axis 1) and strided layout (transpose, axis 0).
  for (bool strided : {false, true}) {
    std::vector<double> d = data;
    if (strided)
      d = {data[0], data[2], data[1], data[3]};
    auto x = ocl::Tensor::fromHost(d, {2, 2}, Dtype::F64).setRequiresGrad(true);
    ocl::Tensor lse = ocl::logSumExp(x, strided ? 0 : 1);
    const auto v = lse.toVector();
    EXPECT_EQ(v[0], -inf);
    EXPECT_EQ(v[1], inf);
    lse.backward(ocl::Tensor::ones({2}, Dtype::F64));
    for (double g : x.grad().toVector())
      EXPECT_EQ(g, 0.0); // no NaN from inf - inf or 0 * inf
  }
}

TEST(Softmax, BadUseThrowsNamingOpAndShape) {
  auto x = ocl::Tensor::zeros({2, 3});
  for (int axis : {2, -3}) {
    try {
      ocl::softmax(x, axis);
      FAIL() << "expected simpli::Error";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("softmax"), std::string::npos) << m;
      EXPECT_NE(m.find("[2, 3]"), std::string::npos) << m;
      EXPECT_NE(m.find(std::to_string(axis)), std::string::npos) << m;
    }
  }
  EXPECT_THROW(ocl::logSumExp(x, 5), Error);
  EXPECT_THROW(ocl::softmax(ocl::Tensor(), 0), Error);
  EXPECT_THROW(ocl::softmax(ocl::Tensor::zeros({0, 3}), 1), Error);
  EXPECT_THROW(ocl::logSumExp(ocl::Tensor::zeros({3, 0}), 0), Error);
}

// Reductions through the harness, on shapes that take each kernel layout of reduce.cl: the
// direct per-output loop, the vector blocks (contiguous long axes, with < 4 tail elements) and
// the split axis (few outputs, long strided axis).
#include "op_harness.h"
#include "test_support.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_reduce.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;

namespace {

// f over the axis of x viewed as [outer, n, inner]: f(values) per output.
std::vector<double> axisRef(const std::vector<double>& x, const Shape& s, int axis,
                            double (*f)(const std::vector<double>&)) {
  const int a = axis < 0 ? axis + static_cast<int>(s.size()) : axis;
  int64_t outer = 1, inner = 1;
  for (int d = 0; d < a; ++d)
    outer *= s[d];
  for (std::size_t d = a + 1; d < s.size(); ++d)
    inner *= s[d];
  const int64_t n = s[a];
  std::vector<double> out(static_cast<std::size_t>(outer * inner));
  std::vector<double> values(static_cast<std::size_t>(n));
  for (int64_t o = 0; o < outer; ++o)
    for (int64_t i = 0; i < inner; ++i) {
      for (int64_t k = 0; k < n; ++k)
        values[k] = x[(o * n + k) * inner + i];
      out[o * inner + i] = f(values);
    }
  return out;
}

double sumOf(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v)
    s += x;
  return s;
}
double meanOf(const std::vector<double>& v) {
  return sumOf(v) / static_cast<double>(v.size());
}
double unbiasedVarOf(const std::vector<double>& v) {
  const double m = meanOf(v);
  double ss = 0.0;
  for (double x : v)
    ss += (x - m) * (x - m);
  return ss / static_cast<double>(v.size() - 1);
}
double biasedVarOf(const std::vector<double>& v) {
  return unbiasedVarOf(v) * static_cast<double>(v.size() - 1) / static_cast<double>(v.size());
}

// (shape, axis): direct, blocks (inner == 1, n >= 512, odd n for a tail), split (few outputs).
const std::pair<Shape, int> kAxisCases[] = {
    {{1}, 0},          {{7}, 0},         {{3, 4}, 0},        {{3, 4}, -1}, {{2, 1, 5}, 1},
    {{2, 3, 4, 5}, 2}, {{3, 1001}, 1},   {{2, 2, 4099}, -1}, {{5003}, 0},  {{701, 3}, 0},
    {{2, 1200, 5}, 1}, {{4, 300, 7}, 1}, {{1, 70, 1, 1}, 1}};

} // namespace

TEST(Reduce, SumMeanVarianceAgainstReference) {
  WorstErrors worst{"Reduce.SumMeanVarianceAgainstReference"};
  struct Fn {
    const char* name;
    std::function<ocl::Tensor(const ocl::Tensor&, int)> op;
    double (*ref)(const std::vector<double>&);
  };
  const Fn fns[] = {
      {"sum", [](const ocl::Tensor& x, int a) { return ocl::sum(x, a); }, sumOf},
      {"mean", [](const ocl::Tensor& x, int a) { return ocl::mean(x, a, true); }, meanOf},
      {"variance unbiased", [](const ocl::Tensor& x, int a) { return ocl::variance(x, a, true); },
       unbiasedVarOf},
      {"variance biased", [](const ocl::Tensor& x, int a) { return ocl::variance(x, a, false); },
       biasedVarOf},
  };
  for (const auto& fn : fns) {
    for (const auto& [shape, axis] : kAxisCases) {
      const int a = axis < 0 ? axis + static_cast<int>(shape.size()) : axis;
      if (std::string(fn.name) == "variance unbiased" && shape[a] < 2)
        continue;
      OpCase c;
      c.name = std::string(fn.name) + " " + ocl::toString(shape) + " axis " + std::to_string(axis);
      c.inputShapes = {shape};
      c.device = [&fn, axis = axis](const std::vector<ocl::Tensor>& in) {
        return fn.op(in[0], axis);
      };
      c.reference = [&fn, shape = shape, axis = axis](const HostInputs& in) {
        return axisRef(in[0], shape, axis, fn.ref);
      };
      c.prepare = [](HostInputs& in) {
        for (auto& x : in[0])
          x += 3.0; // an offset, so variance must centre
      };
      c.maxGradientProbes = 12;
      c.step = 1e-4; // sums over thousands of elements: keep the quotient above round-off
      worst.add(checkOp(c));
    }
  }
}

TEST(Reduce, SumAllAndMeanAllAgainstReference) {
  WorstErrors worst{"Reduce.SumAllAndMeanAllAgainstReference"};
  const Shape shapes[] = {{1}, {3, 5}, {2, 1, 511}, {1, 4099}, {3, 40, 50}};
  for (const auto& shape : shapes) {
    for (bool isMean : {false, true}) {
      OpCase c;
      c.name = std::string(isMean ? "meanAll " : "sumAll ") + ocl::toString(shape);
      c.inputShapes = {shape};
      c.device = [isMean](const std::vector<ocl::Tensor>& in) {
        return isMean ? ocl::meanAll(in[0]) : ocl::sumAll(in[0]);
      };
      c.reference = [isMean](const HostInputs& in) {
        return std::vector<double>{isMean ? meanOf(in[0]) : sumOf(in[0])};
      };
      c.maxGradientProbes = 12;
      c.step = 1e-4;
      worst.add(checkOp(c));
    }
  }
}

TEST(Reduce, LargeSumsAreAccurateAndDeterministic) {
  // 6M floats in float32: blocked partial sums keep the error near float rounding of the
  // result, and the fixed summation order gives the same bits every run.
  const int64_t n = 12LL * 41 * 96 * 128;
  auto x = ocl::Tensor::uniform({n}, 0.0, 1.0, 17, Dtype::F32);
  auto x64 = ocl::Tensor::fromHost(x.toVector(), {n}, Dtype::F64);
  const double exact = ocl::sumAll(x64).item();
  const double s1 = ocl::sumAll(x).item(), s2 = ocl::sumAll(x).item();
  EXPECT_EQ(s1, s2);
  EXPECT_NEAR(s1, exact, exact * 2e-7);
  const double v = ocl::variance(x.viewAs({1, n}), 1, true).item();
  EXPECT_NEAR(v, ocl::variance(x64.viewAs({1, n}), 1, true).item(), 1e-6);
  EXPECT_NEAR(v, 1.0 / 12.0, 1e-3);
}

TEST(Reduce, BadUseThrows) {
  auto x = ocl::Tensor::zeros({2, 3});
  EXPECT_THROW(ocl::sum(x, 2), Error);
  EXPECT_THROW(ocl::mean(x, -3), Error);
  EXPECT_THROW(ocl::variance(ocl::Tensor::zeros({2, 1}), 1, true), Error);
  EXPECT_THROW(ocl::sum(ocl::Tensor::zeros({2, 0}), 1), Error);
  EXPECT_THROW(ocl::meanAll(ocl::Tensor::zeros({0})), Error);
  EXPECT_EQ(ocl::sumAll(ocl::Tensor::zeros({0, 3})).item(), 0.0);
}

TEST(Reduce, ExpandAgainstReferenceAndFiniteDifferences) {
  // expand is a broadcast copy; its gradient sums over the expanded dimensions (this caught a
  // tape bug: the node was recorded inside a no-grad scope and so never recorded).
  struct Case {
    Shape from, to;
  };
  const Case cases[] = {{{3, 1}, {3, 4}}, {{1, 5}, {2, 3, 5}}, {{2, 1, 3}, {2, 4, 3}}, {{1}, {7}}};
  for (const auto& [from, to] : cases) {
    OpCase c;
    c.name = "expand " + ocl::toString(from) + " -> " + ocl::toString(to);
    c.inputShapes = {from};
    c.device = [to = to](const std::vector<ocl::Tensor>& in) { return ocl::expand(in[0], to); };
    c.reference = [from = from, to = to](const HostInputs& in) {
      // Right-aligned broadcast of `from` to `to`.
      const std::size_t pad = to.size() - from.size();
      int64_t n = 1;
      for (int64_t d : to)
        n *= d;
      std::vector<double> out(static_cast<std::size_t>(n));
      for (int64_t i = 0; i < n; ++i) {
        int64_t rest = i, src = 0, stride = 1;
        for (int d = static_cast<int>(to.size()) - 1; d >= 0; --d) {
          const int64_t coord = rest % to[d];
          rest /= to[d];
          if (d >= static_cast<int>(pad)) {
            const int64_t fd = from[d - pad];
            src += (fd == 1 ? 0 : coord) * stride;
            stride *= fd;
          }
        }
        out[i] = in[0][src];
      }
      return out;
    };
    checkOp(c);
  }
}

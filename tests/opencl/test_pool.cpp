// Max and average pooling through the harness (odd sizes, overlapping windows, leftover rows,
// size-1 dims), tie and NaN behaviour of max pooling, and bad use.
#include "op_harness.h"
#include "test_support.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_pool.h"
#include "simpli/ocl/ops_reduce.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <string>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;

namespace {

struct PoolCase {
  Shape shape;
  int kh, kw, sh, sw;
};

const PoolCase kCases[] = {
    {{2, 3, 7, 9}, 2, 2, 2, 2}, // leftover row and column
    {{1, 1, 5, 5}, 3, 3, 1, 1}, // overlapping windows
    {{2, 2, 6, 7}, 2, 3, 1, 2}, // anisotropic
    {{1, 2, 3, 3}, 3, 3, 3, 3}, // one window
    {{3, 1, 4}, 1, 2, 1, 2},    // rank 3, kernel height 1
    {{1, 1, 1, 1, 4, 6}, 2, 2, 2, 2},
};

std::vector<double> poolRef(const std::vector<double>& x, const PoolCase& k, bool isMax) {
  const int64_t h = k.shape[k.shape.size() - 2], w = k.shape.back();
  const int64_t planes = ocl::numelOf(k.shape) / (h * w);
  const int64_t oh = (h - k.kh) / k.sh + 1, ow = (w - k.kw) / k.sw + 1;
  std::vector<double> out;
  for (int64_t b = 0; b < planes; ++b)
    for (int64_t p = 0; p < oh; ++p)
      for (int64_t q = 0; q < ow; ++q) {
        double acc = isMax ? -INFINITY : 0.0;
        for (int dy = 0; dy < k.kh; ++dy)
          for (int dx = 0; dx < k.kw; ++dx) {
            const double v = x[(b * h + p * k.sh + dy) * w + q * k.sw + dx];
            acc = isMax ? std::max(acc, v) : acc + v;
          }
        out.push_back(isMax ? acc : acc / (k.kh * k.kw));
      }
  return out;
}

Shape outShapeOf(const PoolCase& k) {
  Shape s = k.shape;
  s[s.size() - 2] = (s[s.size() - 2] - k.kh) / k.sh + 1;
  s.back() = (s.back() - k.kw) / k.sw + 1;
  return s;
}

} // namespace

TEST(Pool, MaxPoolAgainstReference) {
  for (const auto& k : kCases) {
    OpCase c;
    c.name = "maxPool2d " + ocl::toString(k.shape);
    c.inputShapes = {k.shape};
    c.device = [k](const std::vector<ocl::Tensor>& in) {
      return ocl::maxPool2d(in[0], k.kh, k.kw, k.sh, k.sw);
    };
    c.reference = [k](const HostInputs& in) { return poolRef(in[0], k, true); };
    // Distinct values spaced far beyond the finite-difference step, so no window's argmax
    // changes under a probe.
    c.prepare = [](HostInputs& in) {
      std::vector<double>& x = in[0];
      std::vector<std::size_t> order(x.size());
      std::iota(order.begin(), order.end(), 0);
      std::shuffle(order.begin(), order.end(), std::mt19937_64(7));
      for (std::size_t i = 0; i < x.size(); ++i)
        x[order[i]] = -2.0 + 4.0 * static_cast<double>(i) / static_cast<double>(x.size());
    };
    checkOp(c);
  }
}

TEST(Pool, AvgPoolAgainstReference) {
  for (const auto& k : kCases) {
    OpCase c;
    c.name = "avgPool2d " + ocl::toString(k.shape);
    c.inputShapes = {k.shape};
    c.device = [k](const std::vector<ocl::Tensor>& in) {
      return ocl::avgPool2d(in[0], k.kh, k.kw, k.sh, k.sw);
    };
    c.reference = [k](const HostInputs& in) { return poolRef(in[0], k, false); };
    checkOp(c);
    EXPECT_EQ(ocl::avgPool2d(ocl::Tensor::zeros(k.shape), k.kh, k.kw, k.sh, k.sw).shape(),
              outShapeOf(k));
  }
}

TEST(Pool, MaxPoolTiesSendTheGradientToTheFirstMaximum) {
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    // Overlapping 2x2 windows, stride 1, on a constant 3x3 image: every window's first element
    // (row-major) is its maximum, so the gradient lands on the top-left 2x2 block only.
    ocl::Tensor x = ocl::Tensor::full({1, 1, 3, 3}, 0.5, dtype);
    x.setRequiresGrad(true);
    ocl::Tensor y = ocl::maxPool2d(x, 2, 1);
    ocl::Tensor w = ocl::Tensor::fromHost(std::vector<double>{1, 2, 3, 4}, {1, 1, 2, 2}, dtype);
    ocl::sumAll(ocl::mul(y, w)).backward();
    EXPECT_EQ(x.grad().toVector(), (std::vector<double>{1, 2, 0, 3, 4, 0, 0, 0, 0}));
  }
}

TEST(Pool, MaxPoolPropagatesNaN) {
  ocl::Tensor x = ocl::Tensor::fromHost(std::vector<double>{1, NAN, 3, 4}, {1, 1, 2, 2});
  EXPECT_TRUE(std::isnan(ocl::maxPool2d(x, 2, 2).item()));
}

TEST(Pool, BadUseThrowsNamingOpAndShapes) {
  auto x = ocl::Tensor::zeros({1, 2, 3, 4});
  expectError([&] { ocl::maxPool2d(x, 4, 1); }, {"maxPool2d", "4x4", "[1, 2, 3, 4]"});
  expectError([&] { ocl::avgPool2d(x, 2, 5, 1, 1); }, {"avgPool2d", "2x5", "[1, 2, 3, 4]"});
  expectError([&] { ocl::maxPool2d(x, 0, 1); }, {"maxPool2d", "[1, 2, 3, 4]"});
  expectError([&] { ocl::avgPool2d(x, 2, 0); }, {"avgPool2d", "stride", "[1, 2, 3, 4]"});
  expectError([] { ocl::maxPool2d(ocl::Tensor::zeros({5}), 1, 1); }, {"maxPool2d", "[5]"});
  expectError(
      [] {
        ocl::maxPool2d(ocl::Tensor::zeros({0, 2, 2}), 1, 1);
      },
      {"maxPool2d", "zero-size", "[0, 2, 2]"});
  expectError([] { ocl::avgPool2d(ocl::Tensor(), 1, 1); }, {"avgPool2d", "undefined"});
}

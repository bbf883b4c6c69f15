// Elementwise ops through the harness: broadcasting shapes with size-1 and odd dimensions,
// unary functions, and their extremes.
#include "op_harness.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;

namespace {

// Reference broadcasting on the host (NumPy rules).
std::vector<double> broadcastRef(const HostInputs& in, const Shape& a, const Shape& b,
                                 double (*f)(double, double)) {
  const Shape out = ocl::broadcastShapes(a, b, "ref");
  const std::size_t rank = out.size();
  auto padded = [rank](Shape s) {
    s.insert(s.begin(), rank - s.size(), 1);
    return s;
  };
  const Shape pa = padded(a), pb = padded(b);
  std::vector<double> result(static_cast<std::size_t>(ocl::numelOf(out)));
  std::vector<int64_t> idx(rank, 0);
  for (std::size_t i = 0; i < result.size(); ++i) {
    int64_t rest = static_cast<int64_t>(i), oa = 0, ob = 0, sa = 1, sb = 1;
    for (int d = static_cast<int>(rank) - 1; d >= 0; --d) {
      const int64_t c = rest % out[d];
      rest /= out[d];
      oa += (pa[d] == 1 ? 0 : c) * sa;
      ob += (pb[d] == 1 ? 0 : c) * sb;
      sa *= pa[d];
      sb *= pb[d];
    }
    result[i] = f(in[0][oa], in[1][ob]);
  }
  return result;
}

struct BinaryCase {
  const char* name;
  ocl::Tensor (*op)(const ocl::Tensor&, const ocl::Tensor&);
  double (*ref)(double, double);
};

const BinaryCase kBinary[] = {
    {"add", ocl::add, [](double a, double b) { return a + b; }},
    {"sub", ocl::sub, [](double a, double b) { return a - b; }},
    {"mul", ocl::mul, [](double a, double b) { return a * b; }},
    {"div", ocl::div, [](double a, double b) { return a / b; }},
    {"maximum", ocl::maximum, [](double a, double b) { return std::max(a, b); }},
    {"minimum", ocl::minimum, [](double a, double b) { return std::min(a, b); }},
};

const std::pair<Shape, Shape> kBroadcastShapes[] = {
    {{7}, {7}},
    {{3, 5}, {3, 5}},
    {{2, 3, 5}, {5}},
    {{2, 1, 5}, {1, 3, 1}},
    {{1}, {4, 1, 3}},
    {{2, 3, 1, 1, 5}, {3, 4, 1, 5}},
    {{1, 1, 2, 1, 3, 2}, {2, 1, 4, 1, 1}},
    // Inner runs of >= 16 (binary_broadcast3_grid): a partial work group of 16, groups of 64
    // with a tail, a broadcast inner dimension.
    {{3, 17}, {17}},
    {{2, 1, 70}, {1, 3, 70}},
    {{5, 40}, {5, 1}},
};

} // namespace

TEST(Elementwise, BinaryOpsBroadcastAgainstReference) {
  for (const auto& op : kBinary) {
    for (const auto& [sa, sb] : kBroadcastShapes) {
      OpCase c;
      c.name = std::string(op.name) + " " + ocl::toString(sa) + " x " + ocl::toString(sb);
      c.inputShapes = {sa, sb};
      c.device = [&op](const std::vector<ocl::Tensor>& in) { return op.op(in[0], in[1]); };
      c.reference = [&op, sa = sa, sb = sb](const HostInputs& in) {
        return broadcastRef(in, sa, sb, op.ref);
      };
      // Keep divisors away from 0 and max/min operands apart (kinks).
      c.prepare = [](HostInputs& in) {
        for (auto& x : in[1])
          x = x >= 0 ? x + 0.5 : x - 0.5;
        for (auto& x : in[0])
          x += 0.1;
      };
      c.maxGradientProbes = 16;
      checkOp(c);
    }
  }
}

namespace {
struct UnaryCase {
  const char* name;
  std::function<ocl::Tensor(const ocl::Tensor&)> op;
  std::function<double(double)> ref;
  double low, high;
};
} // namespace

TEST(Elementwise, UnaryOpsAgainstReference) {
  const UnaryCase cases[] = {
      {"neg", [](const ocl::Tensor& x) { return ocl::neg(x); }, [](double x) { return -x; }, -3, 3},
      {"exp", [](const ocl::Tensor& x) { return ocl::exp(x); },
       [](double x) { return std::exp(x); }, -3, 3},
      {"log", [](const ocl::Tensor& x) { return ocl::log(x); },
       [](double x) { return std::log(x); }, 0.1, 5},
      {"sqrt", [](const ocl::Tensor& x) { return ocl::sqrt(x); },
       [](double x) { return std::sqrt(x); }, 0.1, 5},
      {"square", [](const ocl::Tensor& x) { return ocl::square(x); },
       [](double x) { return x * x; }, -3, 3},
      {"abs", [](const ocl::Tensor& x) { return ocl::abs(x); },
       [](double x) { return std::fabs(x); }, 0.05, 3},
      {"relu", [](const ocl::Tensor& x) { return ocl::relu(x); },
       [](double x) { return x > 0 ? x : 0.0; }, 0.05, 3},
      {"elu", [](const ocl::Tensor& x) { return ocl::elu(x, 1.0); },
       [](double x) { return x > 0 ? x : std::expm1(x); }, -3, 3},
      {"elu0.5", [](const ocl::Tensor& x) { return ocl::elu(x, 0.5); },
       [](double x) { return x > 0 ? x : 0.5 * std::expm1(x); }, -3, 3},
      // float ELU switches from a polynomial to exp(x) - 1 at -1/2; both sides, and values so
      // small that exp(x) - 1 alone would have no correct digit.
      {"elu_near0", [](const ocl::Tensor& x) { return ocl::elu(x, 1.0); },
       [](double x) { return x > 0 ? x : std::expm1(x); }, -0.7, -0.3},
      {"elu_tiny", [](const ocl::Tensor& x) { return ocl::elu(x, 1.0); },
       [](double x) { return x > 0 ? x : std::expm1(x); }, -1e-6, -1e-8},
      {"sigmoid", [](const ocl::Tensor& x) { return ocl::sigmoid(x); },
       [](double x) { return 1 / (1 + std::exp(-x)); }, -6, 6},
      {"tanh", [](const ocl::Tensor& x) { return ocl::tanh(x); },
       [](double x) { return std::tanh(x); }, -3, 3},
      {"softplus", [](const ocl::Tensor& x) { return ocl::softplus(x); },
       [](double x) { return std::log1p(std::exp(x)); }, -5, 5},
      {"addScalar", [](const ocl::Tensor& x) { return ocl::addScalar(x, 1.5); },
       [](double x) { return x + 1.5; }, -3, 3},
      {"mulScalar", [](const ocl::Tensor& x) { return ocl::mulScalar(x, -2.5); },
       [](double x) { return -2.5 * x; }, -3, 3},
      {"powScalar", [](const ocl::Tensor& x) { return ocl::powScalar(x, 1.7); },
       [](double x) { return std::pow(x, 1.7); }, 0.2, 3},
      {"clamp", [](const ocl::Tensor& x) { return ocl::clamp(x, -0.5, 0.7); },
       [](double x) { return std::min(std::max(x, -0.5), 0.7); }, -3, 3},
  };
  const Shape shapes[] = {{1}, {13}, {3, 1, 7}, {2, 3, 1, 5, 1, 3}};
  for (const auto& u : cases) {
    for (const auto& shape : shapes) {
      OpCase c;
      c.name = std::string(u.name) + " " + ocl::toString(shape);
      c.inputShapes = {shape};
      c.low = u.low;
      c.high = u.high;
      c.device = [&u](const std::vector<ocl::Tensor>& in) { return u.op(in[0]); };
      c.reference = [&u](const HostInputs& in) {
        std::vector<double> out(in[0].size());
        for (std::size_t i = 0; i < out.size(); ++i)
          out[i] = u.ref(in[0][i]);
        return out;
      };
      if (std::string(u.name) == "clamp") // keep away from the clamp corners
        c.prepare = [](HostInputs& in) {
          for (auto& x : in[0])
            if (std::fabs(x + 0.5) < 0.05 || std::fabs(x - 0.7) < 0.05)
              x += 0.2;
        };
      c.maxGradientProbes = 16;
      checkOp(c);
    }
  }
}

TEST(Elementwise, ActivationsStayFiniteAtExtremes) {
  const std::vector<double> xs = {-1e30, -1e4, -88.0, -1.0, 0.0, 1.0, 88.0, 1e4, 1e30};
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    ocl::Tensor x = ocl::Tensor::fromHost(xs, {static_cast<int64_t>(xs.size())}, dtype);
    x.setRequiresGrad(true);
    ocl::Tensor s = ocl::sigmoid(x), t = ocl::tanh(x), e = ocl::elu(x), sp = ocl::softplus(x);
    const auto sv = s.toVector(), tv = t.toVector(), ev = e.toVector(), spv = sp.toVector();
    for (std::size_t i = 0; i < xs.size(); ++i) {
      SCOPED_TRACE("x = " + std::to_string(xs[i]));
      EXPECT_TRUE(std::isfinite(sv[i]) && std::isfinite(tv[i]) && std::isfinite(ev[i]));
      EXPECT_NEAR(sv[i], 1 / (1 + std::exp(-xs[i])), 1e-7);
      EXPECT_NEAR(tv[i], std::tanh(xs[i]), 1e-7);
      EXPECT_NEAR(ev[i], xs[i] > 0 ? xs[i] : std::expm1(xs[i]),
                  1e-7 * std::max(1.0, std::fabs(xs[i])));
      const double spRef = std::max(xs[i], 0.0) + std::log1p(std::exp(-std::fabs(xs[i])));
      EXPECT_NEAR(spv[i], spRef, 1e-6 * std::max(1.0, std::fabs(xs[i])));
      EXPECT_TRUE(std::isfinite(spv[i]) || std::fabs(xs[i]) > 1e29);
    }
    // Gradients at the extremes are finite too (0 or 1, never NaN).
    ocl::sumAll(ocl::add(ocl::add(s, t), e)).backward();
    for (double g : x.grad().toVector())
      EXPECT_TRUE(std::isfinite(g));
  }
}

TEST(Elementwise, BadUseThrowsWithOpAndShapes) {
  auto a = ocl::Tensor::zeros({2, 3});
  auto b = ocl::Tensor::zeros({4});
  try {
    ocl::add(a, b);
    FAIL() << "expected an exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("add"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[2, 3]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[4]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ocl::mul(a, ocl::Tensor::zeros({2, 3}, Dtype::F64)), Error);
  EXPECT_THROW(ocl::add(ocl::Tensor(), a), Error);
  EXPECT_THROW(ocl::clamp(a, 1.0, 0.0), Error);
  EXPECT_THROW(ocl::Tensor::empty({-1, 2}), Error);
  EXPECT_THROW(ocl::Tensor::empty({1, 1, 1, 1, 1, 1, 1}), Error);
  EXPECT_THROW(ocl::Tensor::fromHost(std::vector<double>{1, 2, 3}, {2, 2}), Error);
}

TEST(Elementwise, EmptyTensorsAreHandled) {
  auto a = ocl::Tensor::zeros({0, 3});
  auto b = ocl::add(a, ocl::Tensor::ones({3}));
  EXPECT_EQ(b.shape(), (Shape{0, 3}));
  EXPECT_EQ(b.toVector().size(), 0u);
}

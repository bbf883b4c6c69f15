// Gradients of whole small stacks in float64 against central finite differences: every
// parameter of the stack and its input are probed.
#include "simpli/model/geometry/planes.h"
#include "simpli/model/network/attention.h"
#include "simpli/model/network/feature_extractor.h"
#include "simpli/model/network/layers.h"
#include "simpli/model/network/surface_ops.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace simpli::network {
namespace {

using ocl::Dtype;
using ocl::Tensor;

struct Leaf {
  std::string name;
  Tensor tensor;
};

// Checks d(sum(f() * R))/d(leaf) for a few entries of every leaf; R is a fixed random
// projection so that every output element matters.
void gradCheck(const std::function<Tensor()>& f, std::vector<Leaf> leaves, int probes,
               double tol = 1e-6) {
  Tensor R;
  {
    const Tensor y = f();
    R = Tensor::uniform(y.shape(), -1, 1, 77, Dtype::F64);
    for (Leaf& l : leaves)
      l.tensor.zeroGrad();
    ocl::sumAll(ocl::mul(y, R)).backward();
  }
  auto loss = [&] {
    ocl::NoGradGuard noGrad;
    return ocl::sumAll(ocl::mul(f(), R)).item();
  };
  for (Leaf& l : leaves) {
    ASSERT_TRUE(l.tensor.grad().defined()) << l.name << " received no gradient";
    const std::vector<double> analytic = l.tensor.grad().toVector();
    double scale = 1e-3;
    for (double g : analytic)
      scale = std::max(scale, std::abs(g));
    std::vector<double> values = l.tensor.toVector();
    const std::size_t n = values.size();
    const std::size_t count = std::min<std::size_t>(n, static_cast<std::size_t>(probes));
    for (std::size_t k = 0; k < count; ++k) {
      const std::size_t i = (k * n) / count + (n > count ? (k * 7) % (n / count) : 0);
      const double h = 1e-5 * std::max(1.0, std::abs(values[i]));
      const double v = values[i];
      values[i] = v + h;
      l.tensor.copyFromHost(values);
      const double up = loss();
      values[i] = v - h;
      l.tensor.copyFromHost(values);
      const double down = loss();
      values[i] = v;
      l.tensor.copyFromHost(values);
      const double fd = (up - down) / (2 * h);
      EXPECT_NEAR(analytic[i], fd, tol * scale) << l.name << "[" << i << "]";
    }
  }
}

std::vector<Leaf> leavesOf(const ParameterStore& s) {
  std::vector<Leaf> out;
  for (const std::string& name : s.names())
    out.push_back({name, s.get(name)});
  return out;
}

Tensor input(const ocl::Shape& shape, uint64_t seed, double lo = -1, double hi = 1) {
  Tensor x = Tensor::uniform(shape, lo, hi, seed, Dtype::F64);
  x.setRequiresGrad(true);
  return x;
}

TEST(NetGradcheck, ResnetStackAndDecoder2d) {
  ParameterStore s(Dtype::F64, 31);
  const DoubleConvResnet stack(s, "post", 2, 4, {{5, 5}, {5, 5}, {5, 3}});
  const ConvMLP decoder(s, "dec", 3, {{4}, Activation::Relu}, 2);
  const Tensor x = input({2, 4, 5, 6}, 1);
  std::vector<Leaf> leaves = leavesOf(s);
  leaves.push_back({"input", x});
  gradCheck([&] { return decoder.forward(stack.forward(x)); }, leaves, 6);
}

TEST(NetGradcheck, ResnetBlock3dWithAlphaDecoder) {
  ParameterStore s(Dtype::F64, 32);
  const DoubleConvResnet stack(s, "post", 3, 3, {{4, 4}, {4, 2}});
  const ConvMLP alpha(s, "alpha", 2, {{3, 3}, Activation::Elu}, 1);
  const Tensor x = input({1, 3, 3, 4, 5}, 2);
  std::vector<Leaf> leaves = leavesOf(s);
  leaves.push_back({"input", x});
  gradCheck(
      [&] {
        // [1, C, P, h, w] -> planes as a batch for the 2-D decoder, as the network does.
        const Tensor m = ocl::permute(stack.forward(x), {0, 2, 1, 3, 4});
        return alpha.forward(ocl::reshape(m, {3, 2, 4, 5}));
      },
      leaves, 5);
}

TEST(NetGradcheck, FeatureExtractor) {
  ParameterStore s(Dtype::F64, 33);
  FeatureExtractorConfig c;
  c.widths = {2, 3, 3, 2};
  c.headWidth = 3;
  c.descriptors = 2;
  const FeatureExtractor fe(s, "fe", c);
  const Tensor x = input({2, 3, 8, 16}, 3);
  std::vector<Leaf> leaves = leavesOf(s);
  leaves.push_back({"images", x});
  gradCheck([&] { return fe.forward(x); }, leaves, 4);
}

TEST(NetGradcheck, RayAttentionThenDepth) {
  ParameterStore s(Dtype::F64, 34);
  const int P = 9, L = 4, C = 5;
  const AnchoredRayAttention ray(s, "deformer", C, L, 2, 3);
  const ConvMLP depth(s, "depth", C, {{4}, Activation::Relu}, 3); // G = ceil(9 / 4)
  const Tensor planes = input({1, P, C, 2, 3}, 4);
  Tensor positions = ocl::mulScalar(Tensor::arange(P, 0, 1, Dtype::F64), 1.0 / (P - 1));
  positions = positions.clone().detach();
  positions.setRequiresGrad(true);
  const std::vector<double> d = geometry::planeDepths(P, 1.0, 100.0);
  std::vector<Leaf> leaves = leavesOf(s);
  leaves.push_back({"planes", planes});
  leaves.push_back({"positions", positions});
  gradCheck(
      [&] {
        const Tensor layers = ray.forward(planes, positions); // [1, L, C, 2, 3]
        const Tensor logits = depth.forward(ocl::reshape(layers, {L, C, 2, 3}));
        return processDepth(ocl::reshape(logits, {1, L * 3, 2, 3}), d, L);
      },
      leaves, 5);
}

TEST(NetGradcheck, ViewAttentionAndSurfaceOps) {
  ParameterStore s(Dtype::F64, 35);
  const ViewAttention attention(s, "att", 3, 5);
  const Tensor tokens = input({4, 3, 4}, 5);
  const Tensor features = input({1, 4, 2, 2, 3}, 6, -2, 2);
  const Tensor alpha = input({1, 4, 1, 2, 3}, 7, -2, 2);
  const Tensor raw = input({2, 4, 3}, 8, -2, 2);
  std::vector<Leaf> leaves = leavesOf(s);
  leaves.push_back({"tokens", tokens});
  leaves.push_back({"features", features});
  leaves.push_back({"alpha", alpha});
  leaves.push_back({"raw", raw});
  gradCheck(
      [&] {
        const Tensor a = ocl::reshape(attention.forward(tokens), {-1});
        const Tensor b = ocl::reshape(assembleMpi0(features, alpha, 2), {-1});
        const Tensor c = ocl::reshape(activateRgba(raw, 1), {-1});
        return ocl::concat({a, b, c}, 0);
      },
      leaves, 6);
}

} // namespace
} // namespace simpli::network

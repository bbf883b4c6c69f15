// Parameter-free network steps against plain C++ references and their defining properties.
#include "support/expect_error.h"

#include "simpli/model/geometry/planes.h"
#include "simpli/model/network/surface_ops.h"
#include "simpli/ocl/ops_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace simpli::network {
namespace {

using ocl::Dtype;
using ocl::Tensor;
using test::expectError;

std::vector<double> randomValues(std::size_t n, double lo, double hi, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<double> v(n);
  for (double& x : v)
    x = u(rng);
  return v;
}

// §4.9 written out directly, in double.
std::vector<double> referenceDepth(const std::vector<double>& logits, const std::vector<double>& d,
                                   int L, int HW) {
  const int P = static_cast<int>(d.size()), G = (P + L - 1) / L, s = P / L;
  std::vector<double> out(static_cast<std::size_t>(L * HW));
  for (int k = 0; k < L; ++k)
    for (int i = 0; i < HW; ++i) {
      std::vector<double> a(G);
      for (int g = 0; g < G; ++g)
        a[g] = g == 0 ? 1.0 : 1.0 / (1.0 + std::exp(-logits[(k * G + g) * HW + i]));
      const double near = d[k * s + G - 1];
      double D = near;
      for (int g = 0; g < G; ++g) {
        double T = 1.0;
        for (int h = g + 1; h < G; ++h)
          T *= 1.0 - a[h] + 1e-6;
        D += a[g] * T * (d[k * s + g] - near);
      }
      out[k * HW + i] = D;
    }
  return out;
}

TEST(NetProcessDepth, MatchesReferenceFormula) {
  for (int L : {4, 8}) {
    const std::vector<double> depths = geometry::planeDepths(41, 1.0, 100.0);
    const int G = (41 + L - 1) / L, H = 3, W = 5;
    const std::vector<double> logits = randomValues(std::size_t(L * G * H * W), -4, 4, 11 + L);
    const Tensor x = Tensor::fromHost(logits, {1, L * G, H, W}, Dtype::F64);
    const std::vector<double> got = processDepth(x, depths, L).toVector();
    const std::vector<double> want = referenceDepth(logits, depths, L, H * W);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i)
      EXPECT_NEAR(got[i], want[i], 1e-12 * want[i]) << "L " << L << " at " << i;
    const std::vector<double> f32 = processDepth(x.to(Dtype::F32), depths, L).toVector();
    for (std::size_t i = 0; i < got.size(); ++i)
      EXPECT_NEAR(f32[i], want[i], 1e-6 * want[i]);
  }
}

TEST(NetProcessDepth, GroupLimitsAndOrdering) {
  const std::vector<double> d = geometry::planeDepths(41, 1.0, 100.0);
  const int L = 4, G = 11;
  // Transparent groups give each group's far plane (up to the 1e-6 leakage per factor).
  const Tensor transparent = Tensor::full({1, L * G, 2, 2}, -40.0, Dtype::F64);
  const std::vector<double> far = processDepth(transparent, d, L).toVector();
  for (int k = 0; k < L; ++k)
    EXPECT_NEAR(far[k * 4], d[k * 10], 2e-5 * d[k * 10]) << k;
  // An opaque nearest plane gives the group's near plane.
  std::vector<double> v(std::size_t(L * G * 4), -40.0);
  for (int k = 0; k < L; ++k)
    for (int i = 0; i < 4; ++i)
      v[(k * G + G - 1) * 4 + i] = 40.0;
  const std::vector<double> near =
      processDepth(Tensor::fromHost(v, {1, L * G, 2, 2}, Dtype::F64), d, L).toVector();
  // ... up to the +1e-6 inside every transmittance factor, which leaks 1e-6 of the far
  // plane's offset through the opaque near plane.
  for (int k = 0; k < L; ++k) {
    EXPECT_GE(near[k * 4], d[k * 10 + 10]);
    EXPECT_NEAR(near[k * 4], d[k * 10 + 10], 1.1e-6 * (d[k * 10] - d[k * 10 + 10])) << k;
  }
  // Layers never cross (layer 0 farthest).
  const std::vector<double> r =
      processDepth(Tensor::fromHost(randomValues(std::size_t(2 * L * G * 6), -6, 6, 3),
                                    {2, L * G, 2, 3}, Dtype::F64),
                   d, L)
          .toVector();
  for (int b = 0; b < 2; ++b)
    for (int k = 1; k < L; ++k)
      for (int i = 0; i < 6; ++i)
        EXPECT_GE(r[(b * L + k - 1) * 6 + i], r[(b * L + k) * 6 + i]);
}

TEST(NetProcessDepth, BadInputs) {
  const std::vector<double> d = geometry::planeDepths(41, 1.0, 100.0);
  const Tensor x = Tensor::zeros({1, 44, 2, 2});
  expectError(
      [&] {
        processDepth(Tensor::zeros({1, 43, 2, 2}), d, 4);
      },
      {"processDepth", "[B, 44, H, W]", "f32[1, 43, 2, 2]"});
  expectError([&] { processDepth(Tensor::zeros({44, 2, 2}), d, 4); }, {"processDepth"});
  expectError([&] { processDepth(x, geometry::planeDepths(42, 1.0, 100.0), 4); },
              {"42 planes", "4"});
  std::vector<double> bad = d;
  bad[3] = -1.0;
  expectError([&] { processDepth(x, bad, 4); }, {"plane depth -1"});
  expectError([&] { processDepth(x, d, 0); }, {"0 layers"});
}

TEST(NetSurfaceOps, NearPlanesTanhAndMpi0) {
  const int B = 1, P = 5, C = 2, h = 2, w = 3;
  const std::vector<double> v = randomValues(std::size_t(B * P * C * h * w), -3, 3, 5);
  const Tensor m = Tensor::fromHost(v, {B, P, C, h, w}, Dtype::F64);
  const std::vector<double> q = nearPlanesTanh(m, 3).toVector();
  const int per = C * h * w;
  for (int p = 0; p < P; ++p)
    for (int i = 0; i < per; ++i) {
      const double x = v[p * per + i];
      EXPECT_NEAR(q[p * per + i], p >= P - 3 ? std::tanh(x) : x, 1e-15);
    }
  EXPECT_EQ(nearPlanesTanh(m, 0).toVector(), v);
  const std::vector<double> all = nearPlanesTanh(m, P).toVector();
  EXPECT_NEAR(all[0], std::tanh(v[0]), 1e-15);

  const std::vector<double> av = randomValues(std::size_t(B * P * h * w), -3, 3, 6);
  const Tensor alpha = Tensor::fromHost(av, {B, P, 1, h, w}, Dtype::F64);
  const Tensor mpi = assembleMpi0(m, alpha, 3);
  ASSERT_EQ(mpi.shape(), (ocl::Shape{B, P, C + 1, h, w}));
  const std::vector<double> mv = mpi.toVector();
  for (int p = 0; p < P; ++p)
    for (int i = 0; i < h * w; ++i) {
      EXPECT_NEAR(mv[(p * (C + 1) + C) * h * w + i], 1 / (1 + std::exp(-av[p * h * w + i])), 1e-15);
      EXPECT_EQ(mv[(p * (C + 1)) * h * w + i], q[p * per + i]);
    }
  expectError([&] { nearPlanesTanh(m, 6); }, {"nearPlanesTanh", "6 planes"});
  expectError(
      [&] {
        assembleMpi0(m, Tensor::zeros({B, P, 2, h, w}, Dtype::F64), 3);
      },
      {"assembleMpi0", "alpha logits", "[1, 5, 1, 2, 3]"});
}

TEST(NetSurfaceOps, ActivateRgba) {
  const std::vector<double> v = randomValues(2 * 4 * 3, -5, 5, 8);
  const Tensor raw = Tensor::fromHost(v, {2, 4, 3}, Dtype::F64);
  const std::vector<double> out = activateRgba(raw, 1).toVector();
  for (int b = 0; b < 2; ++b)
    for (int c = 0; c < 4; ++c)
      for (int i = 0; i < 3; ++i) {
        const double x = v[(b * 4 + c) * 3 + i];
        EXPECT_NEAR(out[(b * 4 + c) * 3 + i], c < 3 ? std::tanh(x) : 1 / (1 + std::exp(-x)), 1e-15);
      }
  expectError([&] { activateRgba(raw, 2); }, {"activateRgba", "4 channels"});
}

TEST(NetSurfaceOps, PlaneStateIsSinusoidalCodeOfIndex) {
  const std::vector<double> s = planeState(41, 12, Dtype::F64).toVector();
  for (int p = 0; p < 41; ++p)
    for (int c = 0; c < 12; ++c) {
      const double theta = p * std::pow(10000.0, -2.0 * (c / 2) / 12.0);
      EXPECT_NEAR(s[p * 12 + c], c % 2 == 0 ? std::sin(theta) : std::cos(theta), 1e-12);
    }
  expectError([] { planeState(0, 12, Dtype::F32); }, {"planeState"});
}

} // namespace
} // namespace simpli::network

// Module behaviour beyond the golden cases: general sizes against plain C++ references, batch
// and pixel independence, and errors for bad inputs.
#include "support/expect_error.h"

#include "simpli/model/network/attention.h"
#include "simpli/model/network/feature_extractor.h"
#include "simpli/model/network/layers.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include <gtest/gtest.h>

#include <cmath>

namespace simpli::network {
namespace {

using ocl::Dtype;
using ocl::Tensor;
using test::expectError;

double maxDiff(const Tensor& a, const Tensor& b) {
  EXPECT_EQ(a.shape(), b.shape());
  const std::vector<double> x = a.toVector(), y = b.toVector();
  double m = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    m = std::max(m, std::abs(x[i] - y[i]));
  return m;
}

// Multi-head attention written out with loops (reference §4.6), in double.
std::vector<double> referenceAttention(const std::vector<double>& q, const std::vector<double>& x,
                                       const ParameterStore& s, const std::string& p, int N, int nq,
                                       int nk, int in, int heads, int dh, int out) {
  const std::vector<double> wq = s.get(p + ".w_qs.weight").toVector(),
                            wk = s.get(p + ".w_ks.weight").toVector(),
                            wv = s.get(p + ".w_vs.weight").toVector(),
                            fc = s.get(p + ".fc.weight").toVector(),
                            lw = s.get(p + ".layer_norm.weight").toVector(),
                            lb = s.get(p + ".layer_norm.bias").toVector();
  const int hid = heads * dh;
  auto project = [&](const std::vector<double>& w, const double* row) {
    std::vector<double> r(hid, 0.0);
    for (int o = 0; o < hid; ++o)
      for (int i = 0; i < in; ++i)
        r[o] += w[o * in + i] * row[i];
    return r;
  };
  std::vector<double> result(std::size_t(N * nq * out));
  for (int n = 0; n < N; ++n) {
    std::vector<std::vector<double>> K, V;
    for (int j = 0; j < nk; ++j) {
      K.push_back(project(wk, &x[(n * nk + j) * in]));
      V.push_back(project(wv, &x[(n * nk + j) * in]));
    }
    for (int i = 0; i < nq; ++i) {
      const std::vector<double> Q = project(wq, &q[(n * nq + i) * in]);
      std::vector<double> O(hid, 0.0);
      for (int h = 0; h < heads; ++h) {
        std::vector<double> sc(nk);
        double mx = -1e300, sum = 0;
        for (int j = 0; j < nk; ++j) {
          sc[j] = 0;
          for (int c = 0; c < dh; ++c)
            sc[j] += Q[h * dh + c] * K[j][h * dh + c];
          sc[j] /= std::sqrt(double(dh));
          mx = std::max(mx, sc[j]);
        }
        for (double& v : sc)
          sum += (v = std::exp(v - mx));
        for (int j = 0; j < nk; ++j)
          for (int c = 0; c < dh; ++c)
            O[h * dh + c] += sc[j] / sum * V[j][h * dh + c];
      }
      std::vector<double> y(out, 0.0);
      double mean = 0, var = 0;
      for (int o = 0; o < out; ++o) {
        for (int c = 0; c < hid; ++c)
          y[o] += fc[o * hid + c] * O[c];
        mean += y[o] / out;
      }
      for (double v : y)
        var += (v - mean) * (v - mean) / out;
      for (int o = 0; o < out; ++o)
        result[(n * nq + i) * out + o] = (y[o] - mean) / std::sqrt(var + 1e-6) * lw[o] + lb[o];
    }
  }
  return result;
}

// Non-trivial LayerNorm affine parameters (the defaults are 1 and 0).
void setLayerNorm(const ParameterStore& s) {
  Tensor w = s.get("m.layer_norm.weight"), b = s.get("m.layer_norm.bias");
  w.copyFromHost({0.5, 1.5, -1, 2, 0.25, 1});
  b.copyFromHost({0.1, -0.2, 0.3, 0, 0.5, -1});
}

TEST(NetModules, MultiHeadAttentionMatchesLoops) {
  ocl::NoGradGuard noGrad;
  const int N = 3, nq = 2, nk = 5, in = 7, heads = 3, dh = 4, out = 6;
  ParameterStore s(Dtype::F64, 21);
  const MultiHeadAttention mha(s, "m", in, heads, dh, out);
  setLayerNorm(s);
  const Tensor q = Tensor::uniform({N, nq, in}, -2, 2, 1, Dtype::F64);
  const Tensor x = Tensor::uniform({N, nk, in}, -2, 2, 2, Dtype::F64);
  Tensor maps;
  const Tensor y = mha.forward(q, x, &maps);
  ASSERT_EQ(y.shape(), (ocl::Shape{N, nq, out}));
  ASSERT_EQ(maps.shape(), (ocl::Shape{N, heads, nq, nk}));
  const std::vector<double> want =
      referenceAttention(q.toVector(), x.toVector(), s, "m", N, nq, nk, in, heads, dh, out);
  const std::vector<double> got = y.toVector();
  for (std::size_t i = 0; i < got.size(); ++i)
    EXPECT_NEAR(got[i], want[i], 1e-12) << i;
  // Softmax rows sum to one.
  const std::vector<double> rows = ocl::sum(maps, 3).toVector();
  for (double r : rows)
    EXPECT_NEAR(r, 1.0, 1e-12);

  // Shared queries (the anchors' path) equal the same queries given per batch entry.
  const Tensor shared = Tensor::uniform({nq, in}, -2, 2, 3, Dtype::F64);
  Tensor sharedMaps, batchedMaps;
  const Tensor a = mha.forward(shared, x, &sharedMaps);
  const Tensor b =
      mha.forward(ocl::expand(ocl::unsqueeze(shared, 0), {N, nq, in}), x, &batchedMaps);
  EXPECT_LT(maxDiff(a, b), 1e-13);
  EXPECT_LT(maxDiff(sharedMaps, batchedMaps), 1e-13);
  // Float32 agrees with float64.
  ParameterStore s32(Dtype::F32, 21);
  const MultiHeadAttention m32(s32, "m", in, heads, dh, out);
  setLayerNorm(s32);
  EXPECT_LT(maxDiff(m32.forward(q.to(Dtype::F32), x.to(Dtype::F32)), y), 1e-5);

  expectError([&] { mha.forward(q, ocl::slice(x, 2, 0, 6)); },
              {"MultiHeadAttention", "keys/values", "[N, nk, 7]"});
  expectError([&] { mha.forward(ocl::slice(q, 0, 0, 2), x); },
              {"MultiHeadAttention", "queries", "f64[2, 2, 7]"});
}

TEST(NetModules, FeatureExtractorViewsAreIndependent) {
  ocl::NoGradGuard noGrad;
  ParameterStore s(Dtype::F64, 4);
  FeatureExtractorConfig c;
  c.widths = {4, 5, 6, 7};
  c.headWidth = 8;
  c.descriptors = 3;
  const FeatureExtractor fe(s, "fe", c);
  const Tensor images = Tensor::uniform({2, 3, 16, 24}, -1, 1, 5, Dtype::F64);
  const Tensor both = fe.forward(images);
  ASSERT_EQ(both.shape(), (ocl::Shape{2, 6, 8, 12}));
  const Tensor second = fe.forward(ocl::slice(images, 0, 1, 2));
  EXPECT_LT(maxDiff(ocl::slice(both, 0, 1, 2), second), 1e-12);
  // The last three channels are the 2x2 box mean of the image.
  const std::vector<double> img = images.toVector(), out = both.toVector();
  for (int c3 = 0; c3 < 3; ++c3) {
    const double* im = &img[(0 * 3 + c3) * 16 * 24];
    const double box = (im[2 * 24 + 4] + im[2 * 24 + 5] + im[3 * 24 + 4] + im[3 * 24 + 5]) / 4;
    EXPECT_NEAR(out[((0 * 6) + 3 + c3) * 8 * 12 + 1 * 12 + 2], box, 1e-14);
  }
  expectError(
      [&] {
        fe.forward(Tensor::zeros({1, 3, 12, 24}, Dtype::F64));
      },
      {"FeatureExtractor", "12x24", "multiple of 8"});
  expectError(
      [&] {
        fe.forward(Tensor::zeros({1, 4, 16, 24}, Dtype::F64));
      },
      {"FeatureExtractor", "[V, 3, H, W]"});
}

TEST(NetModules, DoubleConvResnetSamplesAreIndependent) {
  ocl::NoGradGuard noGrad;
  ParameterStore s(Dtype::F64, 8);
  const DoubleConvResnet net(s, "r", 2, 5, {{6, 6}, {6, 4}, {4, 3}});
  EXPECT_EQ(net.blocks().size(), 3u);
  EXPECT_EQ(net.outChannels(), 3);
  const Tensor x = Tensor::uniform({3, 5, 6, 7}, -1, 1, 9, Dtype::F64);
  const Tensor y = net.forward(x);
  ASSERT_EQ(y.shape(), (ocl::Shape{3, 3, 6, 7}));
  EXPECT_LT(maxDiff(ocl::slice(y, 0, 2, 3), net.forward(ocl::slice(x, 0, 2, 3))), 1e-12);
  // The 3-D variant normalises over the whole volume: a different plane count changes the
  // output of every plane (no per-plane independence), unlike the 2-D stack above.
  ParameterStore s3(Dtype::F64, 8);
  const DoubleConvResnet vol(s3, "v", 3, 2, {{3, 2}});
  const Tensor v = Tensor::uniform({1, 2, 4, 5, 6}, -1, 1, 10, Dtype::F64);
  EXPECT_EQ(vol.forward(v).shape(), (ocl::Shape{1, 2, 4, 5, 6}));
  EXPECT_GT(maxDiff(ocl::slice(vol.forward(v), 2, 0, 2), vol.forward(ocl::slice(v, 2, 0, 2))),
            1e-6);
  expectError([&] { DoubleConvResnet(s, "e", 2, 5, {}); }, {"DoubleConvResnet", "no blocks"});
}

TEST(NetModules, RayAttentionPixelsAreIndependent) {
  ocl::NoGradGuard noGrad;
  ParameterStore s(Dtype::F64, 12);
  const AnchoredRayAttention ray(s, "d", 6, 3, 2, 5);
  const Tensor planes = Tensor::uniform({1, 9, 6, 4, 5}, -1, 1, 13, Dtype::F64);
  const Tensor positions = ocl::mulScalar(Tensor::arange(9, 0, 1, Dtype::F64), 1.0 / 8);
  const Tensor full = ray.forward(planes, positions);
  ASSERT_EQ(full.shape(), (ocl::Shape{1, 3, 6, 4, 5}));
  const Tensor crop = ray.forward(ocl::slice(ocl::slice(planes, 3, 1, 3), 4, 2, 5), positions);
  EXPECT_LT(maxDiff(ocl::slice(ocl::slice(full, 3, 1, 3), 4, 2, 5), crop), 1e-12);
  // The positional code matters: permuting positions changes the output.
  const Tensor reversed = ocl::indexSelect(positions, 0, {8, 7, 6, 5, 4, 3, 2, 1, 0});
  EXPECT_GT(maxDiff(ray.forward(planes, reversed), full), 1e-3);
  expectError([&] { ray.forward(planes, ocl::slice(positions, 0, 0, 8)); },
              {"AnchoredRayAttention", "positions", "[9]"});
  expectError([&] { ray.forward(ocl::slice(planes, 2, 0, 5), positions); },
              {"AnchoredRayAttention", "[B, P, 6, H, W]"});
  ParameterStore v(Dtype::F64);
  const ViewAttention va(v, "a", 6, 16);
  expectError(
      [&] {
        va.forward(Tensor::zeros({4, 3, 6}, Dtype::F64));
      },
      {"ViewAttention", "[N, V, 7]"});
}

} // namespace
} // namespace simpli::network

// Resize (bilinear, bicubic) and grid sampling through the harness against plain C++
// references written from PyTorch's formulas, plus the spec's bicubic weights (delta images),
// grid points exactly on the border and far outside, the validity mask, and bad use.
#include "op_harness.h"
#include "test_support.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_pool.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_resample.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;

namespace {

// ---- references ---------------------------------------------------------------------------

struct AxisTaps {
  std::array<int64_t, 4> idx{};
  std::array<double, 4> w{};
  int count = 0;
};

// PyTorch's area_pixel_compute_source_index with align_corners = False.
double sourcePosition(int64_t p, int64_t in, int64_t out) {
  return (static_cast<double>(p) + 0.5) * (static_cast<double>(in) / static_cast<double>(out)) -
         0.5;
}

AxisTaps linearTaps(int64_t p, int64_t in, int64_t out) {
  const double s = std::max(sourcePosition(p, in, out), 0.0);
  const auto x0 = static_cast<int64_t>(s);
  const double l = s - static_cast<double>(x0);
  AxisTaps t;
  t.count = 2;
  t.idx = {x0, x0 < in - 1 ? x0 + 1 : x0, 0, 0};
  t.w = {1.0 - l, l, 0, 0};
  return t;
}

double keys(double x) { // A = -0.75
  const double a = -0.75;
  x = std::fabs(x);
  if (x <= 1)
    return ((a + 2) * x - (a + 3)) * x * x + 1;
  if (x < 2)
    return ((a * x - 5 * a) * x + 8 * a) * x - 4 * a;
  return 0.0;
}

AxisTaps cubicTaps(int64_t p, int64_t in, int64_t out) {
  const double s = sourcePosition(p, in, out);
  const double f = std::floor(s);
  const double t = s - f;
  AxisTaps r;
  r.count = 4;
  for (int k = 0; k < 4; ++k) {
    r.idx[k] = std::clamp<int64_t>(static_cast<int64_t>(f) - 1 + k, 0, in - 1);
    r.w[k] = keys(t + 1 - k);
  }
  return r;
}

std::vector<double> resizeRef(const std::vector<double>& x, const Shape& shape, int64_t oh,
                              int64_t ow, bool cubic) {
  const int64_t h = shape[shape.size() - 2], w = shape.back();
  const int64_t planes = ocl::numelOf(shape) / (h * w);
  std::vector<double> out;
  for (int64_t b = 0; b < planes; ++b)
    for (int64_t p = 0; p < oh; ++p)
      for (int64_t q = 0; q < ow; ++q) {
        const AxisTaps ty = cubic ? cubicTaps(p, h, oh) : linearTaps(p, h, oh);
        const AxisTaps tx = cubic ? cubicTaps(q, w, ow) : linearTaps(q, w, ow);
        double acc = 0;
        for (int a = 0; a < ty.count; ++a)
          for (int k = 0; k < tx.count; ++k)
            acc += ty.w[a] * tx.w[k] * x[(b * h + ty.idx[a]) * w + tx.idx[k]];
        out.push_back(acc);
      }
  return out;
}

// F.grid_sample(bilinear, zeros, align_corners=False).
std::vector<double> gridSampleRef(const std::vector<double>& x, const Shape& xs,
                                  const std::vector<double>& grid, const Shape& gs) {
  const int64_t n = xs[0], c = xs[1], h = xs[2], w = xs[3], oh = gs[1], ow = gs[2];
  std::vector<double> out(static_cast<std::size_t>(n * c * oh * ow));
  for (int64_t b = 0; b < n; ++b)
    for (int64_t p = 0; p < oh; ++p)
      for (int64_t q = 0; q < ow; ++q) {
        const int64_t point = (b * oh + p) * ow + q;
        const double sx = ((grid[2 * point] + 1) * w - 1) / 2;
        const double sy = ((grid[2 * point + 1] + 1) * h - 1) / 2;
        const double fx = std::floor(sx), fy = std::floor(sy);
        for (int64_t ch = 0; ch < c; ++ch) {
          double v = 0;
          for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
              const double yy = fy + dy, xx = fx + dx;
              if (yy < 0 || yy >= h || xx < 0 || xx >= w)
                continue;
              const double wgt = (dy ? sy - fy : 1 - (sy - fy)) * (dx ? sx - fx : 1 - (sx - fx));
              v += wgt *
                   x[((b * c + ch) * h + static_cast<int64_t>(yy)) * w + static_cast<int64_t>(xx)];
            }
          out[((b * c + ch) * oh + p) * ow + q] = v;
        }
      }
  return out;
}

struct ResizeCase {
  Shape shape;
  int64_t oh, ow;
};

const ResizeCase kResizeCases[] = {
    {{1, 1, 5, 7}, 10, 14},  // x2 up
    {{2, 3, 8, 6}, 4, 3},    // x0.5 down
    {{1, 2, 7, 5}, 11, 3},   // non-integer ratios, up in one axis and down in the other
    {{1, 2, 1, 5}, 3, 1},    // size-1 input rows and output columns
    {{3, 4}, 1, 1},          // rank 2, down to one pixel
    {{2, 1, 1, 1}, 4, 5},    // constant image
    {{2, 1, 2, 5, 4}, 7, 9}, // rank 5
    {{1, 1, 3, 17}, 3, 4},   // strong down-sampling along W
    {{1, 9, 4, 4}, 5, 4},    // more planes than one work item handles
};

} // namespace

TEST(Resample, ResizeAgainstReference) {
  for (bool cubic : {false, true}) {
    for (const auto& k : kResizeCases) {
      OpCase c;
      c.name = std::string(cubic ? "resizeBicubic " : "resizeBilinear ") + ocl::toString(k.shape) +
               " -> " + std::to_string(k.oh) + "x" + std::to_string(k.ow);
      c.inputShapes = {k.shape};
      c.device = [k, cubic](const std::vector<ocl::Tensor>& in) {
        return cubic ? ocl::resizeBicubic(in[0], k.oh, k.ow)
                     : ocl::resizeBilinear(in[0], k.oh, k.ow);
      };
      c.reference = [k, cubic](const HostInputs& in) {
        return resizeRef(in[0], k.shape, k.oh, k.ow, cubic);
      };
      checkOp(c);
    }
  }
}

TEST(Resample, ResizeGradientEqualsTransposeOnLargerMaps) {
  // <resize(x), g> == <x, resize^T(g)> on sizes with many outputs per input (x3.5 up) and
  // many inputs per output (x0.3 down): exercises the gather ranges of the backward kernels.
  for (bool cubic : {false, true}) {
    for (auto [ih, iw, oh, ow] : {std::array<int64_t, 4>{6, 4, 21, 14}, {20, 30, 6, 9}}) {
      ocl::Tensor x = ocl::Tensor::uniform({2, ih, iw}, -1, 1, 3, Dtype::F64);
      x.setRequiresGrad(true);
      ocl::Tensor g = ocl::Tensor::uniform({2, oh, ow}, -1, 1, 4, Dtype::F64);
      ocl::Tensor y = cubic ? ocl::resizeBicubic(x, oh, ow) : ocl::resizeBilinear(x, oh, ow);
      ocl::sumAll(ocl::mul(y, g)).backward();
      const double lhs = ocl::sumAll(ocl::mul(y, g)).item();
      const double rhs = ocl::sumAll(ocl::mul(x.detach(), x.grad())).item();
      EXPECT_NEAR(lhs, rhs, 1e-12 * std::max(1.0, std::fabs(lhs)))
          << (cubic ? "bicubic " : "bilinear ") << ih << "x" << iw << " -> " << oh << "x" << ow;
    }
  }
}

TEST(Resample, BicubicWeightsMatchTheSpec) {
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    // Plane b holds a delta at column `first + b`; output column q of every plane then reads
    // the four tap weights of q in order.
    auto weightsAt = [dtype](int64_t inW, int64_t outW, int64_t first, int64_t q) {
      std::vector<double> x(4 * inW, 0.0);
      for (int64_t b = 0; b < 4; ++b)
        x[b * inW + first + b] = 1.0;
      const auto y =
          ocl::resizeBicubic(ocl::Tensor::fromHost(x, {4, 1, 1, inW}, dtype), 1, outW).toVector();
      return std::vector<double>{y[q], y[outW + q], y[2 * outW + q], y[3 * outW + q]};
    };
    const double tol = dtype == Dtype::F32 ? 1e-7 : 1e-15;
    // x0.5 (t = 0.5): output 2 sits at source 4.5, taps 3..6.
    const std::vector<double> half = {-0.09375, 0.59375, 0.59375, -0.09375};
    const auto down = weightsAt(8, 4, 3, 2);
    // x2 (t = 0.25): output 7 sits at source 3.25, taps 2..5; output 8 (t = 0.75) mirrors it.
    const std::vector<double> quarter = {-0.10546875, 0.87890625, 0.26171875, -0.03515625};
    const std::vector<double> spec = {-0.10547, 0.87891, 0.26172, -0.03516};
    const auto up = weightsAt(8, 16, 2, 7);
    const auto upMirror = weightsAt(8, 16, 2, 8);
    for (int k = 0; k < 4; ++k) {
      EXPECT_NEAR(down[k], half[k], tol) << "x0.5 tap " << k;
      EXPECT_NEAR(up[k], quarter[k], tol) << "x2 tap " << k;
      EXPECT_NEAR(up[k], spec[k], 5e-6) << "x2 tap " << k << " vs the spec's rounded value";
      EXPECT_NEAR(upMirror[k], quarter[3 - k], tol) << "x2 mirrored tap " << k;
    }
    // Separable in 2-D: a delta at (4, 3) in 8x8 -> 4x4 gives products of the 1-D weights.
    std::vector<double> img(64, 0.0);
    img[4 * 8 + 3] = 1.0;
    const auto y = ocl::resizeBicubic(ocl::Tensor::fromHost(img, {8, 8}, dtype), 4, 4).toVector();
    EXPECT_NEAR(y[2 * 4 + 1], 0.59375 * 0.59375, tol);
    EXPECT_NEAR(y[1 * 4 + 2], 0.09375 * 0.09375, tol);
    EXPECT_NEAR(y[2 * 4 + 2], 0.59375 * -0.09375, tol);
  }
}

TEST(Resample, BilinearHalfIsABoxMeanForEvenSizes) {
  ocl::Tensor x = ocl::Tensor::uniform({2, 3, 6, 8}, -1, 1, 11, Dtype::F64);
  const auto a = ocl::resizeBilinear(x, 3, 4).toVector();
  const auto b = ocl::avgPool2d(x, 2, 2).toVector();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_NEAR(a[i], b[i], 1e-15);
}

TEST(Resample, GridSampleAgainstReference) {
  struct Case {
    Shape input, grid;
  };
  const Case cases[] = {
      {{2, 3, 5, 7}, {2, 4, 6, 2}},
      {{1, 1, 1, 1}, {1, 1, 3, 2}},
      {{2, 2, 3, 1}, {2, 3, 1, 2}},
      {{1, 16, 4, 6}, {1, 2, 3, 2}},
  };
  for (const auto& k : cases) {
    OpCase c;
    c.name = "gridSample " + ocl::toString(k.input) + " grid " + ocl::toString(k.grid);
    c.inputShapes = {k.input, k.grid};
    c.low = -1.3; // some points in the border band and outside the image
    c.high = 1.3;
    c.device = [](const std::vector<ocl::Tensor>& in) { return ocl::gridSample(in[0], in[1]); };
    c.reference = [k](const HostInputs& in) {
      return gridSampleRef(in[0], k.input, in[1], k.grid);
    };
    // Keep every source coordinate's fractional part away from 0 (the kinks of bilinear
    // interpolation) so finite differences see a smooth function.
    c.prepare = [k](HostInputs& in) {
      for (std::size_t i = 0; i < in[1].size(); ++i) {
        const double size = static_cast<double>(i % 2 == 0 ? k.input[3] : k.input[2]);
        const double s = ((in[1][i] + 1) * size - 1) / 2;
        const double frac = s - std::floor(s);
        if (frac < 0.01 || frac > 0.99)
          in[1][i] += 0.05 * 2 / size;
      }
    };
    checkOp(c);
  }
}

TEST(Resample, GridSampleAtPixelCentresEqualsBilinearDownsampling) {
  // Interior sample points: grid_sample at the output pixel centres is the bilinear resize.
  ocl::Tensor x = ocl::Tensor::uniform({1, 2, 8, 8}, -1, 1, 5, Dtype::F64);
  std::vector<double> grid;
  for (int p = 0; p < 4; ++p)
    for (int q = 0; q < 4; ++q) {
      grid.push_back((2.0 * q + 1) / 4 - 1);
      grid.push_back((2.0 * p + 1) / 4 - 1);
    }
  const auto a =
      ocl::gridSample(x, ocl::Tensor::fromHost(grid, {1, 4, 4, 2}, Dtype::F64)).toVector();
  const auto b = ocl::resizeBilinear(x, 4, 4).toVector();
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_NEAR(a[i], b[i], 1e-14);
}

TEST(Resample, GridSampleFarOutsideGivesZerosAndZeroGradients) {
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    const std::vector<double> grid = {1e6, 0, -1e6, 0, 0, 1e6, 0, -1e6, 1e6, 1e6, -1e30, 1e30};
    ocl::Tensor x = ocl::Tensor::uniform({1, 3, 4, 5}, -1, 1, 2, dtype);
    ocl::Tensor g = ocl::Tensor::fromHost(grid, {1, 2, 3, 2}, dtype);
    x.setRequiresGrad(true);
    g.setRequiresGrad(true);
    ocl::Tensor y = ocl::gridSample(x, g);
    for (double v : y.toVector())
      EXPECT_EQ(v, 0.0);
    ocl::sumAll(y).backward();
    for (double v : x.grad().toVector())
      EXPECT_EQ(v, 0.0);
    for (double v : g.grad().toVector())
      EXPECT_EQ(v, 0.0);
  }
}

TEST(Resample, GridSampleOnTheBorderTakesHalfTaps) {
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    // 3x4 image; H = 3 makes gy = 0 the centre of row 1 exactly.
    std::vector<double> img(12);
    for (int i = 0; i < 12; ++i)
      img[i] = 1.0 + i;
    auto at = [&](int r, int c) { return img[r * 4 + c]; };
    const std::vector<double> grid = {1, 0, -1, 0, 1, 1, -1, -1, 0, -1};
    ocl::Tensor x = ocl::Tensor::fromHost(img, {1, 1, 3, 4}, dtype);
    ocl::Tensor g = ocl::Tensor::fromHost(grid, {1, 1, 5, 2}, dtype);
    g.setRequiresGrad(true);
    ocl::Tensor y = ocl::gridSample(x, g);
    const auto v = y.toVector();
    const double tol = dtype == Dtype::F32 ? 1e-6 : 1e-14;
    EXPECT_NEAR(v[0], 0.5 * at(1, 3), tol);                    // right edge
    EXPECT_NEAR(v[1], 0.5 * at(1, 0), tol);                    // left edge
    EXPECT_NEAR(v[2], 0.25 * at(2, 3), tol);                   // bottom-right corner
    EXPECT_NEAR(v[3], 0.25 * at(0, 0), tol);                   // top-left corner
    EXPECT_NEAR(v[4], 0.5 * 0.5 * (at(0, 1) + at(0, 2)), tol); // top edge, between columns
    ocl::sumAll(y).backward();
    const auto gg = g.grad().toVector();
    // At (1, 0): sx = 3.5 between column 3 and the outside, sy = 1 exactly (ty = 0).
    EXPECT_NEAR(gg[0], -at(1, 3) * 4 / 2.0, tol);
    EXPECT_NEAR(gg[1], 0.5 * (at(2, 3) - at(1, 3)) * 3 / 2.0, tol);
    // All values finite.
    for (double d : gg)
      EXPECT_TRUE(std::isfinite(d));
  }
}

TEST(Resample, GridSampleMaskIsInclusive) {
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    const std::vector<double> grid = {1,   1,    -1,  -1, 1.0000002, 0,   0, -1.0000002,
                                      0.3, -0.7, NAN, 0,  -1.5,      0.2, 0, 1e30};
    ocl::Tensor g = ocl::Tensor::fromHost(grid, {2, 2, 2, 2}, dtype);
    ocl::Tensor m = ocl::gridSampleMask(g);
    EXPECT_EQ(m.shape(), (Shape{2, 1, 2, 2}));
    EXPECT_EQ(m.toVector(), (std::vector<double>{1, 1, 0, 0, 1, 0, 0, 0}));
    EXPECT_FALSE(m.requiresGrad());
  }
}

TEST(Resample, BadUseThrowsNamingOpAndShapes) {
  auto x = ocl::Tensor::zeros({1, 2, 3, 4});
  expectError([&] { ocl::resizeBicubic(x, 0, 4); }, {"resizeBicubic", "0x4", "[1, 2, 3, 4]"});
  expectError([&] { ocl::resizeBilinear(x, 3, -1); }, {"resizeBilinear", "[1, 2, 3, 4]"});
  expectError([] { ocl::resizeBilinear(ocl::Tensor::zeros({5}), 2, 2); },
              {"resizeBilinear", "[5]"});
  expectError(
      [] {
        ocl::resizeBicubic(ocl::Tensor::zeros({2, 0, 3}), 2, 2);
      },
      {"resizeBicubic", "[2, 0, 3]"});
  auto grid = ocl::Tensor::zeros({1, 2, 2, 2});
  expectError(
      [&] {
        ocl::gridSample(ocl::Tensor::zeros({2, 3, 4}), grid);
      },
      {"gridSample", "[2, 3, 4]"});
  expectError(
      [&] {
        ocl::gridSample(x, ocl::Tensor::zeros({1, 2, 2, 3}));
      },
      {"gridSample", "[1, 2, 2, 3]"});
  expectError(
      [&] {
        ocl::gridSample(x, ocl::Tensor::zeros({2, 2, 2, 2}));
      },
      {"gridSample", "[1, 2, 3, 4]", "[2, 2, 2, 2]"});
  expectError(
      [&] {
        ocl::gridSample(x, ocl::Tensor::zeros({1, 2, 2, 2}, Dtype::F64));
      },
      {"gridSample", "f64[1, 2, 2, 2]"});
  expectError(
      [&] {
        ocl::gridSample(x, ocl::Tensor::zeros({1, 0, 2, 2}));
      },
      {"gridSample", "zero-size", "[1, 0, 2, 2]"});
  expectError(
      [&] {
        ocl::gridSample(ocl::Tensor::zeros({1, 0, 3, 4}), grid);
      },
      {"gridSample", "[1, 0, 3, 4]"});
  expectError(
      [] {
        ocl::gridSampleMask(ocl::Tensor::zeros({4, 2}));
      },
      {"gridSampleMask", "[4, 2]"});
}

// conv2d / conv3d through the harness: odd sizes, size-1 dimensions, strides, both padding
// modes, with and without bias, 1x1 and 3x3(x3) kernels, column blocks of one row or spanning
// several depth slices; bad use; the column memory bound. Both paths: lowered (im2col + GEMM)
// and direct (conv_direct.cl), each forced, the direct one also against the lowered one in
// float64, and the automatic routing.
#include "op_harness.h"
#include "test_support.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_conv.h"
#include "simpli/ocl/profiler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;
using ocl::PaddingMode;

namespace {

struct ConvSpec {
  Shape x, w;                // 4-D (conv2d) or 5-D (conv3d)
  std::array<int, 3> stride; // per spatial axis; only the trailing ones are used for conv2d
  std::array<int, 3> pad;
  PaddingMode mode;
  bool bias;
};

int spatialOf(const ConvSpec& s) {
  return static_cast<int>(s.x.size()) - 2;
}

// Plain double-precision convolution (cross-correlation), every rank as 3-D.
std::vector<double> convRef(const HostInputs& h, const ConvSpec& s) {
  const int sp = spatialOf(s);
  const int first = 3 - sp; // conv2d: the D axis is absent (size 1, stride 1, no padding)
  const int64_t N = s.x[0], C = s.x[1], O = s.w[0];
  int64_t in[3], k[3], st[3], pd[3], out[3];
  for (int a = 0; a < 3; ++a) {
    const bool present = a >= first;
    in[a] = present ? s.x[2 + a - first] : 1;
    k[a] = present ? s.w[2 + a - first] : 1;
    st[a] = present ? s.stride[a - first] : 1;
    pd[a] = present ? s.pad[a - first] : 0;
    out[a] = (in[a] + 2 * pd[a] - k[a]) / st[a] + 1;
  }
  const bool rep = s.mode == PaddingMode::Replicate;
  std::vector<double> y(static_cast<std::size_t>(N * O * out[0] * out[1] * out[2]));
  std::size_t idx = 0;
  for (int64_t n = 0; n < N; ++n)
    for (int64_t o = 0; o < O; ++o)
      for (int64_t z = 0; z < out[0]; ++z)
        for (int64_t yy = 0; yy < out[1]; ++yy)
          for (int64_t xx = 0; xx < out[2]; ++xx) {
            double acc = s.bias ? h[2][o] : 0.0;
            for (int64_t c = 0; c < C; ++c)
              for (int64_t i = 0; i < k[0]; ++i)
                for (int64_t j = 0; j < k[1]; ++j)
                  for (int64_t l = 0; l < k[2]; ++l) {
                    int64_t q[3] = {z * st[0] - pd[0] + i, yy * st[1] - pd[1] + j,
                                    xx * st[2] - pd[2] + l};
                    bool inside = true;
                    for (int a = 0; a < 3; ++a) {
                      if (rep)
                        q[a] = std::clamp<int64_t>(q[a], 0, in[a] - 1);
                      inside = inside && q[a] >= 0 && q[a] < in[a];
                    }
                    if (!inside)
                      continue;
                    const int64_t xi = (((n * C + c) * in[0] + q[0]) * in[1] + q[1]) * in[2] + q[2];
                    const int64_t wi = (((o * C + c) * k[0] + i) * k[1] + j) * k[2] + l;
                    acc += h[0][static_cast<std::size_t>(xi)] * h[1][static_cast<std::size_t>(wi)];
                  }
            y[idx++] = acc;
          }
  return y;
}

ocl::Tensor runConv(const ConvSpec& s, const std::vector<ocl::Tensor>& t) {
  const ocl::Tensor bias = s.bias ? t[2] : ocl::Tensor();
  if (spatialOf(s) == 2)
    return ocl::conv2d(t[0], t[1], bias, {s.stride[0], s.stride[1]}, {s.pad[0], s.pad[1]}, s.mode);
  return ocl::conv3d(t[0], t[1], bias, s.stride, s.pad, s.mode);
}

std::string describe(const ConvSpec& s) {
  std::string name =
      (spatialOf(s) == 2 ? "conv2d x" : "conv3d x") + ocl::toString(s.x) + " w" +
      ocl::toString(s.w) + " stride " + std::to_string(s.stride[0]) + "," +
      std::to_string(s.stride[1]) + "," + std::to_string(s.stride[2]) + " pad " +
      std::to_string(s.pad[0]) + "," + std::to_string(s.pad[1]) + "," + std::to_string(s.pad[2]) +
      (s.mode == PaddingMode::Replicate ? " replicate" : " zeros") + (s.bias ? " +bias" : "");
  return name;
}

void checkConv(const ConvSpec& s, int probes = 16) {
  OpCase c;
  c.name = describe(s);
  c.inputShapes = {s.x, s.w};
  if (s.bias)
    c.inputShapes.push_back({s.w[0]});
  c.device = [s](const std::vector<ocl::Tensor>& t) { return runConv(s, t); };
  c.reference = [s](const HostInputs& in) { return convRef(in, s); };
  c.maxGradientProbes = probes;
  checkOp(c);
}

const PaddingMode kModes[] = {PaddingMode::Zeros, PaddingMode::Replicate};
const ocl::ConvPath kPaths[] = {ocl::ConvPath::Lowered, ocl::ConvPath::Direct};

const char* pathName(ocl::ConvPath path) {
  switch (path) {
  case ocl::ConvPath::Auto:
    return "auto";
  case ocl::ConvPath::Lowered:
    return "lowered";
  case ocl::ConvPath::Direct:
    return "direct";
  }
  return "?";
}

// Sets the convolution path for a scope (and names it in failure messages).
class PathScope {
public:
  explicit PathScope(ocl::ConvPath path)
      : previous_(ocl::setConvPath(path)), trace_(__FILE__, __LINE__, pathName(path)) {}
  ~PathScope() { ocl::setConvPath(previous_); }
  PathScope(const PathScope&) = delete;
  PathScope& operator=(const PathScope&) = delete;

private:
  ocl::ConvPath previous_;
  ::testing::ScopedTrace trace_;
};

// The convolutions' GEMMs run on both backends: the host BLAS and CLBlast with the skinny kernels.
class ConvGemm : public GemmBackendTest {};
SIMPLI_GEMM_BACKENDS(ConvGemm);

} // namespace

TEST_P(ConvGemm, Conv2dAgainstReference) {
  for (ocl::ConvPath path : kPaths)
    for (PaddingMode mode : kModes) {
      const PathScope scope(path);
      const ConvSpec cases[] = {
          {{1, 1, 1, 1}, {1, 1, 1, 1}, {1, 1, 1}, {0, 0, 0}, mode, true},  // all size 1
          {{2, 3, 5, 7}, {4, 3, 3, 3}, {1, 1, 1}, {1, 1, 0}, mode, true},  // 3x3 pad 1
          {{1, 3, 5, 7}, {2, 3, 3, 3}, {1, 1, 1}, {1, 1, 0}, mode, false}, // no bias
          {{1, 2, 7, 6}, {3, 2, 3, 3}, {2, 2, 1}, {1, 1, 0}, mode, true},  // stride 2
          {{2, 5, 3, 4}, {3, 5, 1, 1}, {1, 1, 1}, {0, 0, 0}, mode, true},  // 1x1 (no im2col)
          {{1, 4, 5, 5}, {2, 4, 1, 1}, {1, 1, 1}, {0, 0, 0}, mode, false}, // 1x1 without bias
          {{1, 3, 5, 7}, {2, 3, 1, 1}, {2, 2, 1}, {0, 0, 0}, mode, true},  // 1x1 stride 2
          {{1, 2, 6, 5}, {3, 2, 2, 3}, {2, 1, 1}, {0, 1, 0}, mode, true},  // 2x3, mixed
          {{1, 1, 2, 2}, {1, 1, 3, 3}, {1, 1, 1}, {1, 1, 0}, mode, true},  // kernel > input
          {{1, 2, 1, 9}, {2, 2, 1, 3}, {1, 1, 1}, {0, 1, 0}, mode, false}, // height 1
          {{1, 2, 4, 4}, {1, 2, 3, 3}, {1, 1, 1}, {2, 2, 0}, mode, true},  // pad 2
      };
      for (const auto& s : cases)
        checkConv(s);
    }
}

TEST_P(ConvGemm, Conv3dAgainstReference) {
  for (ocl::ConvPath path : kPaths)
    for (PaddingMode mode : kModes) {
      const PathScope scope(path);
      const ConvSpec cases[] = {
          {{1, 2, 3, 4, 5}, {3, 2, 3, 3, 3}, {1, 1, 1}, {1, 1, 1}, mode, true},
          {{2, 2, 3, 4, 3}, {2, 2, 3, 3, 3}, {1, 1, 1}, {1, 1, 1}, mode, false},
          {{1, 2, 5, 5, 4}, {2, 2, 3, 3, 3}, {2, 2, 2}, {1, 1, 1}, mode, true},
          {{1, 3, 2, 3, 4}, {2, 3, 1, 1, 1}, {1, 1, 1}, {0, 0, 0}, mode, true},
          {{1, 2, 1, 4, 4}, {2, 2, 1, 3, 3}, {1, 1, 1}, {0, 1, 1}, mode, true},
          {{1, 1, 4, 1, 1}, {1, 1, 3, 1, 1}, {1, 1, 1}, {1, 0, 0}, mode, false},
      };
      for (const auto& s : cases)
        checkConv(s);
    }
}

TEST_P(ConvGemm, SmallColumnBlocksGiveTheSameResult) {
  // One output row per block, then blocks that span depth-slice boundaries (5 rows of a
  // 4-row slice), in both directions of the GEMM and through col2im.
  const ConvSpec specs[] = {
      {{2, 2, 3, 4, 5}, {3, 2, 3, 3, 3}, {1, 1, 1}, {1, 1, 1}, PaddingMode::Replicate, true},
      {{1, 2, 4, 4, 3}, {2, 2, 3, 3, 3}, {1, 2, 1}, {1, 1, 1}, PaddingMode::Zeros, true},
      {{2, 3, 6, 5}, {2, 3, 3, 3}, {1, 1, 1}, {1, 1, 0}, PaddingMode::Replicate, false},
  };
  for (std::size_t rowsPerBlock : {1, 5}) {
    for (const auto& s : specs) {
      const int64_t ck = ocl::numelOf(s.w) / s.w[0];
      const int64_t wo =
          (s.x.back() + 2 * s.pad[spatialOf(s) - 1] - s.w.back()) / s.stride[spatialOf(s) - 1] + 1;
      // Budgets are computed for float and hold for double at half the rows (>= 1).
      const std::size_t previous = ocl::setConvColumnBudget(rowsPerBlock * ck * wo * 4);
      SCOPED_TRACE("rows per block " + std::to_string(rowsPerBlock));
      checkConv(s);
      ocl::setConvColumnBudget(previous);
    }
  }
}

TEST(Conv, ColumnBlocksBoundDeviceMemory) {
  // A full column matrix would be 108 x 8192 floats (3.5 MB); with a 256 KB budget the peak
  // stays well below that.
  const std::size_t previous = ocl::setConvColumnBudget(256 << 10);
  auto x = ocl::Tensor::uniform({1, 4, 8, 32, 32}, -1, 1, 3);
  auto w = ocl::Tensor::uniform({2, 4, 3, 3, 3}, -1, 1, 4);
  auto& pool = ocl::Device::current().pool();
  ocl::Device::current().finish();
  pool.resetPeak();
  const std::size_t before = pool.stats().liveBytes;
  auto y = ocl::conv3d(x, w, ocl::Tensor(), 1, 1, PaddingMode::Replicate);
  ocl::Device::current().finish();
  const std::size_t fullColumns = 108 * 8192 * 4;
  EXPECT_LT(pool.stats().peakBytes - before, fullColumns)
      << "peak " << pool.stats().peakBytes - before << " bytes above the inputs";
  ocl::setConvColumnBudget(previous);
}

TEST(Conv, BadUseNamesOpAndShapes) {
  using ocl::Tensor;
  const Tensor x = Tensor::zeros({1, 3, 5, 5});
  const Tensor w = Tensor::zeros({2, 3, 3, 3});
  expectError(
      [&] {
        ocl::conv2d(x, Tensor::zeros({2, 4, 3, 3}));
      },
      {"conv2d", "[1, 3, 5, 5]", "[2, 4, 3, 3]", "channels"});
  expectError(
      [&] {
        ocl::conv2d(x, Tensor::zeros({2, 3, 7, 7}));
      },
      {"conv2d", "larger", "[2, 3, 7, 7]", "[1, 3, 5, 5]"});
  expectError(
      [&] {
        ocl::conv2d(x, Tensor::zeros({2, 3, 7, 7}), Tensor(), 1, 0, PaddingMode::Replicate);
      },
      {"conv2d", "larger"});
  expectError([&] { ocl::conv2d(Tensor::zeros({3, 5, 5}), w); }, {"conv2d", "[3, 5, 5]"});
  expectError([&] { ocl::conv2d(x, Tensor::zeros({2, 3, 3})); }, {"conv2d", "weight", "[2, 3, 3]"});
  expectError([&] { ocl::conv3d(x, w); }, {"conv3d", "[1, 3, 5, 5]"});
  expectError([&] { ocl::conv2d(x, w, Tensor::zeros({3})); }, {"conv2d", "bias", "[3]"});
  expectError([&] { ocl::conv2d(x, w, Tensor(), 0); }, {"conv2d", "stride", "(0, 0)"});
  expectError([&] { ocl::conv2d(x, w, Tensor(), 1, -1); }, {"conv2d", "padding", "(-1, -1)"});
  expectError(
      [&] {
        ocl::conv2d(x, Tensor::zeros({2, 3, 3, 3}, Dtype::F64));
      },
      {"conv2d", "dtype"});
  expectError([&] { ocl::conv2d(Tensor(), w); }, {"conv2d", "undefined"});
  expectError(
      [&] {
        ocl::conv2d(Tensor::zeros({1, 0, 5, 5}), Tensor::zeros({2, 0, 3, 3}));
      },
      {"conv2d", "channel"});
  expectError(
      [&] {
        ocl::conv3d(Tensor::zeros({1, 3, 2, 5, 5}), Tensor::zeros({2, 3, 3, 3, 3}));
      },
      {"conv3d", "larger", "[1, 3, 2, 5, 5]"});
}

TEST(Conv, EmptyBatchGivesEmptyOutput) {
  auto y = ocl::conv2d(ocl::Tensor::zeros({0, 3, 5, 5}), ocl::Tensor::zeros({2, 3, 3, 3}),
                       ocl::Tensor::zeros({2}), 1, 1);
  EXPECT_EQ(y.shape(), (Shape{0, 2, 5, 5}));
}

TEST_P(ConvGemm, ReplicatePaddingOfAConstantImageIsExact) {
  // With replicate padding a constant input sees the constant at every tap: each output is
  // value * sum(weights) + bias, including at the borders (zero padding would not be).
  auto x = ocl::Tensor::full({1, 2, 4, 5, 6}, 1.5, Dtype::F64);
  auto w = ocl::Tensor::uniform({3, 2, 3, 3, 3}, -1, 1, 9, Dtype::F64);
  auto b = ocl::Tensor::fromHost(std::vector<double>{0.5, -1, 2}, {3}, Dtype::F64);
  auto y = ocl::conv3d(x, w, b, 1, 1, PaddingMode::Replicate).toVector();
  const auto wv = w.toVector();
  for (int o = 0; o < 3; ++o) {
    double sw = 0;
    for (int i = 0; i < 54; ++i)
      sw += wv[o * 54 + i];
    const double expect = 1.5 * sw + std::vector<double>{0.5, -1, 2}[o];
    for (int p = 0; p < 4 * 5 * 6; ++p)
      ASSERT_NEAR(y[o * 120 + p], expect, 1e-12) << "o " << o << " p " << p;
  }
}

namespace {

// Shapes for the direct kernels' own edges: rows wider than one 8-wide vector (interior vector
// loads, stride-2 loads of 16, a partial last vector), channel counts above one block of 16
// (17 -> 2 blocks of 9, 33 -> 3 of 11, with a partial last block), batch > 1, pads larger than
// half the kernel, stride 3 and 5-wide kernels (the per-sample gather), mixed strides.
std::vector<ConvSpec> directCases(PaddingMode mode) {
  return {
      {{2, 17, 5, 21}, {9, 17, 3, 3}, {1, 1, 1}, {1, 1, 0}, mode, true},
      {{2, 3, 7, 37}, {18, 3, 3, 3}, {2, 2, 1}, {1, 1, 0}, mode, true},
      {{1, 4, 4, 19}, {33, 4, 3, 3}, {1, 1, 1}, {1, 1, 0}, mode, false},
      {{1, 2, 6, 23}, {3, 2, 5, 5}, {3, 3, 1}, {2, 2, 0}, mode, true},
      {{1, 2, 5, 11}, {3, 2, 3, 3}, {1, 2, 1}, {2, 2, 0}, mode, true},
      {{2, 5, 3, 4, 19}, {7, 5, 3, 3, 3}, {1, 1, 1}, {1, 1, 1}, mode, true},
      {{1, 3, 5, 4, 37}, {4, 3, 3, 3, 3}, {2, 2, 2}, {1, 1, 1}, mode, false},
      {{1, 2, 4, 5, 17}, {3, 2, 3, 3, 3}, {1, 2, 1}, {1, 0, 2}, mode, true},
  };
}

} // namespace

TEST_P(ConvGemm, DirectPathAgainstReference) {
  const PathScope scope(ocl::ConvPath::Direct);
  for (PaddingMode mode : kModes)
    for (const auto& s : directCases(mode))
      checkConv(s, 24);
}

namespace {

// The forward and all gradients of one case on the current path, in float64.
std::vector<std::vector<double>> runF64(const ConvSpec& s) {
  std::vector<ocl::Tensor> t = {ocl::Tensor::uniform(s.x, -1, 1, 31, Dtype::F64),
                                ocl::Tensor::uniform(s.w, -1, 1, 32, Dtype::F64)};
  if (s.bias)
    t.push_back(ocl::Tensor::uniform({s.w[0]}, -1, 1, 33, Dtype::F64));
  for (auto& v : t)
    v.setRequiresGrad(true);
  const ocl::Tensor y = runConv(s, t);
  y.backward(ocl::Tensor::uniform(y.shape(), -1, 1, 34, Dtype::F64));
  std::vector<std::vector<double>> out = {y.toVector()};
  for (const auto& v : t)
    out.push_back(v.grad().toVector());
  return out;
}

} // namespace

TEST_P(ConvGemm, DirectPathEqualsLoweredPathInFloat64) {
  PoisonGuard poison;
  const char* names[] = {"output", "input gradient", "weight gradient", "bias gradient"};
  for (PaddingMode mode : kModes)
    for (const auto& s : directCases(mode)) {
      SCOPED_TRACE(describe(s));
      std::vector<std::vector<double>> lowered, direct;
      {
        const PathScope scope(ocl::ConvPath::Lowered);
        lowered = runF64(s);
      }
      {
        const PathScope scope(ocl::ConvPath::Direct);
        direct = runF64(s);
      }
      ASSERT_EQ(lowered.size(), direct.size());
      for (std::size_t i = 0; i < lowered.size(); ++i)
        EXPECT_LT(relativeError(direct[i], lowered[i]), 1e-12) << names[i];
    }
}

namespace {

// Names of the kernels one forward and backward of a case launch on the automatic path.
std::vector<std::string> kernelsLaunched(const ConvSpec& s) {
  const PathScope scope(ocl::ConvPath::Auto);
  ocl::Profiler::setEnabled(true);
  ocl::Profiler::reset();
  runF64(s);
  std::vector<std::string> names;
  for (const auto& e : ocl::Profiler::entries())
    names.push_back(e.name);
  ocl::Profiler::setEnabled(false);
  ocl::Profiler::reset();
  return names;
}

bool launched(const std::vector<std::string>& names, const std::string& kernel) {
  return std::find(names.begin(), names.end(), kernel) != names.end();
}

} // namespace

TEST(Conv, AutomaticPathTakesTheDirectKernelsForSmallChannelCounts) {
  const bool wasEnabled = ocl::Profiler::enabled();
  // 16 -> 16 channels, 3x3 (the small configs' convolutions): all three passes direct, no
  // column matrix.
  const auto small = kernelsLaunched(
      {{1, 16, 6, 24}, {16, 16, 3, 3}, {1, 1, 1}, {1, 1, 0}, PaddingMode::Zeros, true});
  EXPECT_TRUE(launched(small, "conv_direct.conv_direct_forward"));
  EXPECT_TRUE(launched(small, "conv_direct.conv_direct_input_grad"));
  EXPECT_TRUE(launched(small, "conv_direct.conv_direct_weight_grad"));
  EXPECT_FALSE(launched(small, "conv.im2col3d"));
  EXPECT_FALSE(launched(small, "conv.col2im3d"));
  // 64 input channels: the input gradient goes lowered, the forward and weight gradient direct.
  const auto mixed = kernelsLaunched(
      {{1, 64, 4, 8}, {16, 64, 3, 3}, {1, 1, 1}, {1, 1, 0}, PaddingMode::Zeros, false});
  EXPECT_TRUE(launched(mixed, "conv_direct.conv_direct_forward"));
  EXPECT_TRUE(launched(mixed, "conv_direct.conv_direct_weight_grad"));
  EXPECT_TRUE(launched(mixed, "conv.col2im3d"));
  // 128 -> 128 channels (the official configs' widths) and x stride 2: the lowered path.
  for (const ConvSpec& s :
       {ConvSpec{{1, 128, 4, 8}, {128, 128, 3, 3}, {1, 1, 1}, {1, 1, 0}, PaddingMode::Zeros, false},
        ConvSpec{{1, 8, 6, 16}, {8, 8, 3, 3}, {1, 2, 1}, {1, 1, 0}, PaddingMode::Zeros, false}}) {
    SCOPED_TRACE(describe(s));
    const auto wide = kernelsLaunched(s);
    EXPECT_FALSE(launched(wide, "conv_direct.conv_direct_forward"));
    EXPECT_FALSE(launched(wide, "conv_direct.conv_direct_weight_grad"));
    EXPECT_TRUE(launched(wide, "conv.im2col3d"));
    EXPECT_TRUE(launched(wide, "conv.col2im3d"));
  }
  ocl::Profiler::setEnabled(wasEnabled);
}

#include "simpli/ocl/ops_conv.h"

#include "clblast_call.h"
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_reduce.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>

namespace simpli::ocl {
namespace {

// Column blocks hold at most this many bytes (per batch item); larger outputs are processed in
// several blocks of whole output rows. 32 MB keeps the GEMMs' N large (>= 2000 columns even
// for 384 channels x 3x3 in float) while a 41 x 96 x 128 volume would need 2 GB at once.
std::size_t columnBudgetBytes = std::size_t{32} << 20;

ConvPath pathFromEnvironment() {
  const char* env = std::getenv("SIMPLI_CONV_DIRECT");
  if (env && std::string(env) == "0")
    return ConvPath::Lowered;
  if (env && std::string(env) == "1")
    return ConvPath::Direct;
  return ConvPath::Auto;
}

ConvPath convPath = pathFromEnvironment();

std::size_t sz(int64_t v) {
  return static_cast<std::size_t>(v);
}

// A convolution of any rank as a 3-D one (conv2d: D = KD = 1).
struct Geometry {
  int64_t N = 0, C = 0, D = 1, H = 0, W = 0, O = 0;
  int64_t KD = 1, KH = 1, KW = 1, SD = 1, SH = 1, SW = 1, PD = 0, PH = 0, PW = 0;
  int64_t Do = 1, Ho = 0, Wo = 0;
  bool replicate = false;
  int64_t ck() const { return C * KD * KH * KW; } // GEMM inner size
  int64_t inP() const { return D * H * W; }       // input positions per channel
  int64_t outP() const { return Do * Ho * Wo; }   // output positions per channel
  bool pointwise() const {
    return KD == 1 && KH == 1 && KW == 1 && SD == 1 && SH == 1 && SW == 1 && PD == 0 && PH == 0 &&
           PW == 0;
  }
};

std::string joined(const int* v, int n) {
  std::ostringstream os;
  os << '(';
  for (int i = 0; i < n; ++i)
    os << (i ? ", " : "") << v[i];
  os << ')';
  return os.str();
}

Geometry checkedGeometry(const char* op, int spatial, const Tensor& x, const Tensor& w,
                         const Tensor& bias, const int* stride, const int* padding,
                         PaddingMode mode) {
  if (!x.defined() || !w.defined())
    fail(op, ": input or weight is undefined");
  const int rank = spatial + 2;
  const char* layout = spatial == 2 ? "[N, C, H, W]" : "[N, C, D, H, W]";
  const char* wlayout = spatial == 2 ? "[O, C, kh, kw]" : "[O, C, kd, kh, kw]";
  if (x.dim() != rank)
    fail(op, ": input ", x.describe(), " must be ", layout);
  if (w.dim() != rank)
    fail(op, ": weight ", w.describe(), " must be ", wlayout);
  if (x.dtype() != w.dtype() || (bias.defined() && bias.dtype() != x.dtype()))
    fail(op, ": dtype mismatch: input ", x.describe(), ", weight ", w.describe(),
         bias.defined() ? ", bias " + bias.describe() : std::string());
  if (x.size(1) != w.size(1))
    fail(op, ": input ", x.describe(), " has ", x.size(1), " channels but weight ", w.describe(),
         " expects ", w.size(1));
  if (x.size(1) == 0 || w.size(0) == 0)
    fail(op, ": input ", x.describe(), " and weight ", w.describe(),
         " must have at least one channel");
  if (bias.defined() && (bias.dim() != 1 || bias.size(0) != w.size(0)))
    fail(op, ": bias ", bias.describe(), " must be [", w.size(0), "] for weight ", w.describe());
  for (int i = 0; i < spatial; ++i) {
    if (stride[i] < 1)
      fail(op, ": stride ", joined(stride, spatial), " must be positive (input ", x.describe(),
           ")");
    if (padding[i] < 0)
      fail(op, ": padding ", joined(padding, spatial), " must not be negative (input ",
           x.describe(), ")");
  }
  Geometry g;
  g.N = x.size(0);
  g.C = x.size(1);
  g.O = w.size(0);
  g.replicate = mode == PaddingMode::Replicate;
  int64_t* in[3] = {&g.D, &g.H, &g.W};
  int64_t* k[3] = {&g.KD, &g.KH, &g.KW};
  int64_t* s[3] = {&g.SD, &g.SH, &g.SW};
  int64_t* p[3] = {&g.PD, &g.PH, &g.PW};
  int64_t* out[3] = {&g.Do, &g.Ho, &g.Wo};
  const int first = 3 - spatial;
  for (int i = 0; i < spatial; ++i) {
    const int64_t n = x.size(2 + i), kk = w.size(2 + i);
    if (kk < 1)
      fail(op, ": weight ", w.describe(), " has an empty kernel");
    if (n < 1 || n + 2 * padding[i] < kk)
      fail(op, ": kernel of weight ", w.describe(), " is larger than the input ", x.describe(),
           " padded by ", joined(padding, spatial));
    *in[first + i] = n;
    *k[first + i] = kk;
    *s[first + i] = stride[i];
    *p[first + i] = padding[i];
    *out[first + i] = (n + 2 * padding[i] - kk) / stride[i] + 1;
  }
  checkedInt(x.numel(), op);
  checkedInt(g.N * g.O * g.outP(), op);
  return g;
}

// Output rows (od, oh flattened) per column block.
int64_t rowsPerBlock(const Geometry& g, Dtype dtype) {
  const int64_t perRow = g.ck() * g.Wo * static_cast<int64_t>(sizeOf(dtype));
  return std::max<int64_t>(1, std::min(g.Do * g.Ho, static_cast<int64_t>(columnBudgetBytes) /
                                                        std::max<int64_t>(perRow, 1)));
}

// The kernels' shared argument run: input sizes, kernel sizes, strides, paddings.
Launch& geometryArgs(Launch& launch, const Geometry& g) {
  for (int64_t v : {g.C, g.D, g.H, g.W, g.KD, g.KH, g.KW, g.SD, g.SH, g.SW, g.PD, g.PH, g.PW})
    launch.arg(static_cast<int>(v));
  return launch;
}

void im2col(const Geometry& g, const Tensor& x, int64_t n, int64_t row0, int64_t rows,
            const Tensor& col) {
  Launch launch("conv", "im2col3d", x.dtype());
  launch.arg(x).arg(static_cast<int>(n * g.C * g.inP()));
  geometryArgs(launch, g)
      .arg(static_cast<int>(g.Ho))
      .arg(static_cast<int>(g.Wo))
      .arg(static_cast<int>(row0))
      .arg(static_cast<int>(rows))
      .arg(g.replicate ? 1 : 0)
      .arg(col)
      .run2(rows, g.ck(), 4, 16);
}

// Input coordinates [lo, hi] that outputs o0..o1 read along one axis.
std::pair<int64_t, int64_t> inputSpan(int64_t o0, int64_t o1, int64_t s, int64_t p, int64_t k,
                                      int64_t n) {
  return {std::clamp<int64_t>(o0 * s - p, 0, n - 1),
          std::clamp<int64_t>(o1 * s - p + k - 1, 0, n - 1)};
}

// The input rows (d, h) the column block of output rows row0 .. row0 + rows reads: d0, dCount,
// h0, hCount.
std::array<int64_t, 4> col2imSpan(const Geometry& g, int64_t row0, int64_t rows) {
  const int64_t od0 = row0 / g.Ho, od1 = (row0 + rows - 1) / g.Ho;
  const auto [d0, d1] = inputSpan(od0, od1, g.SD, g.PD, g.KD, g.D);
  int64_t h0 = 0, h1 = g.H - 1;
  if (od0 == od1)
    std::tie(h0, h1) = inputSpan(row0 % g.Ho, (row0 + rows - 1) % g.Ho, g.SH, g.PH, g.KH, g.H);
  return {d0, d1 - d0 + 1, h0, h1 - h0 + 1};
}

// True when one column block holds all output rows and reads every input row: col2im then
// writes (clears, then accumulates) every element of dx itself, with no zero fill before.
bool col2imCoversInput(const Geometry& g, Dtype dtype) {
  const int64_t totalRows = g.Do * g.Ho;
  if (rowsPerBlock(g, dtype) < totalRows)
    return false;
  const auto [d0, dCount, h0, hCount] = col2imSpan(g, 0, totalRows);
  return d0 == 0 && dCount == g.D && h0 == 0 && hCount == g.H;
}

// Accumulates the column block into dx; with `clear` (col2imCoversInput) its rows are zeroed
// first.
void col2im(const Geometry& g, const Tensor& col, int64_t n, int64_t row0, int64_t rows,
            const Tensor& dx, bool clear) {
  const auto [d0, dCount, h0, hCount] = col2imSpan(g, row0, rows);
  Launch launch("conv", "col2im3d", col.dtype());
  geometryArgs(launch.arg(col), g)
      .arg(static_cast<int>(g.Do))
      .arg(static_cast<int>(g.Ho))
      .arg(static_cast<int>(g.Wo))
      .arg(static_cast<int>(row0))
      .arg(static_cast<int>(rows))
      .arg(g.replicate ? 1 : 0)
      .arg(static_cast<int>(d0))
      .arg(static_cast<int>(dCount))
      .arg(static_cast<int>(h0))
      .arg(static_cast<int>(hCount))
      .arg(dx)
      .arg(static_cast<int>(n * g.C * g.inP()))
      .arg(clear ? 1 : 0)
      .run2(dCount * hCount, g.C, 16, 4);
}

// Calls f(n, row0, rows, p0, chunk) for every batch item and column block.
template <typename F> void forEachBlock(const Geometry& g, Dtype dtype, F f) {
  const int64_t totalRows = g.Do * g.Ho;
  const int64_t perBlock = g.pointwise() ? totalRows : rowsPerBlock(g, dtype);
  for (int64_t n = 0; n < g.N; ++n)
    for (int64_t row0 = 0; row0 < totalRows; row0 += perBlock) {
      const int64_t rows = std::min(perBlock, totalRows - row0);
      f(n, row0, rows, row0 * g.Wo, rows * g.Wo);
    }
}

// ---- the direct path (conv_direct.cl) ------------------------------------------------------

enum class Pass { Forward, InputGrad, WeightGrad };

// True when the direct kernels compute this pass of the convolution. The rule, measured with
// `simpli bench ops --conv-paths` on PoCL (2-core AMD EPYC, AVX-512; docs/benchmarks.md): a
// direct kernel reads its input once per block of 8-16 channels it writes and keeps no column
// matrix, while the lowered path writes and reads the 9x / 27x column matrix once and then runs
// a GEMM that gets efficient as the channel counts grow. With up to 32 output channels the
// direct forward was 1.1-3.6x faster and the direct weight gradient 1.5-3.2x (input channels
// up to 64); with 64 or more output channels both were 0.4-0.9x. The direct input gradient
// (blocked along the input channels, reducing over the output channels) was 1.2-2.3x faster
// with up to 40 input channels, 0.7-1.7x (noise) at 64 and 0.2-0.5x beyond. Along x the
// kernels load vectors at stride 1 only (a larger x stride gathers sample by sample), so other
// strides keep the lowered path.
bool useDirect(const Geometry& g, Pass pass) {
  if (g.pointwise()) // already a plain GEMM, no column matrix
    return false;
  switch (convPath) {
  case ConvPath::Lowered:
    return false;
  case ConvPath::Direct:
    return true;
  case ConvPath::Auto:
    break;
  }
  if (g.SW != 1 || g.O > 32)
    return false;
  return pass != Pass::InputGrad || g.C <= 48;
}

// Channels per work item: all of them up to 16 (BLOCK REAL8 accumulators fit the registers),
// else equal blocks of at most 16.
int64_t channelBlock(int64_t channels) {
  const int64_t blocks = (channels + 15) / 16;
  return (channels + blocks - 1) / blocks;
}

// The direct kernels' geometry run: sizes, kernel (KW is a build option), strides, paddings,
// output sizes, padding mode.
Launch& directGeometryArgs(Launch& launch, const Geometry& g) {
  for (int64_t v : {g.N, g.C, g.D, g.H, g.W, g.O, g.KD, g.KH, g.SD, g.SH, g.SW, g.PD, g.PH, g.PW,
                    g.Do, g.Ho, g.Wo})
    launch.arg(static_cast<int>(v));
  return launch.arg(g.replicate ? 1 : 0);
}

// Output channels per work item of the direct weight gradient (WG_BLOCK): KW x 8 REAL8
// accumulators, 24 of the 32 vector registers for 3-wide kernels.
constexpr int64_t kWeightGradBlock = 8;

// Build options of the direct kernels for blocks of `block` channels.
std::string directOptions(const Geometry& g, int64_t block) {
  return "-DBLOCK=" + std::to_string(block) + " -DKW=" + std::to_string(g.KW) +
         " -DWG_BLOCK=" + std::to_string(kWeightGradBlock);
}

// The weights regrouped for the kernels (conv_direct_weights), blocked along the output
// channels (forward) or the input channels (input gradient).
Tensor regroupedWeights(const Geometry& g, const Tensor& w, int64_t block, bool byInput) {
  const int64_t blocked = byInput ? g.C : g.O, other = byInput ? g.O : g.C;
  const int64_t taps = g.KD * g.KH * g.KW, blocks = (blocked + block - 1) / block;
  Tensor wb = Tensor::empty({blocks * other * taps * block}, w.dtype());
  Launch("conv_direct", "conv_direct_weights", w.dtype(), directOptions(g, block))
      .arg(w)
      .arg(static_cast<int>(g.O))
      .arg(static_cast<int>(g.C))
      .arg(static_cast<int>(taps))
      .arg(byInput ? 1 : 0)
      .arg(wb)
      .run(wb.numel());
  return wb;
}

Tensor directForward(const Geometry& g, const Tensor& x, const Tensor& w, const Tensor& bias,
                     const Shape& outShape) {
  Tensor y = Tensor::empty(outShape, x.dtype());
  if (g.N == 0 || g.outP() == 0)
    return y;
  const int64_t block = channelBlock(g.O), blocks = (g.O + block - 1) / block;
  const Tensor wb = regroupedWeights(g, w, block, false);
  Launch launch("conv_direct", "conv_direct_forward", x.dtype(), directOptions(g, block));
  launch.arg(x).arg(wb).arg(bias.defined() ? bias : wb).arg(bias.defined() ? 1 : 0);
  directGeometryArgs(launch, g).arg(y).run3((g.Wo + 7) / 8, g.Do * g.Ho, g.N * blocks, 4, 4, 1);
  return y;
}

Tensor directInputGrad(const Geometry& g, const Tensor& w, const Tensor& gy, const Shape& xShape) {
  Tensor gx = Tensor::empty(xShape, gy.dtype());
  if (g.N == 0)
    return gx;
  const int64_t block = channelBlock(g.C), blocks = (g.C + block - 1) / block;
  const Tensor wb = regroupedWeights(g, w, block, true);
  Launch launch("conv_direct", "conv_direct_input_grad", gy.dtype(), directOptions(g, block));
  directGeometryArgs(launch.arg(gy).arg(wb), g)
      .arg(gx)
      .run3((g.W + 7) / 8, g.D * g.H, g.N * blocks, 4, 4, 1);
  return gx;
}

// Weight gradient: partial sums over parts of the output rows (conv_direct_weight_grad),
// then their sum. Enough parts for ~512 work items (each a (c, i, j) and kWeightGradBlock
// output channels), so that both cores stay busy with few channels.
Tensor directWeightGrad(const Geometry& g, const Tensor& x, const Tensor& gy, const Shape& wShape) {
  const int64_t taps = g.KD * g.KH * g.KW;
  const int64_t oBlocks = (g.O + kWeightGradBlock - 1) / kWeightGradBlock;
  const int64_t items = g.C * g.KD * g.KH * oBlocks, rows = g.N * g.Do * g.Ho;
  const int64_t parts =
      std::clamp<int64_t>((512 + items - 1) / items, 1, std::max<int64_t>(rows, 1));
  Tensor partial = Tensor::empty({parts, g.O * g.C * taps}, x.dtype());
  Launch launch("conv_direct", "conv_direct_weight_grad", x.dtype(),
                directOptions(g, channelBlock(g.O)));
  directGeometryArgs(launch.arg(x).arg(gy), g)
      .arg(static_cast<int>(parts))
      .arg(partial)
      .run3(parts, g.C * g.KD * g.KH, oBlocks, 1, 8, 1);
  return (parts == 1 ? partial : sum(partial, 0)).viewAs(wShape);
}

// ---- the lowered path (im2col / col2im + GEMM) ----------------------------------------------

Tensor convForward(const char* op, const Geometry& g, const Tensor& x, const Tensor& w,
                   const Tensor& bias, const Shape& outShape) {
  const Dtype dtype = x.dtype();
  Tensor y = Tensor::empty(outShape, dtype);
  const int64_t P = g.outP(), CK = g.ck();
  if (g.N == 0 || P == 0)
    return y;
  double beta = 0.0;
  if (bias.defined()) {
    const int rows = checkedInt(y.numel() / P, op);
    Launch("conv", "conv_bias_fill", dtype)
        .arg(rows)
        .arg(static_cast<int>(g.O))
        .arg(checkedInt(P, op))
        .arg(bias)
        .arg(y)
        .run2((P + 7) / 8, rows, 64, 1);
    beta = 1.0;
  }
  const blas::Operand weight{w.buffer(), 0, sz(CK), false};
  if (g.pointwise()) { // the input of one batch item already is the column matrix [C, P]
    forEachBlock(g, dtype, [&](int64_t n, int64_t, int64_t, int64_t, int64_t) {
      blas::gemm(op, dtype, g.O, P, CK, 1.0, weight, {x.buffer(), sz(n * CK * P), sz(P), false},
                 beta, y.buffer(), sz(n * g.O * P), sz(P));
    });
    return y;
  }
  const int64_t perBlock = rowsPerBlock(g, dtype);
  Tensor col = Tensor::empty({CK, perBlock * g.Wo}, dtype);
  forEachBlock(g, dtype, [&](int64_t n, int64_t row0, int64_t rows, int64_t p0, int64_t chunk) {
    im2col(g, x, n, row0, rows, col);
    blas::gemm(op, dtype, g.O, chunk, CK, 1.0, weight, {col.buffer(), 0, sz(chunk), false}, beta,
               y.buffer(), sz(n * g.O * P + p0), sz(P));
  });
  return y;
}

// Gradients of the input, weight and bias (undefined where not needed).
std::vector<Tensor> convBackward(const char* op, const Geometry& g, const Tensor& x,
                                 const Tensor& w, bool needX, bool needW, bool needBias,
                                 const Tensor& gy) {
  const Dtype dtype = x.dtype();
  const int64_t P = g.outP(), CK = g.ck();
  Tensor gx, gw, gb;
  if (needBias) {
    const int parts = static_cast<int>(std::clamp<int64_t>(P / 256, 1, 64));
    Tensor partial = Tensor::empty({g.O, parts}, dtype);
    Launch("conv", "conv_bias_grad", dtype)
        .arg(static_cast<int>(g.N))
        .arg(static_cast<int>(g.O))
        .arg(static_cast<int>(P))
        .arg(parts)
        .arg(gy)
        .arg(partial)
        .run2(parts, g.O, 16, 4);
    gb = sum(partial, 1);
  }
  if (needW && useDirect(g, Pass::WeightGrad)) {
    gw = directWeightGrad(g, x, gy, w.shape());
    needW = false;
  }
  if (needX && useDirect(g, Pass::InputGrad)) {
    gx = directInputGrad(g, w, gy, x.shape());
    needX = false; // the lowered path below computes the weight gradient only
  }
  if (!needX && !needW)
    return {gx, gw, gb};
  if (needW)
    gw = Tensor::zeros(w.shape(), dtype);
  // Pointwise convolutions write gx with beta = 0; col2im clears it itself when it covers it.
  const bool col2imClears = !g.pointwise() && col2imCoversInput(g, dtype);
  if (needX)
    gx = g.pointwise() || col2imClears ? Tensor::empty(x.shape(), dtype)
                                       : Tensor::zeros(x.shape(), dtype);
  const blas::Operand weightT{w.buffer(), 0, sz(CK), true};
  if (g.pointwise()) {
    forEachBlock(g, dtype, [&](int64_t n, int64_t, int64_t, int64_t, int64_t) {
      const blas::Operand gyn{gy.buffer(), sz(n * g.O * P), sz(P), false};
      if (needW) // gw += gy_n x_n^T
        blas::gemm(op, dtype, g.O, CK, P, 1.0, gyn, {x.buffer(), sz(n * CK * P), sz(P), true}, 1.0,
                   gw.buffer(), 0, sz(CK));
      if (needX) // gx_n = w^T gy_n
        blas::gemm(op, dtype, CK, P, g.O, 1.0, weightT, gyn, 0.0, gx.buffer(), sz(n * CK * P),
                   sz(P));
    });
    return {gx, gw, gb};
  }
  const int64_t perBlock = rowsPerBlock(g, dtype);
  Tensor col = Tensor::empty({CK, perBlock * g.Wo}, dtype);
  forEachBlock(g, dtype, [&](int64_t n, int64_t row0, int64_t rows, int64_t p0, int64_t chunk) {
    const blas::Operand gyn{gy.buffer(), sz(n * g.O * P + p0), sz(P), false};
    if (needW) { // gw += gy_block col_block^T
      im2col(g, x, n, row0, rows, col);
      blas::gemm(op, dtype, g.O, CK, chunk, 1.0, gyn, {col.buffer(), 0, sz(chunk), true}, 1.0,
                 gw.buffer(), 0, sz(CK));
    }
    if (needX) { // dcol = w^T gy_block, scattered back (as a gather) into gx
      blas::gemm(op, dtype, CK, chunk, g.O, 1.0, weightT, gyn, 0.0, col.buffer(), 0, sz(chunk));
      col2im(g, col, n, row0, rows, gx, col2imClears);
    }
  });
  return {gx, gw, gb};
}

Tensor conv(const char* op, int spatial, const Tensor& x, const Tensor& w, const Tensor& bias,
            const int* stride, const int* padding, PaddingMode mode) {
  const Geometry g = checkedGeometry(op, spatial, x, w, bias, stride, padding, mode);
  Shape outShape = {g.N, g.O};
  if (spatial == 3)
    outShape.push_back(g.Do);
  outShape.push_back(g.Ho);
  outShape.push_back(g.Wo);
  Tensor y = useDirect(g, Pass::Forward) ? directForward(g, x, w, bias, outShape)
                                         : convForward(op, g, x, w, bias, outShape);
  if (!needsGrad({x, w, bias}))
    return y;
  Tensor xd = x.detach(), wd = w.detach();
  const bool needX = x.requiresGrad(), needW = w.requiresGrad();
  const bool needBias = bias.defined() && bias.requiresGrad();
  std::vector<Tensor> inputs = {x, w};
  if (bias.defined())
    inputs.push_back(bias);
  const std::size_t count = inputs.size();
  return record(op, y, inputs, [=](const Tensor& gy) {
    std::vector<Tensor> grads = convBackward(op, g, xd, wd, needX, needW, needBias, gy);
    grads.resize(count); // no bias input: drop its (undefined) slot
    return grads;
  });
}

} // namespace

std::size_t setConvColumnBudget(std::size_t bytes) {
  return std::exchange(columnBudgetBytes, bytes);
}

ConvPath setConvPath(ConvPath path) {
  return std::exchange(convPath, path);
}

Tensor conv2d(const Tensor& x, const Tensor& weight, const Tensor& bias, std::array<int, 2> stride,
              std::array<int, 2> padding, PaddingMode mode) {
  return conv("conv2d", 2, x, weight, bias, stride.data(), padding.data(), mode);
}

Tensor conv2d(const Tensor& x, const Tensor& weight, const Tensor& bias, int stride, int padding,
              PaddingMode mode) {
  return conv2d(x, weight, bias, {stride, stride}, {padding, padding}, mode);
}

Tensor conv3d(const Tensor& x, const Tensor& weight, const Tensor& bias, std::array<int, 3> stride,
              std::array<int, 3> padding, PaddingMode mode) {
  return conv("conv3d", 3, x, weight, bias, stride.data(), padding.data(), mode);
}

Tensor conv3d(const Tensor& x, const Tensor& weight, const Tensor& bias, int stride, int padding,
              PaddingMode mode) {
  return conv3d(x, weight, bias, {stride, stride, stride}, {padding, padding, padding}, mode);
}

} // namespace simpli::ocl

#include "simpli/ocl/ops_linalg.h"

#include "clblast_call.h"
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"
#include "tuning.h"

#include <algorithm>

namespace simpli::ocl {
namespace {

std::size_t sz(int64_t v) {
  return static_cast<std::size_t>(v);
}

// For every batch entry b: op(X_b)[m, k] * op(Y_b)[k, n]. X holds bx matrices stored [m, k]
// ([k, m] when tX), Y holds by matrices stored [k, n] ([n, k] when tY); a count of 1 shares the
// matrix across the batch B = max(bx, by). Returns [B, m, n], or their sum [m, n] when
// sumBatch. Shared operands are folded into a single GEMM where the layout allows, which is
// both faster and what lets linear() run as one GEMM.
Tensor bmm(const char* op, const Tensor& x, int64_t bx, bool tX, const Tensor& y, int64_t by,
           bool tY, int64_t m, int64_t n, int64_t k, bool sumBatch) {
  const int64_t batch = std::max(bx, by);
  const Dtype dtype = x.dtype();
  const Shape outShape = sumBatch ? Shape{m, n} : Shape{batch, m, n};
  if (k == 0 || batch == 0)
    return Tensor::zeros(outShape, dtype);
  Tensor out = Tensor::empty(outShape, dtype);
  if (m == 0 || n == 0)
    return out;
  const blas::Operand ox{x.buffer(), 0, sz(tX ? m : k), tX};
  const blas::Operand oy{y.buffer(), 0, sz(tY ? k : n), tY};
  if (batch == 1) {
    blas::gemm(op, dtype, m, n, k, 1.0, ox, oy, 0.0, out.buffer(), 0, sz(n));
    return out;
  }
  if (sumBatch && tX && !tY && bx == by) {
    // sum_b X_b^T Y_b = [X_0; X_1; ...]^T [Y_0; Y_1; ...]: one GEMM with k' = batch * k.
    blas::gemm(op, dtype, m, n, batch * k, 1.0, ox, oy, 0.0, out.buffer(), 0, sz(n));
    return out;
  }
  if (!sumBatch && by == 1 && !tX) {
    // X_b Y for every b = [X_0; X_1; ...] Y: one GEMM with m' = batch * m.
    blas::gemm(op, dtype, batch * m, n, k, 1.0, ox, oy, 0.0, out.buffer(), 0, sz(n));
    return out;
  }
  Tensor full = sumBatch ? Tensor::empty({batch, m, n}, dtype) : out;
  blas::gemmStridedBatched(op, dtype, m, n, k, 1.0, ox, bx == 1 ? 0 : sz(m * k), oy,
                           by == 1 ? 0 : sz(k * n), 0.0, full.buffer(), 0, sz(n), sz(m * n), batch);
  if (!sumBatch)
    return full;
  NoGradGuard noGrad; // a raw helper: the caller records the op
  return sum(full, 0);
}

struct MatrixArg {
  int64_t batch = 1; // 1 also for rank-2 operands
  int64_t rows = 0, cols = 0;
};

MatrixArg matrixArg(const Tensor& t, const char* which, const Tensor& a, const Tensor& b) {
  if (!t.defined())
    fail("matmul: operand ", which, " is undefined");
  if (t.dim() != 2 && t.dim() != 3)
    fail("matmul: operand ", which, " ", t.describe(), " must have rank 2 or 3 (a ",
         a.defined() ? a.describe() : "undefined", ", b ", b.defined() ? b.describe() : "undefined",
         ")");
  MatrixArg m;
  m.batch = t.dim() == 3 ? t.size(0) : 1;
  m.rows = t.size(-2);
  m.cols = t.size(-1);
  return m;
}

Tensor toShape(const Tensor& t, const Shape& shape) {
  return t.shape() == shape ? t : t.viewAs(shape);
}

} // namespace

Tensor matmul(const Tensor& a, const Tensor& b, bool transA, bool transB) {
  const MatrixArg ma = matrixArg(a, "a", a, b);
  const MatrixArg mb = matrixArg(b, "b", a, b);
  if (a.dtype() != b.dtype())
    fail("matmul: dtype mismatch ", a.describe(), " vs ", b.describe());
  const int64_t m = transA ? ma.cols : ma.rows;
  const int64_t k = transA ? ma.rows : ma.cols;
  const int64_t kb = transB ? mb.cols : mb.rows;
  const int64_t n = transB ? mb.rows : mb.cols;
  if (k != kb)
    fail("matmul: inner dimensions differ: a ", a.describe(), (transA ? " (transposed)" : ""),
         " has ", k, ", b ", b.describe(), (transB ? " (transposed)" : ""), " has ", kb);
  if (ma.batch != mb.batch && ma.batch != 1 && mb.batch != 1)
    fail("matmul: batch sizes of a ", a.describe(), " and b ", b.describe(),
         " differ and neither is 1");
  const int64_t batch = std::max(ma.batch, mb.batch);
  const bool batched = a.dim() == 3 || b.dim() == 3;
  const Shape outShape = batched ? Shape{batch, m, n} : Shape{m, n};

  Tensor out =
      toShape(bmm("matmul", a, ma.batch, transA, b, mb.batch, transB, m, n, k, false), outShape);
  if (!needsGrad({a, b}))
    return out;
  Tensor ad = a.detach(), bd = b.detach();
  const bool needA = a.requiresGrad(), needB = b.requiresGrad();
  return record("matmul", out, {a, b}, [=](const Tensor& g) {
    Tensor ga, gb;
    const bool sumA = ma.batch == 1 && batch > 1, sumB = mb.batch == 1 && batch > 1;
    // d op(A) = G op(B)^T and d op(B) = op(A)^T G, transposed back where A or B is stored
    // transposed.
    if (needA) {
      ga = transA ? bmm("matmul backward", bd, mb.batch, transB, g, batch, true, k, m, n, sumA)
                  : bmm("matmul backward", g, batch, false, bd, mb.batch, !transB, m, k, n, sumA);
      ga = toShape(ga, ad.shape());
    }
    if (needB) {
      gb = transB ? bmm("matmul backward", g, batch, true, ad, ma.batch, transA, n, k, m, sumB)
                  : bmm("matmul backward", ad, ma.batch, !transA, g, batch, false, k, n, m, sumB);
      gb = toShape(gb, bd.shape());
    }
    return std::vector<Tensor>{ga, gb};
  });
}

Tensor linear(const Tensor& x, const Tensor& weight, const Tensor& bias) {
  if (!x.defined() || !weight.defined())
    fail("linear: input or weight is undefined");
  if (weight.dim() != 2)
    fail("linear: weight ", weight.describe(), " must be [out, in]");
  if (x.dim() < 1 || x.size(-1) != weight.size(1))
    fail("linear: input ", x.describe(), " does not end in in_features = ", weight.size(1),
         " of weight ", weight.describe());
  if (bias.defined() && (bias.dim() != 1 || bias.size(0) != weight.size(0)))
    fail("linear: bias ", bias.describe(), " must be [", weight.size(0), "] for weight ",
         weight.describe());
  const int64_t in = weight.size(1), outFeatures = weight.size(0);
  Shape outShape = x.shape();
  outShape.back() = outFeatures;
  const int64_t rows = numelOf(Shape(x.shape().begin(), x.shape().end() - 1));
  Tensor y = matmul(reshape(x, {rows, in}), weight, false, true);
  if (bias.defined())
    y = add(y, bias);
  return reshape(y, outShape);
}

std::string clblastTuningSummary() {
  Device::current(); // opening the device applies the tuning
  return lastTuningSummary();
}

} // namespace simpli::ocl

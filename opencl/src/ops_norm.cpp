#include "simpli/ocl/ops_norm.h"

#include "row_blocks.h"
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"

#include <algorithm>

namespace simpli::ocl {
namespace {

void checkAffine(const char* op, const Tensor& x, const Tensor& p, const char* name,
                 int64_t expected, const char* axisName) {
  if (!p.defined())
    fail(op, ": ", name, " is undefined (input ", x.describe(), ")");
  if (p.dtype() != x.dtype())
    fail(op, ": dtype mismatch, input ", x.describe(), " vs ", name, " ", p.describe());
  if (p.dim() != 1 || p.size(0) != expected)
    fail(op, ": ", name, " ", p.describe(), " must be [", expected, "] (", axisName, " of input ",
         x.describe(), ")");
}

/// Per-sample statistics [N, 3] = (mean, unbiased std s, 1 / (s + eps)) of x viewed as
/// [N, M]: blocked partial (count, mean, M2) triples, then one combine per sample.
Tensor totalStats(const Tensor& x, int N, int M, double eps) {
  const RowBlocks rb = rowBlocks(M);
  const int stride = N * rb.groups;
  Tensor part = Tensor::empty({3, stride}, x.dtype());
  Launch("norm", "lnt_stats_partial", x.dtype())
      .arg(M)
      .arg(rb.perItem)
      .arg(x)
      .arg(part)
      .arg(stride)
      .run2(static_cast<int64_t>(rb.groups) * kGroupSize, N, kGroupSize, 1);
  Tensor stats = Tensor::empty({N, 3}, x.dtype());
  Launch("norm", "lnt_stats_finish", x.dtype())
      .arg(N)
      .arg(rb.groups)
      .arg(M)
      .real(eps)
      .arg(part)
      .arg(stride)
      .arg(stats)
      .run(N);
  return stats;
}

struct TotalDims {
  int N, C, M, inner, n;
};

/// Gradients of layerNormTotal: {dx (or undefined), dgamma, dbeta}.
std::vector<Tensor> totalBackward(const Tensor& x, const Tensor& g, const Tensor& stats,
                                  const Tensor& gamma, const TotalDims& d, bool wantX) {
  const RowBlocks rb = rowBlocks(d.inner);
  const int rows = d.N * d.C;
  const int stride = rows * rb.groups;
  Tensor part = Tensor::empty({2, stride}, x.dtype());
  Launch("norm", "lnt_bwd_partial", x.dtype())
      .arg(d.inner)
      .arg(rb.perItem)
      .arg(d.C)
      .arg(x)
      .arg(g)
      .arg(stats)
      .arg(part)
      .arg(stride)
      .run2(static_cast<int64_t>(rb.groups) * kGroupSize, rows, kGroupSize, 1);
  Tensor coef = Tensor::empty({d.N, 2}, x.dtype());
  Tensor dgamma = Tensor::empty({d.C}, x.dtype());
  Tensor dbeta = Tensor::empty({d.C}, x.dtype());
  Launch("norm", "lnt_bwd_coeffs", x.dtype())
      .arg(d.N)
      .arg(d.C)
      .arg(rb.groups)
      .arg(d.M)
      .arg(part)
      .arg(stride)
      .arg(stats)
      .arg(gamma)
      .arg(coef)
      .arg(dgamma)
      .arg(dbeta)
      .run(std::max(d.N, d.C));
  Tensor dx;
  if (wantX) {
    dx = Tensor::empty(x.shape(), x.dtype());
    Launch("norm", "lnt_bwd_dx", x.dtype())
        .arg(d.inner)
        .arg(rows)
        .arg(d.C)
        .arg(x)
        .arg(g)
        .arg(stats)
        .arg(gamma)
        .arg(coef)
        .arg(dx)
        .run2(rowItems(d.inner), rows, rowLocal(rowItems(d.inner)).first,
              rowLocal(rowItems(d.inner)).second);
  }
  return {dx, dgamma, dbeta};
}

} // namespace

Tensor layerNormTotal(const Tensor& x, const Tensor& gamma, const Tensor& beta, double eps) {
  const char* op = "layerNormTotal";
  if (!x.defined())
    fail(op, ": undefined input");
  if (x.dim() < 2)
    fail(op, ": input ", x.describe(), " must be [N, C, ...] (rank >= 2)");
  if (!(eps > 0.0))
    fail(op, ": eps ", eps, " must be > 0");
  checkAffine(op, x, gamma, "gamma", x.size(1), "axis 1");
  checkAffine(op, x, beta, "beta", x.size(1), "axis 1");
  TotalDims d;
  d.n = checkedInt(x.numel(), op);
  d.N = static_cast<int>(x.size(0));
  d.C = static_cast<int>(x.size(1));
  if (d.N == 0 || d.C == 0)
    fail(op, ": input ", x.describe(), " is empty");
  d.M = d.n / d.N;
  d.inner = d.M / d.C;
  if (d.M < 2)
    fail(op, ": input ", x.describe(), " has ", d.M,
         " element(s) per sample; the unbiased std needs at least 2");

  Tensor stats = totalStats(x, d.N, d.M, eps);
  Tensor y = Tensor::empty(x.shape(), x.dtype());
  Launch("norm", "lnt_apply", x.dtype())
      .arg(d.inner)
      .arg(d.N * d.C)
      .arg(d.C)
      .arg(x)
      .arg(stats)
      .arg(gamma)
      .arg(beta)
      .arg(y)
      .run2(rowItems(d.inner), static_cast<int64_t>(d.N) * d.C, rowLocal(rowItems(d.inner)).first,
            rowLocal(rowItems(d.inner)).second);
  if (!needsGrad({x, gamma, beta}))
    return y;
  const bool wantX = x.requiresGrad();
  return record(op, y, {x, gamma, beta},
                [xd = x.detach(), gd = gamma.detach(), stats, d, wantX](const Tensor& g) {
                  return totalBackward(xd, g, stats, gd, d, wantX);
                });
}

Tensor layerNorm(const Tensor& x, const Tensor& weight, const Tensor& bias, double eps) {
  const char* op = "layerNorm";
  if (!x.defined())
    fail(op, ": undefined input");
  if (x.dim() < 1 || x.numel() == 0)
    fail(op, ": input ", x.describe(), " must be non-empty [..., D]");
  if (!(eps > 0.0))
    fail(op, ": eps ", eps, " must be > 0");
  checkAffine(op, x, weight, "weight", x.size(-1), "last axis");
  checkAffine(op, x, bias, "bias", x.size(-1), "last axis");
  const int D = static_cast<int>(x.size(-1));
  const int rows = checkedInt(x.numel() / D, op);
  Tensor y = Tensor::empty(x.shape(), x.dtype());
  Tensor stats = Tensor::empty({rows, 2}, x.dtype());
  Launch("norm", "ln_forward", x.dtype())
      .arg(rows)
      .arg(D)
      .real(eps)
      .arg(x)
      .arg(weight)
      .arg(bias)
      .arg(y)
      .arg(stats)
      .run(rows);
  if (!needsGrad({x, weight, bias}))
    return y;
  const bool wantX = x.requiresGrad();
  const bool wantWB = weight.requiresGrad() || bias.requiresGrad();
  return record(
      op, y, {x, weight, bias},
      [xd = x.detach(), wd = weight.detach(), stats, rows, D, wantX, wantWB](const Tensor& g) {
        std::vector<Tensor> grads(3);
        if (wantX) {
          grads[0] = Tensor::empty(xd.shape(), xd.dtype());
          Launch("norm", "ln_bwd_dx", xd.dtype())
              .arg(rows)
              .arg(D)
              .arg(xd)
              .arg(g)
              .arg(wd)
              .arg(stats)
              .arg(grads[0])
              .run(rows);
        }
        if (wantWB) {
          // Column sums in two stages: `parts` row blocks, then a sum over blocks.
          const int rowsPer = (rows + 255) / 256;
          const int parts = (rows + rowsPer - 1) / rowsPer;
          Tensor pw = Tensor::empty({parts, D}, xd.dtype());
          Tensor pb = Tensor::empty({parts, D}, xd.dtype());
          Launch("norm", "ln_bwd_wb_partial", xd.dtype())
              .arg(rows)
              .arg(D)
              .arg(rowsPer)
              .arg(parts)
              .arg(xd)
              .arg(g)
              .arg(stats)
              .arg(pw)
              .arg(pb)
              .run(static_cast<int64_t>(parts) * D);
          for (int k = 0; k < 2; ++k) {
            grads[1 + k] = Tensor::empty({D}, xd.dtype());
            Launch("reduce", "reduce_sum_axis", xd.dtype())
                .arg(1)
                .arg(parts)
                .arg(D)
                .arg(k == 0 ? pw : pb)
                .arg(grads[1 + k])
                .run(D);
          }
        }
        return grads;
      });
}

} // namespace simpli::ocl

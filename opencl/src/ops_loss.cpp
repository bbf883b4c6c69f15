#include "simpli/ocl/ops_loss.h"

#include "row_blocks.h"
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"

namespace simpli::ocl {
namespace {

constexpr int kModeAbs = 0;    // MODE_ABS in loss.cl
constexpr int kModeSquare = 1; // MODE_SQUARE in loss.cl

void checkPair(const char* op, const char* nameA, const Tensor& a, const char* nameB,
               const Tensor& b) {
  if (!a.defined() || !b.defined())
    fail(op, ": undefined ", !a.defined() ? nameA : nameB);
  if (a.dtype() != b.dtype())
    fail(op, ": dtype mismatch, ", nameA, " ", a.describe(), " vs ", nameB, " ", b.describe());
}

void checkSameShape(const char* op, const char* nameA, const Tensor& a, const char* nameB,
                    const Tensor& b) {
  checkPair(op, nameA, a, nameB, b);
  if (a.shape() != b.shape())
    fail(op, ": shapes differ, ", nameA, " ", a.describe(), " vs ", nameB, " ", b.describe());
}

/// mean penalty(a - b): blocked partial sums, then one fixed-order sum.
Tensor pointwiseLoss(const char* op, int mode, const Tensor& a, const Tensor& b) {
  checkSameShape(op, "a", a, "b", b);
  if (a.numel() == 0)
    fail(op, ": inputs ", a.describe(), " are empty");
  const int n = checkedInt(a.numel(), op);
  const double scale = 1.0 / static_cast<double>(n);
  const RowBlocks rb = rowBlocks(n);
  Tensor part = Tensor::empty({2, rb.groups}, a.dtype());
  Launch("loss", "pointwise_partial", a.dtype())
      .arg(mode)
      .arg(n)
      .arg(rb.perItem)
      .arg(a)
      .arg(b)
      .arg(part)
      .run(static_cast<int64_t>(rb.groups) * kGroupSize);
  Tensor out = Tensor::empty({1}, a.dtype());
  Launch("loss", "finish_sum", a.dtype()).arg(rb.groups).real(scale).arg(part).arg(out).run(1);
  if (!needsGrad({a, b}))
    return out;
  const bool wantA = a.requiresGrad(), wantB = b.requiresGrad();
  return record(op, out, {a, b},
                [ad = a.detach(), bd = b.detach(), mode, n, scale, wantA, wantB](const Tensor& g) {
                  Tensor ga = wantA ? Tensor::empty(ad.shape(), ad.dtype()) : Tensor();
                  Tensor gb = wantB ? Tensor::empty(bd.shape(), bd.dtype()) : Tensor();
                  Launch("loss", "pointwise_backward", ad.dtype())
                      .arg(mode)
                      .arg(n)
                      .real(scale)
                      .arg(g)
                      .arg(ad)
                      .arg(bd)
                      .arg(wantA ? ga : ad) // placeholders are never written
                      .arg(wantB ? gb : ad)
                      .arg(static_cast<int>(wantA))
                      .arg(static_cast<int>(wantB))
                      .run(rowItems(n));
                  return std::vector<Tensor>{ga, gb};
                });
}

/// Shared by totalVariation (abs) and smoothLayersLoss (square): x as a stack of H x W images.
struct Grad2d {
  int n, H, W;
  double cy, cx;
};

Tensor grad2dLoss(const char* op, int mode, const Tensor& x, const Grad2d& d) {
  const RowBlocks rb = rowBlocks(d.n);
  Tensor part = Tensor::empty({2, rb.groups}, x.dtype());
  Launch("loss", "grad2d_partial", x.dtype())
      .arg(mode)
      .arg(d.n)
      .arg(d.H)
      .arg(d.W)
      .arg(rb.perItem)
      .arg(x)
      .arg(part)
      .arg(rb.groups)
      .run(static_cast<int64_t>(rb.groups) * kGroupSize);
  Tensor out = Tensor::empty({1}, x.dtype());
  Tensor aux = Tensor::empty({1}, x.dtype());
  Launch("loss", "grad2d_finish", x.dtype())
      .arg(mode)
      .arg(rb.groups)
      .real(d.cy)
      .real(d.cx)
      .real(1e-6) // the reference's sqrt(... + 1e-6)
      .arg(part)
      .arg(rb.groups)
      .arg(out)
      .arg(aux)
      .run(1);
  if (!needsGrad({x}))
    return out;
  return record(op, out, {x}, [xd = x.detach(), aux, mode, d](const Tensor& g) {
    Tensor gx = Tensor::empty(xd.shape(), xd.dtype());
    Launch("loss", "grad2d_backward", xd.dtype())
        .arg(mode)
        .arg(d.n)
        .arg(d.H)
        .arg(d.W)
        .real(d.cy)
        .real(d.cx)
        .arg(g)
        .arg(aux)
        .arg(xd)
        .arg(gx)
        .run(d.n);
    return std::vector<Tensor>{gx};
  });
}

} // namespace

Tensor l1Loss(const Tensor& a, const Tensor& b) {
  return pointwiseLoss("l1Loss", kModeAbs, a, b);
}

Tensor mseLoss(const Tensor& a, const Tensor& b) {
  return pointwiseLoss("mseLoss", kModeSquare, a, b);
}

Tensor maskedL1(const Tensor& pred, const Tensor& target, const Tensor& mask) {
  const char* op = "maskedL1";
  checkSameShape(op, "pred", pred, "target", target);
  checkPair(op, "pred", pred, "mask", mask);
  if (pred.dim() != 4)
    fail(op, ": pred ", pred.describe(), " must be [N, C, H, W]");
  const Shape& s = pred.shape();
  const int64_t cm = mask.dim() == 4 ? mask.size(1) : -1;
  if (mask.dim() != 4 || mask.size(0) != s[0] || mask.size(2) != s[2] || mask.size(3) != s[3] ||
      (cm != 1 && cm != s[1]))
    fail(op, ": mask ", mask.describe(), " must be [", s[0], ", 1, ", s[2], ", ", s[3], "] or [",
         s[0], ", ", s[1], ", ", s[2], ", ", s[3], "] for pred ", pred.describe());
  if (pred.numel() == 0)
    fail(op, ": pred ", pred.describe(), " is empty");
  checkedInt(pred.numel(), op);
  const int C = static_cast<int>(s[1]), Cm = static_cast<int>(cm);
  const int L = static_cast<int>(s[2] * s[3]);
  const int rows = static_cast<int>(s[0]) * C;
  const int mrows = static_cast<int>(s[0]) * Cm;
  const double scale = 1.0 / rows;

  const RowBlocks rb = rowBlocks(L);
  const int stride = rows * rb.groups;
  Tensor part = Tensor::empty({2, stride}, pred.dtype());
  Launch("loss", "masked_l1_partial", pred.dtype())
      .arg(C)
      .arg(Cm)
      .arg(L)
      .arg(rb.perItem)
      .arg(pred)
      .arg(target)
      .arg(mask)
      .arg(part)
      .arg(stride)
      .run2(static_cast<int64_t>(rb.groups) * kGroupSize, rows, kGroupSize, 1);
  Tensor sz = Tensor::empty({rows, 2}, pred.dtype());
  Tensor ratio = Tensor::empty({rows}, pred.dtype());
  Launch("loss", "masked_l1_rows", pred.dtype())
      .arg(rows)
      .arg(rb.groups)
      .real(1e-6) // the reference's sum(mask) + 1e-6
      .arg(part)
      .arg(stride)
      .arg(sz)
      .arg(ratio)
      .run(rows);
  Tensor out = Tensor::empty({1}, pred.dtype());
  Launch("loss", "finish_sum", pred.dtype()).arg(rows).real(scale).arg(ratio).arg(out).run(1);
  if (!needsGrad({pred, target, mask}))
    return out;
  const bool wantP = pred.requiresGrad(), wantT = target.requiresGrad();
  const bool wantM = mask.requiresGrad();
  return record(
      op, out, {pred, target, mask},
      [pd = pred.detach(), td = target.detach(), md = mask.detach(), sz, rows, mrows, C, Cm, L,
       scale, wantP, wantT, wantM](const Tensor& g) {
        std::vector<Tensor> grads(3);
        if (wantP || wantT) {
          Tensor gp = wantP ? Tensor::empty(pd.shape(), pd.dtype()) : Tensor();
          Tensor gt = wantT ? Tensor::empty(td.shape(), td.dtype()) : Tensor();
          Launch("loss", "masked_l1_bwd_pt", pd.dtype())
              .arg(rows)
              .arg(C)
              .arg(Cm)
              .arg(L)
              .real(scale)
              .arg(g)
              .arg(pd)
              .arg(td)
              .arg(md)
              .arg(sz)
              .arg(wantP ? gp : pd) // placeholders are never written
              .arg(wantT ? gt : pd)
              .arg(static_cast<int>(wantP))
              .arg(static_cast<int>(wantT))
              .run2(rowItems(L), rows, rowLocal(rowItems(L)).first, rowLocal(rowItems(L)).second);
          grads[0] = gp;
          grads[1] = gt;
        }
        if (wantM) {
          grads[2] = Tensor::empty(md.shape(), md.dtype());
          Launch("loss", "masked_l1_bwd_mask", md.dtype())
              .arg(mrows)
              .arg(C)
              .arg(Cm)
              .arg(L)
              .real(scale)
              .arg(g)
              .arg(pd)
              .arg(td)
              .arg(sz)
              .arg(grads[2])
              .run2(rowItems(L), mrows, rowLocal(rowItems(L)).first, rowLocal(rowItems(L)).second);
        }
        return grads;
      });
}

Tensor totalVariation(const Tensor& x) {
  const char* op = "totalVariation";
  if (!x.defined())
    fail(op, ": undefined input");
  if (x.dim() < 2 || x.numel() == 0)
    fail(op, ": input ", x.describe(), " must be non-empty [..., H, W]");
  Grad2d d;
  d.n = checkedInt(x.numel(), op);
  d.H = static_cast<int>(x.size(-2));
  d.W = static_cast<int>(x.size(-1));
  const int64_t images = x.numel() / (static_cast<int64_t>(d.H) * d.W);
  // Each mean is over its own pairs; a direction without pairs contributes 0.
  const int64_t pairsY = images * (d.H - 1) * d.W, pairsX = images * d.H * (d.W - 1);
  d.cy = pairsY > 0 ? 1.0 / static_cast<double>(pairsY) : 0.0;
  d.cx = pairsX > 0 ? 1.0 / static_cast<double>(pairsX) : 0.0;
  return grad2dLoss(op, kModeAbs, x, d);
}

Tensor smoothLayersLoss(const Tensor& depth) {
  const char* op = "smoothLayersLoss";
  if (!depth.defined())
    fail(op, ": undefined input");
  if (depth.dim() != 4 || depth.numel() == 0)
    fail(op, ": depth ", depth.describe(), " must be non-empty [B, L, H, W]");
  Grad2d d;
  d.n = checkedInt(depth.numel(), op);
  d.H = static_cast<int>(depth.size(2));
  d.W = static_cast<int>(depth.size(3));
  d.cy = d.cx = 1.0 / static_cast<double>(d.n);
  return grad2dLoss(op, kModeSquare, depth, d);
}

} // namespace simpli::ocl

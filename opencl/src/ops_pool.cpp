#include "simpli/ocl/ops_pool.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"

namespace simpli::ocl {
namespace {

struct PoolGeometry {
  int planes, h, w, oh, ow, kh, kw, sh, sw;
  Shape outShape;
};

PoolGeometry geometry(const Tensor& x, int kh, int kw, int sh, int sw, const char* op) {
  if (!x.defined())
    fail(op, ": undefined tensor");
  if (x.dim() < 2)
    fail(op, ": input ", x.describe(), " needs at least 2 dimensions (..., H, W)");
  if (kh < 1 || kw < 1 || sh < 1 || sw < 1)
    fail(op, ": kernel ", kh, "x", kw, " and stride ", sh, "x", sw, " must be positive (input ",
         x.describe(), ")");
  PoolGeometry g{};
  const Shape& s = x.shape();
  const int64_t h = s[s.size() - 2], w = s[s.size() - 1];
  if (kh > h || kw > w)
    fail(op, ": kernel ", kh, "x", kw, " is larger than the input ", x.describe());
  g.outShape = s;
  g.outShape[s.size() - 2] = (h - kh) / sh + 1;
  g.outShape[s.size() - 1] = (w - kw) / sw + 1;
  if (numelOf(g.outShape) == 0)
    fail(op, ": input ", x.describe(), " gives the zero-size output ", toString(g.outShape));
  checkedInt(x.numel(), op);
  g.planes = static_cast<int>(x.numel() / (h * w));
  g.h = static_cast<int>(h);
  g.w = static_cast<int>(w);
  g.oh = static_cast<int>(g.outShape[s.size() - 2]);
  g.ow = static_cast<int>(g.outShape[s.size() - 1]);
  g.kh = kh;
  g.kw = kw;
  g.sh = sh;
  g.sw = sw;
  return g;
}

Launch& geometryArgs(Launch& launch, const PoolGeometry& g) {
  return launch.arg(g.planes)
      .arg(g.h)
      .arg(g.w)
      .arg(g.oh)
      .arg(g.ow)
      .arg(g.kh)
      .arg(g.kw)
      .arg(g.sh)
      .arg(g.sw);
}

} // namespace

Tensor maxPool2d(const Tensor& x, int kernelH, int kernelW, int strideH, int strideW) {
  const PoolGeometry g = geometry(x, kernelH, kernelW, strideH, strideW, "maxPool2d");
  Tensor out = Tensor::empty(g.outShape, x.dtype());
  Launch forward("pool", "max_pool_forward", x.dtype());
  geometryArgs(forward, g).arg(x).arg(out).run3(g.ow, g.oh, g.planes);
  if (!needsGrad({x}))
    return out;
  // The backward pass recomputes each window's argmax from the input instead of storing it:
  // no index buffer, and the gather needs no atomics for overlapping windows.
  return record("maxPool2d", out, {x}, [g, xd = x.detach()](const Tensor& grad) {
    Tensor gx = Tensor::empty(xd.shape(), grad.dtype());
    Launch backward("pool", "max_pool_backward", grad.dtype());
    geometryArgs(backward, g).arg(xd).arg(grad).arg(gx).run3(g.w, g.h, g.planes);
    return std::vector<Tensor>{gx};
  });
}

Tensor maxPool2d(const Tensor& x, int kernel, int stride) {
  return maxPool2d(x, kernel, kernel, stride, stride);
}

Tensor avgPool2d(const Tensor& x, int kernelH, int kernelW, int strideH, int strideW) {
  const PoolGeometry g = geometry(x, kernelH, kernelW, strideH, strideW, "avgPool2d");
  Tensor out = Tensor::empty(g.outShape, x.dtype());
  Launch forward("pool", "avg_pool_forward", x.dtype());
  geometryArgs(forward, g).arg(x).arg(out).run3(g.ow, g.oh, g.planes);
  return record("avgPool2d", out, {x}, [g, xs = x.shape()](const Tensor& grad) {
    Tensor gx = Tensor::empty(xs, grad.dtype());
    Launch backward("pool", "avg_pool_backward", grad.dtype());
    geometryArgs(backward, g).arg(grad).arg(gx).run3(g.w, g.h, g.planes);
    return std::vector<Tensor>{gx};
  });
}

Tensor avgPool2d(const Tensor& x, int kernel, int stride) {
  return avgPool2d(x, kernel, kernel, stride, stride);
}

} // namespace simpli::ocl

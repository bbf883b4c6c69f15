#include "simpli/ocl/ops_reduce.h"

#include "row_blocks.h"
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_shape.h"

#include <algorithm>

namespace simpli::ocl {

int normaliseAxis(int axis, int rank, const char* op, const Shape& shape) {
  const int a = axis < 0 ? axis + rank : axis;
  if (a < 0 || a >= rank)
    fail(op, ": axis ", axis, " is out of range for shape ", toString(shape));
  return a;
}

namespace {

struct AxisSplit {
  int outer = 1, n = 1, inner = 1;
  Shape keptShape;    // x's shape with the axis set to 1
  Shape droppedShape; // x's shape without the axis
};

AxisSplit splitAt(const Tensor& x, int axis, const char* op) {
  if (!x.defined())
    fail(op, ": undefined tensor");
  const Shape& s = x.shape();
  const int a = normaliseAxis(axis, x.dim(), op, s);
  AxisSplit r;
  int64_t outer = 1, inner = 1;
  for (int d = 0; d < a; ++d)
    outer *= s[d];
  for (int d = a + 1; d < x.dim(); ++d)
    inner *= s[d];
  r.outer = checkedInt(outer, op);
  r.inner = checkedInt(inner, op);
  r.n = checkedInt(s[a], op);
  r.keptShape = s;
  r.keptShape[a] = 1;
  r.droppedShape = s;
  r.droppedShape.erase(r.droppedShape.begin() + a);
  return r;
}

constexpr int kRedSum = 0;   // RED_SUM in reduce.cl
constexpr int kRedSqdev = 1; // RED_SQDEV in reduce.cl

/// scale * sum over the axis of x (mean undefined) or of (x - mean)^2 (mean: one value per
/// (outer, inner) pair); shape sp.keptShape. Picks the kernel layout by shape (reduce.cl): the
/// direct loop only when there are enough outputs to keep the device busy or the axis is short.
Tensor axisReduceRaw(const Tensor& x, const AxisSplit& sp, const Tensor& mean, double scale) {
  const int mode = mean.defined() ? kRedSqdev : kRedSum;
  const cl_mem meanBuffer = mean.defined() ? mean.buffer() : x.buffer(); // unread for sums
  const int64_t outputs = static_cast<int64_t>(sp.outer) * sp.inner;
  Tensor out = Tensor::empty(sp.keptShape, x.dtype());
  Tensor part;
  int parts = 0;
  if (sp.inner == 1 && sp.n >= 512) {
    const RowBlocks rb = rowBlocks(sp.n);
    parts = rb.groups;
    part = Tensor::empty({sp.outer, parts}, x.dtype());
    Launch("reduce", "reduce_blocks", x.dtype())
        .arg(mode)
        .arg(sp.n)
        .arg(rb.perItem)
        .arg(x)
        .arg(meanBuffer)
        .arg(part)
        .run2(static_cast<int64_t>(rb.groups) * kGroupSize, sp.outer, kGroupSize, 1);
  } else if (outputs < 4096 && sp.n >= 64) {
    // ~4096 items in all, each summing at least 16 elements of the axis.
    const int64_t wanted = std::max<int64_t>(1, 4096 / outputs);
    const int64_t maxParts = std::max<int64_t>(1, sp.n / 16);
    const int chunkTry =
        static_cast<int>((sp.n + std::min(wanted, maxParts) - 1) / std::min(wanted, maxParts));
    parts = (sp.n + chunkTry - 1) / chunkTry;
    part = Tensor::empty({sp.outer, parts, sp.inner}, x.dtype());
    Launch("reduce", "reduce_split", x.dtype())
        .arg(mode)
        .arg(sp.outer)
        .arg(sp.n)
        .arg(sp.inner)
        .arg(chunkTry)
        .arg(parts)
        .arg(x)
        .arg(meanBuffer)
        .arg(part)
        .run(outputs * parts);
  }
  if (part.defined()) {
    Launch("reduce", "reduce_partials", x.dtype())
        .arg(sp.outer)
        .arg(parts)
        .arg(sp.inner)
        .real(scale)
        .arg(part)
        .arg(out)
        .run(outputs);
  } else {
    Launch("reduce", "reduce_axis", x.dtype())
        .arg(mode)
        .arg(sp.outer)
        .arg(sp.n)
        .arg(sp.inner)
        .real(scale)
        .arg(x)
        .arg(meanBuffer)
        .arg(out)
        .run(outputs);
  }
  return out;
}

} // namespace

Tensor expand(const Tensor& x, const Shape& shape) {
  const Shape target = broadcastShapes(x.shape(), shape, "expand");
  if (target != shape)
    fail("expand: ", x.describe(), " cannot be expanded to ", toString(shape));
  if (x.shape() == shape)
    return x;
  Tensor out;
  {
    NoGradGuard inner; // the copy is one op on the tape, recorded below (outside this guard)
    out = add(Tensor::zeros(shape, x.dtype()), x.detach());
  }
  const Shape source = x.shape();
  return record("expand", out, {x},
                [source](const Tensor& g) { return std::vector<Tensor>{sumToShape(g, source)}; });
}

Tensor sum(const Tensor& x, int axis, bool keepdim) {
  AxisSplit sp = splitAt(x, axis, "sum");
  if (sp.n == 0)
    fail("sum: axis ", axis, " of ", x.describe(), " is empty");
  Tensor out = axisReduceRaw(x, sp, Tensor(), 1.0);
  out = record("sum", out, {x},
               [xs = x.shape()](const Tensor& g) { return std::vector<Tensor>{expand(g, xs)}; });
  return keepdim ? out : reshape(out, sp.droppedShape);
}

Tensor mean(const Tensor& x, int axis, bool keepdim) {
  AxisSplit sp = splitAt(x, axis, "mean");
  if (sp.n == 0)
    fail("mean: axis ", axis, " of ", x.describe(), " is empty");
  return mulScalar(sum(x, axis, keepdim), 1.0 / sp.n);
}

Tensor variance(const Tensor& x, int axis, bool unbiased, bool keepdim) {
  AxisSplit sp = splitAt(x, axis, "variance");
  const int ddof = unbiased ? 1 : 0;
  if (sp.n - ddof <= 0)
    fail("variance: axis ", axis, " of ", x.describe(), " has ", sp.n,
         " element(s), too few for the ", unbiased ? "unbiased" : "biased", " estimator");
  // Two passes over the data (mean first), so large offsets do not cancel.
  Tensor m = axisReduceRaw(x, sp, Tensor(), 1.0 / sp.n);
  Tensor out = axisReduceRaw(x, sp, m, 1.0 / (sp.n - ddof));
  if (needsGrad({x})) {
    Tensor xd = x.detach();
    const int a = normaliseAxis(axis, x.dim(), "variance", x.shape());
    const double scale = 2.0 / (sp.n - ddof);
    out = record("variance", out, {x}, [xd, a, scale](const Tensor& g) {
      // d var / d x_k = 2 (x_k - mean) / (n - ddof)
      Tensor centred = sub(xd, mean(xd, a, true));
      return std::vector<Tensor>{mul(mulScalar(centred, scale), g)};
    });
  }
  return keepdim ? out : reshape(out, sp.droppedShape);
}

Tensor sumAll(const Tensor& x) {
  if (!x.defined())
    fail("sumAll: undefined tensor");
  AxisSplit sp;
  sp.n = checkedInt(x.numel(), "sumAll");
  sp.keptShape = {1};
  Tensor out = sp.n == 0 ? Tensor::zeros({1}, x.dtype()) : axisReduceRaw(x, sp, Tensor(), 1.0);
  return record("sumAll", out, {x}, [xs = x.shape()](const Tensor& g) {
    return std::vector<Tensor>{expand(g.viewAs(Shape(xs.size(), 1)), xs)};
  });
}

Tensor meanAll(const Tensor& x) {
  if (x.numel() == 0)
    fail("meanAll: tensor ", x.describe(), " is empty");
  return mulScalar(sumAll(x), 1.0 / static_cast<double>(x.numel()));
}

} // namespace simpli::ocl

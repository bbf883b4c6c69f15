#include "simpli/ocl/ops_reduce.h"

#include "launch.h"
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_shape.h"

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

Tensor sumAxisRaw(const Tensor& x, const AxisSplit& sp) {
  Tensor out = Tensor::empty(sp.keptShape, x.dtype());
  Launch("reduce", "reduce_sum_axis", x.dtype())
      .arg(sp.outer)
      .arg(sp.n)
      .arg(sp.inner)
      .arg(x)
      .arg(out)
      .run(static_cast<int64_t>(sp.outer) * sp.inner);
  return out;
}

} // namespace

Tensor expand(const Tensor& x, const Shape& shape) {
  const Shape target = broadcastShapes(x.shape(), shape, "expand");
  if (target != shape)
    fail("expand: ", x.describe(), " cannot be expanded to ", toString(shape));
  if (x.shape() == shape)
    return x;
  NoGradGuard inner; // the copy below is one op on the tape, recorded next
  Tensor out = add(Tensor::zeros(shape, x.dtype()), x.detach());
  const Shape source = x.shape();
  return record("expand", out, {x},
                [source](const Tensor& g) { return std::vector<Tensor>{sumToShape(g, source)}; });
}

Tensor sum(const Tensor& x, int axis, bool keepdim) {
  AxisSplit sp = splitAt(x, axis, "sum");
  if (sp.n == 0)
    fail("sum: axis ", axis, " of ", x.describe(), " is empty");
  Tensor out = sumAxisRaw(x, sp);
  out = record("sum", out, {x}, [xs = x.shape()](const Tensor& g) {
    return std::vector<Tensor>{expand(g, xs)};
  });
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
  Tensor out = Tensor::empty(sp.keptShape, x.dtype());
  Launch("reduce", "reduce_var_axis", x.dtype())
      .arg(sp.outer)
      .arg(sp.n)
      .arg(sp.inner)
      .arg(ddof)
      .arg(x)
      .arg(out)
      .run(static_cast<int64_t>(sp.outer) * sp.inner);
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
  const int n = checkedInt(x.numel(), "sumAll");
  // Two stages keep the device busy: `parts` strided partial sums, then one final sum.
  const int parts = n < 4096 ? 1 : 256;
  Tensor partial = Tensor::empty({parts}, x.dtype());
  Launch("reduce", "reduce_sum_strided", x.dtype()).arg(n).arg(parts).arg(x).arg(partial).run(
      parts);
  Tensor out = partial;
  if (parts > 1) {
    out = Tensor::empty({1}, x.dtype());
    Launch("reduce", "reduce_sum_strided", x.dtype()).arg(parts).arg(1).arg(partial).arg(out).run(
        1);
  }
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

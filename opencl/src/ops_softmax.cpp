#include "simpli/ocl/ops_softmax.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_reduce.h"

#include <initializer_list>
#include <string>

namespace simpli::ocl {
namespace {

/// x viewed as [outer, n, inner] around `axis`.
struct Slices {
  int outer = 1, n = 1, inner = 1, axis = 0;
};

Slices slicesOf(const Tensor& x, int axis, const char* op) {
  if (!x.defined())
    fail(op, ": undefined input");
  if (x.dim() == 0)
    fail(op, ": input ", x.describe(), " has no axis ", axis);
  Slices s;
  s.axis = normaliseAxis(axis, x.dim(), op, x.shape());
  if (x.numel() == 0)
    fail(op, ": input ", x.describe(), " is empty");
  int64_t outer = 1, inner = 1;
  for (int d = 0; d < s.axis; ++d)
    outer *= x.size(d);
  for (int d = s.axis + 1; d < x.dim(); ++d)
    inner *= x.size(d);
  checkedInt(x.numel(), op);
  s.outer = static_cast<int>(outer);
  s.inner = static_cast<int>(inner);
  s.n = static_cast<int>(x.size(s.axis));
  return s;
}

/// Launches `<name>_rows_<stage>` (contiguous slices, inner == 1) or `<name>_strided_<stage>`
/// with the slice geometry first, then the given buffers.
void launchSlices(const char* name, const char* stage, const Slices& s, Dtype dtype,
                  std::initializer_list<cl_mem> buffers) {
  const bool rows = s.inner == 1;
  const std::string kernel = std::string(name) + (rows ? "_rows_" : "_strided_") + stage;
  Launch launch("softmax", kernel.c_str(), dtype);
  if (rows)
    launch.arg(s.outer).arg(s.n);
  else
    launch.arg(s.outer).arg(s.n).arg(s.inner);
  for (cl_mem b : buffers)
    launch.arg(b);
  launch.run(static_cast<int64_t>(s.outer) * s.inner);
}

} // namespace

Tensor softmax(const Tensor& x, int axis) {
  const Slices s = slicesOf(x, axis, "softmax");
  Tensor y = Tensor::empty(x.shape(), x.dtype());
  launchSlices("softmax", "forward", s, x.dtype(), {x.buffer(), y.buffer()});
  if (!needsGrad({x}))
    return y;
  return record("softmax", y, {x}, [yd = y.detach(), s](const Tensor& g) {
    Tensor dx = Tensor::empty(yd.shape(), yd.dtype());
    launchSlices("softmax", "backward", s, yd.dtype(), {yd.buffer(), g.buffer(), dx.buffer()});
    return std::vector<Tensor>{dx};
  });
}

Tensor logSumExp(const Tensor& x, int axis, bool keepdim) {
  const Slices s = slicesOf(x, axis, "logSumExp");
  Shape outShape = x.shape();
  if (keepdim)
    outShape[s.axis] = 1;
  else
    outShape.erase(outShape.begin() + s.axis);
  Tensor out = Tensor::empty(outShape, x.dtype());
  launchSlices("lse", "forward", s, x.dtype(), {x.buffer(), out.buffer()});
  if (!needsGrad({x}))
    return out;
  return record("logSumExp", out, {x}, [xd = x.detach(), od = out.detach(), s](const Tensor& g) {
    Tensor dx = Tensor::empty(xd.shape(), xd.dtype());
    launchSlices("lse", "backward", s, xd.dtype(),
                 {xd.buffer(), od.buffer(), g.buffer(), dx.buffer()});
    return std::vector<Tensor>{dx};
  });
}

} // namespace simpli::ocl

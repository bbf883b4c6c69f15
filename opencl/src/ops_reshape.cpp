#include "simpli/ocl/ops_reshape.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_reduce.h"

namespace simpli::ocl {

Tensor reshape(const Tensor& x, const Shape& shape) {
  if (!x.defined())
    fail("reshape: undefined tensor");
  Shape target = shape;
  int inferred = -1;
  int64_t known = 1;
  for (std::size_t d = 0; d < target.size(); ++d) {
    if (target[d] == -1) {
      if (inferred >= 0)
        fail("reshape: more than one -1 in ", toString(shape));
      inferred = static_cast<int>(d);
    } else {
      known *= target[d];
    }
  }
  if (inferred >= 0) {
    if (known == 0 || x.numel() % known != 0)
      fail("reshape: cannot reshape ", x.describe(), " to ", toString(shape));
    target[inferred] = x.numel() / known;
  }
  if (numelOf(target) != x.numel())
    fail("reshape: cannot reshape ", x.describe(), " to ", toString(shape));
  Tensor out = x.viewAs(target);
  return record("reshape", out, {x}, [source = x.shape()](const Tensor& g) {
    return std::vector<Tensor>{reshape(g, source)};
  });
}

Tensor squeeze(const Tensor& x, int axis) {
  if (!x.defined())
    fail("squeeze: undefined tensor");
  const int a = normaliseAxis(axis, x.dim(), "squeeze", x.shape());
  if (x.shape()[a] != 1)
    fail("squeeze: axis ", axis, " of ", x.describe(), " has size ", x.shape()[a], ", not 1");
  Shape target = x.shape();
  target.erase(target.begin() + a);
  return reshape(x, target);
}

Tensor unsqueeze(const Tensor& x, int axis) {
  if (!x.defined())
    fail("unsqueeze: undefined tensor");
  // The new axis may sit anywhere from before the first to after the last dimension.
  const int a = normaliseAxis(axis, x.dim() + 1, "unsqueeze", x.shape());
  if (x.dim() >= kMaxDims)
    fail("unsqueeze: ", x.describe(), " already has the maximum of ", kMaxDims, " dimensions");
  Shape target = x.shape();
  target.insert(target.begin() + a, 1);
  return reshape(x, target);
}

} // namespace simpli::ocl

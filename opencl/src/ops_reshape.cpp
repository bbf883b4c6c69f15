#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_shape.h"

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

} // namespace simpli::ocl

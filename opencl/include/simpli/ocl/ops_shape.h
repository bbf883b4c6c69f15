#pragma once
// Shape ops. Tensors are contiguous, so reshape is free; the others copy.
#include "simpli/ocl/tensor.h"

#include <vector>

namespace simpli::ocl {

/// Same data, new shape of equal numel; one dimension may be -1 (inferred).
Tensor reshape(const Tensor& x, const Shape& shape);

} // namespace simpli::ocl

#pragma once
// Reshapes (ops_reshape.cpp): tensors are contiguous, so these are free (a new shape on the same
// buffer), differentiable and recorded on the tape; negative axes count from the end. Included
// by ops_shape.h with the shape ops that copy.
#include "simpli/ocl/tensor.h"

namespace simpli::ocl {

/// Same data, new shape of equal numel; one dimension may be -1 (inferred).
Tensor reshape(const Tensor& x, const Shape& shape);
/// Removes dimension `axis`, which must have size 1.
Tensor squeeze(const Tensor& x, int axis);
/// Inserts a dimension of size 1 before position `axis` (in [-(rank+1), rank]).
Tensor unsqueeze(const Tensor& x, int axis);

} // namespace simpli::ocl

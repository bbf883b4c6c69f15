#pragma once
// Reductions over one axis (negative axes count from the end) and over all elements.
#include "simpli/ocl/tensor.h"

namespace simpli::ocl {

Tensor sum(const Tensor& x, int axis, bool keepdim = false);
Tensor mean(const Tensor& x, int axis, bool keepdim = false);
/// Variance over `axis`: unbiased (divides by n - 1) or biased (by n). Two-pass per output
/// element (mean first), so large offsets do not cancel.
Tensor variance(const Tensor& x, int axis, bool unbiased, bool keepdim = false);
/// Sum / mean of every element, shape [1].
Tensor sumAll(const Tensor& x);
Tensor meanAll(const Tensor& x);
/// Broadcasts x to `shape` (NumPy rules) by copying; the gradient sums back.
Tensor expand(const Tensor& x, const Shape& shape);

/// Normalises a possibly negative axis for a tensor of `rank` dims; throws naming `op`.
int normaliseAxis(int axis, int rank, const char* op, const Shape& shape);

} // namespace simpli::ocl

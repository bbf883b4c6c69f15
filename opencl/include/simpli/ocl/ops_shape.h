#pragma once
// Shape ops. Tensors are contiguous, so reshape, squeeze and unsqueeze (ops_reshape.h, included
// here) are free; the ops below copy. All are differentiable and recorded on the tape; negative
// axes count from the end. Ops whose result would have no elements throw (an empty slice is almost
// always a bug in the caller's index arithmetic).
#include "simpli/ocl/ops_reshape.h"
#include "simpli/ocl/tensor.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace simpli::ocl {

/// Joins tensors of equal rank and dtype along `axis`; all other dimensions must match.
Tensor concat(const std::vector<Tensor>& xs, int axis);

/// Elements start, start+step, ... before end along `axis`, with Python semantics: negative
/// start/end count from the end, out-of-range values clamp, step may be negative (not 0).
Tensor slice(const Tensor& x, int axis, int64_t start, int64_t end, int64_t step = 1);

/// out.shape[d] = x.shape[perm[d]]; perm must list every axis exactly once.
Tensor permute(const Tensor& x, const std::vector<int>& perm);
/// Swaps two axes.
Tensor transpose(const Tensor& x, int axisA, int axisB);

enum class PadMode { Zeros, Replicate };
/// Pads every axis by padding[d] = (before, after) elements (non-negative; one pair per axis).
/// Replicate repeats the border element (and needs a non-empty axis).
Tensor pad(const Tensor& x, const std::vector<std::pair<int64_t, int64_t>>& padding,
           PadMode mode = PadMode::Zeros);

/// The slices x[..., indices[j], ...] along `axis`, stacked in order (indices may repeat and
/// may be negative, Python style). The gradient sums over repeats.
Tensor indexSelect(const Tensor& x, int axis, const std::vector<int64_t>& indices);

} // namespace simpli::ocl

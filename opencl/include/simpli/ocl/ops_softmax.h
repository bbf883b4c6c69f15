#pragma once
// Softmax and log-sum-exp over one axis (negative axes count from the end). Both subtract the
// maximum first, so logits of any finite magnitude (1e4, 1e30) give finite results.
#include "simpli/ocl/tensor.h"

namespace simpli::ocl {

/// exp(x - max) / sum exp(x - max) along `axis`; same shape as x.
Tensor softmax(const Tensor& x, int axis);
/// max + log(sum exp(x - max)) along `axis` (the axis removed unless keepdim). A slice whose
/// maximum is -inf gives -inf, one whose maximum is +inf gives +inf.
Tensor logSumExp(const Tensor& x, int axis, bool keepdim = false);

} // namespace simpli::ocl

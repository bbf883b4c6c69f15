#pragma once
// Matrix products through CLBlast (tuned GEMM), differentiable (the backward is GEMMs too).
#include "simpli/ocl/tensor.h"

#include <string>

namespace simpli::ocl {

/// Matrix product op(a) * op(b), where op transposes the last two dimensions when the flag is
/// set. Shapes (without transposition):
///   a [M, K]    x b [K, N]    -> [M, N]
///   a [B, M, K] x b [B, K, N] -> [B, M, N]   (batched; either batch may be 1 or the operand
///                                             rank 2, and it is then shared by every entry)
/// With transA, a is stored [..., K, M]; with transB, b is stored [..., N, K]. Both operands
/// must have the same dtype. Throws simpli::Error naming the op and both shapes on mismatch.
Tensor matmul(const Tensor& a, const Tensor& b, bool transA = false, bool transB = false);

/// Fully connected layer in PyTorch's layout: x [..., in], weight [out, in], bias [out] or
/// undefined -> x * weight^T + bias, shape [..., out].
Tensor linear(const Tensor& x, const Tensor& weight, const Tensor& bias = Tensor());

/// One line saying which CLBlast tuning parameters the current device runs with (table and
/// number of kernel families, or CLBlast's defaults); see docs/clblast_tuning.md.
std::string clblastTuningSummary();

} // namespace simpli::ocl

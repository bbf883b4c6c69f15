#pragma once
// Fused scaled dot-product attention over many small independent sequences (thousands to
// millions of sequences of a few to a few dozen tokens: one per pixel). Composing it from
// batched GEMMs and a softmax costs one tiny GEMM per sequence; this op runs one work item per
// query and never stores the scores, so memory stays O(output).
#include "simpli/ocl/tensor.h"

namespace simpli::ocl {

/// out[n, i, :] = sum_j softmax_j(scale * q[n, i, :] . k[n, j, :]) v[n, j, :].
/// q [N, nq, d] or [nq, d] (queries shared by every sequence), k [N, nk, d], v [N, nk, dv]
/// -> [N, nq, dv]. The softmax subtracts the maximum score, so large logits stay finite.
/// Differentiable in q, k and v.
Tensor attention(const Tensor& q, const Tensor& k, const Tensor& v, double scale);

} // namespace simpli::ocl

#pragma once
// Normalisation layers. Both are differentiable with respect to the input and the affine
// parameters, in float and double.
#include "simpli/ocl/tensor.h"

namespace simpli::ocl {

/// SIMPLI's "total" layer norm (reference §4.1, the `'ln'` norm). x is [N, C, ...] (rank >= 2):
/// per sample n, over ALL of its C * prod(...) elements, mu = mean and s = the unbiased (n - 1)
/// standard deviation; y = (x - mu) / (s + eps), then gamma[c] * y + beta[c] with c = axis 1.
/// Not GroupNorm(1): different variance estimator and eps placement. A constant sample gives
/// exactly beta (x - mu is exactly 0), with finite gradients. gamma and beta are [C].
Tensor layerNormTotal(const Tensor& x, const Tensor& gamma, const Tensor& beta, double eps = 1e-5);

/// Standard LayerNorm over the last axis (reference §4.6): x is [..., D];
/// y = (x - mean) / sqrt(biased var + eps) * weight + bias, weight and bias [D].
Tensor layerNorm(const Tensor& x, const Tensor& weight, const Tensor& bias, double eps = 1e-6);

} // namespace simpli::ocl

#pragma once
// Internal: GEMMs with one dimension of at most 32 (convolutions with few output channels,
// linear layers with few outputs or inputs, per-pixel projections) run on the engine's own
// register-blocked kernels (kernels/gemm_skinny.cl) instead of CLBlast, which pads such shapes
// to its 64 x 128 tiles. SIMPLI_GEMM_SKINNY=0 turns the path off (to compare with CLBlast).
#include "clblast_call.h"

namespace simpli::ocl::blas {

/// Runs C = alpha op(A) op(B) + beta C (batched: `batch` products `stride*` elements apart)
/// when the shape suits the skinny kernels and every index fits in 32 bits; returns false
/// (doing nothing) otherwise.
bool trySkinnyGemm(Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha, const Operand& a,
                   std::size_t strideA, const Operand& b, std::size_t strideB, double beta,
                   cl_mem c, std::size_t cOffset, std::size_t ldc, std::size_t strideC,
                   int64_t batch);

} // namespace simpli::ocl::blas

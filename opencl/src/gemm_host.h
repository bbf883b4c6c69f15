#pragma once
// Internal: the host-BLAS GEMM backend (simpli/ocl/gemm_backend.h). The operands' device
// buffers are mapped (blocking, so the in-order queue has drained; zero copy on a CPU device
// whose buffers are host memory), multiplied by cblas_sgemm / cblas_dgemm with OpenBLAS using as
// many threads as the device has compute units, and unmapped.
#include "clblast_call.h"

namespace simpli::ocl::blas {

/// Products with at most this many rows or columns try the engine's skinny kernels before the
/// host BLAS: measured on 2 EPYC cores under PoCL, 16x24576x144 took 2.1 ms on gemm_skinny.cl vs
/// 4.5 ms in OpenBLAS, 98304x16x7 0.7 vs 2.7 ms, while at 32 rows OpenBLAS was faster.
constexpr int64_t kSkinnyBeforeHost = 16;

/// Whether the host backend serves the current device (SIMPLI_GEMM / setGemmBackend resolved).
bool hostGemmSelected();

/// Runs C = alpha op(A) op(B) + beta C (batched: `batch` products `stride*` elements apart) on
/// the host BLAS when that backend is selected for the current device and the shape suits it
/// (sizes within BLAS's 32-bit int; batches of small products stay on the device, whose
/// kernels run them in one launch); returns false (doing nothing) otherwise.
bool tryHostGemm(Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha, const Operand& a,
                 std::size_t strideA, const Operand& b, std::size_t strideB, double beta, cl_mem c,
                 std::size_t cOffset, std::size_t ldc, std::size_t strideC, int64_t batch);

} // namespace simpli::ocl::blas

#pragma once
// Internal: the host-BLAS GEMM backend (simpli/ocl/gemm_backend.h). The operands' device
// buffers are mapped (blocking, so the in-order queue has drained; zero copy on a CPU device
// whose buffers are host memory), multiplied by cblas_sgemm / cblas_dgemm with OpenBLAS using as
// many threads as the device has compute units, and unmapped.
#include "clblast_call.h"

namespace simpli::ocl::blas {

/// Runs C = alpha op(A) op(B) + beta C (batched: `batch` products `stride*` elements apart) on
/// the host BLAS when that backend is selected for the current device and the shape suits it
/// (sizes within BLAS's 32-bit int; batches of small products stay on the device, whose
/// kernels run them in one launch); returns false (doing nothing) otherwise.
bool tryHostGemm(Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha, const Operand& a,
                 std::size_t strideA, const Operand& b, std::size_t strideB, double beta, cl_mem c,
                 std::size_t cOffset, std::size_t ldc, std::size_t strideC, int64_t batch);

} // namespace simpli::ocl::blas

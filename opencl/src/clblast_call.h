#pragma once
// Internal: row-major GEMMs on device buffers, in the tensor's precision, on the current device's
// queue: the host BLAS where that backend is selected (gemm_host.h, simpli/ocl/gemm_backend.h),
// else the engine's skinny kernels (gemm_skinny.h) or CLBlast. Offsets and leading dimensions are in elements. Failures throw
// simpli::Error naming the calling op, the CLBlast routine, its status and the sizes.
#include "simpli/ocl/dtype.h"

#include <CL/cl.h>

#include <cstddef>
#include <cstdint>

namespace simpli::ocl::blas {

/// One operand: a buffer, an element offset, a leading dimension (row stride) and whether it is
/// used transposed.
struct Operand {
  cl_mem mem = nullptr;
  std::size_t offset = 0;
  std::size_t ld = 0;
  bool trans = false;
};

/// C[m, n] = alpha * op(A)[m, k] * op(B)[k, n] + beta * C.
void gemm(const char* op, Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha,
          const Operand& a, const Operand& b, double beta, cl_mem c, std::size_t cOffset,
          std::size_t ldc);

/// `batch` GEMMs whose operands lie `strideA/B/C` elements apart (a stride of 0 reuses the same
/// matrix for every batch entry).
void gemmStridedBatched(const char* op, Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha,
                        const Operand& a, std::size_t strideA, const Operand& b,
                        std::size_t strideB, double beta, cl_mem c, std::size_t cOffset,
                        std::size_t ldc, std::size_t strideC, int64_t batch);

/// CLBlast's own name for a status code (e.g. "kInvalidLeadDimA").
const char* statusName(int status);

} // namespace simpli::ocl::blas

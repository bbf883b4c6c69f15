#include "clblast_call.h"

#include "gemm_host.h"
#include "gemm_skinny.h"

#include "simpli/error.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/profiler.h"

#include <clblast.h>

#include <algorithm>
#include <memory>

namespace simpli::ocl::blas {
namespace {

clblast::Transpose transOf(bool t) {
  return t ? clblast::Transpose::kYes : clblast::Transpose::kNo;
}

void check(clblast::StatusCode status, const char* op, const char* routine, int64_t m, int64_t n,
           int64_t k, int64_t batch) {
  if (status == clblast::StatusCode::kSuccess)
    return;
  fail(op, ": CLBlast ", routine, " failed with ", statusName(static_cast<int>(status)), " (",
       static_cast<int>(status), ") for m=", m, " n=", n, " k=", k, " batch=", batch);
}

void checkSizes(const char* op, int64_t m, int64_t n, int64_t k) {
  if (m < 0 || n < 0 || k < 0)
    fail(op, ": negative GEMM size m=", m, " n=", n, " k=", k);
}

// Profile entry name with the GEMM's shape ("clblast.Gemm NT 16x24576x144").
std::string gemmName(const char* what, const Operand& a, const Operand& b, int64_t m, int64_t n,
                     int64_t k) {
  return std::string(what) + " " + (a.trans ? "T" : "N") + (b.trans ? "T" : "N") + " " +
         std::to_string(m) + "x" + std::to_string(n) + "x" + std::to_string(k);
}

// Everything that selects the kernels and work sizes CLBlast launches for a GEMM: routine,
// precision, shape, transposes, leading dimensions, whether operands start at offset 0 (else it
// copies them), batch. Device::settleFirstUse finishes the queue the first time a key is seen
// (PoCL compiles each CLBlast kernel at its first launch; see Device::settleFirstLaunch).
template <typename T>
std::string firstUseKey(const char* routine, const Operand& a, const Operand& b, int64_t m,
                        int64_t n, int64_t k, std::size_t cOffset, std::size_t ldc, int64_t batch) {
  return std::string(routine) + (sizeof(T) == 8 ? " f64 " : " f32 ") + gemmName("", a, b, m, n, k) +
         " ld " + std::to_string(a.ld) + "," + std::to_string(b.ld) + "," + std::to_string(ldc) +
         " off0 " + std::to_string(a.offset == 0) + std::to_string(b.offset == 0) +
         std::to_string(cOffset == 0) + " x" + std::to_string(batch);
}

template <typename T>
void gemmT(const char* op, int64_t m, int64_t n, int64_t k, double alpha, const Operand& a,
           const Operand& b, double beta, cl_mem c, std::size_t cOffset, std::size_t ldc) {
  Device& device = Device::current();
  cl_command_queue queue = device.queue();
  const auto M = static_cast<std::size_t>(m), N = static_cast<std::size_t>(n),
             K = static_cast<std::size_t>(k);
  // CLBlast allocates its padding/transposition scratch per call unless given one; a pooled
  // buffer avoids fresh (page-faulting) allocations on every GEMM. The in-order queue makes
  // reuse by a later op safe once this handle is released.
  std::size_t tempBytes = 0;
  std::shared_ptr<Buffer> temp;
  auto status = clblast::GemmTempBufferSize<T>(clblast::Layout::kRowMajor, transOf(a.trans),
                                               transOf(b.trans), M, N, K, a.offset, a.ld, b.offset,
                                               b.ld, cOffset, ldc, &queue, tempBytes);
  check(status, op, "GemmTempBufferSize", m, n, k, 1);
  if (tempBytes > 0)
    temp = device.pool().acquire(tempBytes);
  const Profiler::Scope profile(Profiler::enabled() ? gemmName("clblast.Gemm", a, b, m, n, k)
                                                    : std::string());
  status = clblast::Gemm<T>(clblast::Layout::kRowMajor, transOf(a.trans), transOf(b.trans), M, N, K,
                            static_cast<T>(alpha), a.mem, a.offset, a.ld, b.mem, b.offset, b.ld,
                            static_cast<T>(beta), c, cOffset, ldc, &queue, nullptr,
                            temp ? temp->mem() : nullptr);
  check(status, op, "Gemm", m, n, k, 1);
  device.settleFirstUse(firstUseKey<T>("Gemm", a, b, m, n, k, cOffset, ldc, 1));
}

template <typename T>
void batchedT(const char* op, int64_t m, int64_t n, int64_t k, double alpha, const Operand& a,
              std::size_t strideA, const Operand& b, std::size_t strideB, double beta, cl_mem c,
              std::size_t cOffset, std::size_t ldc, std::size_t strideC, int64_t batch) {
  Device& device = Device::current();
  cl_command_queue queue = device.queue();
  const Profiler::Scope profile(Profiler::enabled()
                                    ? gemmName("clblast.GemmStridedBatched", a, b, m, n, k) + " x" +
                                          std::to_string(batch)
                                    : std::string());
  const auto status = clblast::GemmStridedBatched<T>(
      clblast::Layout::kRowMajor, transOf(a.trans), transOf(b.trans), static_cast<std::size_t>(m),
      static_cast<std::size_t>(n), static_cast<std::size_t>(k), static_cast<T>(alpha), a.mem,
      a.offset, a.ld, strideA, b.mem, b.offset, b.ld, strideB, static_cast<T>(beta), c, cOffset,
      ldc, strideC, static_cast<std::size_t>(batch), &queue, nullptr);
  check(status, op, "GemmStridedBatched", m, n, k, batch);
  device.settleFirstUse(firstUseKey<T>("GemmStridedBatched", a, b, m, n, k, cOffset, ldc, batch));
}

} // namespace

void gemm(const char* op, Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha,
          const Operand& a, const Operand& b, double beta, cl_mem c, std::size_t cOffset,
          std::size_t ldc) {
  checkSizes(op, m, n, k);
  if (m == 0 || n == 0)
    return;
  const bool skinnyFirst = std::min(m, n) <= kSkinnyBeforeHost || !hostGemmSelected();
  if (skinnyFirst && trySkinnyGemm(dtype, m, n, k, alpha, a, 0, b, 0, beta, c, cOffset, ldc, 0, 1))
    return;
  if (tryHostGemm(dtype, m, n, k, alpha, a, 0, b, 0, beta, c, cOffset, ldc, 0, 1))
    return;
  if (!skinnyFirst && trySkinnyGemm(dtype, m, n, k, alpha, a, 0, b, 0, beta, c, cOffset, ldc, 0, 1))
    return;
  if (dtype == Dtype::F64)
    gemmT<double>(op, m, n, k, alpha, a, b, beta, c, cOffset, ldc);
  else
    gemmT<float>(op, m, n, k, alpha, a, b, beta, c, cOffset, ldc);
}

void gemmStridedBatched(const char* op, Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha,
                        const Operand& a, std::size_t strideA, const Operand& b,
                        std::size_t strideB, double beta, cl_mem c, std::size_t cOffset,
                        std::size_t ldc, std::size_t strideC, int64_t batch) {
  checkSizes(op, m, n, k);
  if (m == 0 || n == 0 || batch == 0)
    return;
  if (batch == 1) { // the plain routine takes the temp buffer and is tuned per routine
    gemm(op, dtype, m, n, k, alpha, a, b, beta, c, cOffset, ldc);
    return;
  }
  const bool skinnyFirst = std::min(m, n) <= kSkinnyBeforeHost || !hostGemmSelected();
  if (skinnyFirst && trySkinnyGemm(dtype, m, n, k, alpha, a, strideA, b, strideB, beta, c, cOffset,
                                   ldc, strideC, batch))
    return;
  if (tryHostGemm(dtype, m, n, k, alpha, a, strideA, b, strideB, beta, c, cOffset, ldc, strideC,
                  batch))
    return;
  if (!skinnyFirst && trySkinnyGemm(dtype, m, n, k, alpha, a, strideA, b, strideB, beta, c, cOffset,
                                    ldc, strideC, batch))
    return;
  if (dtype == Dtype::F64)
    batchedT<double>(op, m, n, k, alpha, a, strideA, b, strideB, beta, c, cOffset, ldc, strideC,
                     batch);
  else
    batchedT<float>(op, m, n, k, alpha, a, strideA, b, strideB, beta, c, cOffset, ldc, strideC,
                    batch);
}

const char* statusName(int status) {
  using S = clblast::StatusCode;
  switch (static_cast<S>(status)) {
  case S::kSuccess:
    return "kSuccess";
  case S::kOpenCLCompilerNotAvailable:
    return "kOpenCLCompilerNotAvailable";
  case S::kTempBufferAllocFailure:
    return "kTempBufferAllocFailure";
  case S::kOpenCLOutOfResources:
    return "kOpenCLOutOfResources";
  case S::kOpenCLOutOfHostMemory:
    return "kOpenCLOutOfHostMemory";
  case S::kOpenCLBuildProgramFailure:
    return "kOpenCLBuildProgramFailure";
  case S::kInvalidValue:
    return "kInvalidValue";
  case S::kInvalidCommandQueue:
    return "kInvalidCommandQueue";
  case S::kInvalidMemObject:
    return "kInvalidMemObject";
  case S::kInvalidBinary:
    return "kInvalidBinary";
  case S::kInvalidBuildOptions:
    return "kInvalidBuildOptions";
  case S::kInvalidProgram:
    return "kInvalidProgram";
  case S::kInvalidProgramExecutable:
    return "kInvalidProgramExecutable";
  case S::kInvalidKernelName:
    return "kInvalidKernelName";
  case S::kInvalidKernelDefinition:
    return "kInvalidKernelDefinition";
  case S::kInvalidKernel:
    return "kInvalidKernel";
  case S::kInvalidArgIndex:
    return "kInvalidArgIndex";
  case S::kInvalidArgValue:
    return "kInvalidArgValue";
  case S::kInvalidArgSize:
    return "kInvalidArgSize";
  case S::kInvalidKernelArgs:
    return "kInvalidKernelArgs";
  case S::kInvalidLocalNumDimensions:
    return "kInvalidLocalNumDimensions";
  case S::kInvalidLocalThreadsTotal:
    return "kInvalidLocalThreadsTotal";
  case S::kInvalidLocalThreadsDim:
    return "kInvalidLocalThreadsDim";
  case S::kInvalidGlobalOffset:
    return "kInvalidGlobalOffset";
  case S::kInvalidEventWaitList:
    return "kInvalidEventWaitList";
  case S::kInvalidEvent:
    return "kInvalidEvent";
  case S::kInvalidOperation:
    return "kInvalidOperation";
  case S::kInvalidBufferSize:
    return "kInvalidBufferSize";
  case S::kInvalidGlobalWorkSize:
    return "kInvalidGlobalWorkSize";
  case S::kNotImplemented:
    return "kNotImplemented";
  case S::kInvalidMatrixA:
    return "kInvalidMatrixA";
  case S::kInvalidMatrixB:
    return "kInvalidMatrixB";
  case S::kInvalidMatrixC:
    return "kInvalidMatrixC";
  case S::kInvalidVectorX:
    return "kInvalidVectorX";
  case S::kInvalidVectorY:
    return "kInvalidVectorY";
  case S::kInvalidDimension:
    return "kInvalidDimension";
  case S::kInvalidLeadDimA:
    return "kInvalidLeadDimA";
  case S::kInvalidLeadDimB:
    return "kInvalidLeadDimB";
  case S::kInvalidLeadDimC:
    return "kInvalidLeadDimC";
  case S::kInvalidIncrementX:
    return "kInvalidIncrementX";
  case S::kInvalidIncrementY:
    return "kInvalidIncrementY";
  case S::kInsufficientMemoryA:
    return "kInsufficientMemoryA";
  case S::kInsufficientMemoryB:
    return "kInsufficientMemoryB";
  case S::kInsufficientMemoryC:
    return "kInsufficientMemoryC";
  case S::kInsufficientMemoryX:
    return "kInsufficientMemoryX";
  case S::kInsufficientMemoryY:
    return "kInsufficientMemoryY";
  case S::kInsufficientMemoryTemp:
    return "kInsufficientMemoryTemp";
  case S::kInvalidBatchCount:
    return "kInvalidBatchCount";
  case S::kInvalidOverrideKernel:
    return "kInvalidOverrideKernel";
  case S::kMissingOverrideParameter:
    return "kMissingOverrideParameter";
  case S::kInvalidLocalMemUsage:
    return "kInvalidLocalMemUsage";
  case S::kNoHalfPrecision:
    return "kNoHalfPrecision";
  case S::kNoDoublePrecision:
    return "kNoDoublePrecision";
  case S::kInvalidVectorScalar:
    return "kInvalidVectorScalar";
  case S::kInsufficientMemoryScalar:
    return "kInsufficientMemoryScalar";
  case S::kDatabaseError:
    return "kDatabaseError";
  case S::kUnknownError:
    return "kUnknownError";
  case S::kUnexpectedError:
    return "kUnexpectedError";
  }
  return "unknown CLBlast status";
}

} // namespace simpli::ocl::blas

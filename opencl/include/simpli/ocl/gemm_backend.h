#pragma once
// Which library runs the engine's GEMMs (matmul, linear, the convolutions' im2col products).
// On an OpenCL CPU device (PoCL) the buffers are host memory, so the host's BLAS (OpenBLAS)
// can work on them in place through a blocking map (zero copy) and is 2-4x faster than
// CLBlast's kernels compiled by PoCL; on a GPU, CLBlast (and the engine's skinny kernels)
// run on the device. See docs/architecture.md, "GEMM backends".
//
// The choice: setGemmBackend() if called, else SIMPLI_GEMM = auto | host | clblast (default
// auto: host on CL_DEVICE_TYPE_CPU devices, clblast elsewhere). `host` on a GPU works (the
// map copies) but is slow; `clblast` on a CPU device is the previous behaviour.
#include <string>

namespace simpli::ocl {

enum class GemmBackend {
  Auto,    ///< host on CPU devices, clblast elsewhere
  Host,    ///< cblas_sgemm / cblas_dgemm on mapped device buffers
  Clblast, ///< CLBlast and the engine's skinny / split-k kernels (gemm_skinny.cl)
};

/// "auto", "host" or "clblast".
const char* toString(GemmBackend backend);
/// Parses "auto", "host" or "clblast"; throws simpli::Error naming `origin` and the value.
GemmBackend parseGemmBackend(const std::string& text, const std::string& origin);

/// The configured choice (SIMPLI_GEMM, or the last setGemmBackend()); may be Auto.
GemmBackend gemmBackendSetting();
/// Overrides SIMPLI_GEMM for the process (tests, benchmarks); returns the previous setting.
GemmBackend setGemmBackend(GemmBackend backend);
/// What runs GEMMs on the current device: Host or Clblast (Auto resolved). Opens the device.
GemmBackend gemmBackend();
/// One line for logs and benchmarks, e.g. "host (OpenBLAS 0.3.21 ... core SkylakeX, 2 threads;
/// SIMPLI_GEMM=auto, CPU device)".
std::string gemmBackendSummary();

} // namespace simpli::ocl

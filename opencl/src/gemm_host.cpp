#include "gemm_host.h"

#include "simpli/error.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/gemm_backend.h"
#include "simpli/ocl/profiler.h"

#include <cblas.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace simpli::ocl {
namespace {

std::optional<GemmBackend>& overridden() {
  static std::optional<GemmBackend> backend;
  return backend;
}

GemmBackend fromEnvironment() {
  static const GemmBackend backend = [] {
    const char* env = std::getenv("SIMPLI_GEMM");
    return env && *env ? parseGemmBackend(env, "SIMPLI_GEMM") : GemmBackend::Auto;
  }();
  return backend;
}

bool isCpuDevice(const Device& device) {
  cl_device_type type = 0;
  checkCl(clGetDeviceInfo(device.id(), CL_DEVICE_TYPE, sizeof(type), &type, nullptr),
          "clGetDeviceInfo(CL_DEVICE_TYPE)");
  return (type & CL_DEVICE_TYPE_CPU) != 0;
}

// The backend for `device`, with OpenBLAS's thread count set to the device's compute units the
// first time the host backend serves a device (PoCL runs one worker per compute unit, so both
// use the same cores, and never at once: the map drains the queue first).
GemmBackend resolvedFor(Device& device) {
  static cl_device_id known = nullptr;
  static bool cpu = false, threadsSet = false;
  if (known != device.id()) {
    known = device.id();
    cpu = isCpuDevice(device);
    threadsSet = false;
  }
  GemmBackend b = gemmBackendSetting();
  if (b == GemmBackend::Auto)
    b = cpu ? GemmBackend::Host : GemmBackend::Clblast;
  if (b == GemmBackend::Host && !threadsSet) {
    openblas_set_num_threads(std::max(1, device.info().computeUnits));
    threadsSet = true;
  }
  return b;
}

} // namespace

const char* toString(GemmBackend backend) {
  switch (backend) {
  case GemmBackend::Auto:
    return "auto";
  case GemmBackend::Host:
    return "host";
  case GemmBackend::Clblast:
    return "clblast";
  }
  return "?";
}

GemmBackend parseGemmBackend(const std::string& text, const std::string& origin) {
  for (GemmBackend b : {GemmBackend::Auto, GemmBackend::Host, GemmBackend::Clblast})
    if (text == toString(b))
      return b;
  fail(origin, " '", text, "': expected auto, host or clblast");
}

GemmBackend gemmBackendSetting() {
  return overridden() ? *overridden() : fromEnvironment();
}

GemmBackend setGemmBackend(GemmBackend backend) {
  const GemmBackend previous = gemmBackendSetting();
  overridden() = backend;
  return previous;
}

GemmBackend gemmBackend() {
  return resolvedFor(Device::current());
}

std::string gemmBackendSummary() {
  Device& device = Device::current();
  const GemmBackend b = resolvedFor(device);
  std::string s = toString(b);
  if (b == GemmBackend::Host) {
    // How long idle worker threads spin (2^N cycles), read by OpenBLAS when it loaded.
    const char* timeout = std::getenv("OPENBLAS_THREAD_TIMEOUT");
    s += std::string(" (") + openblas_get_config() + ", core " + openblas_get_corename() + ", " +
         std::to_string(openblas_get_num_threads()) +
         " thread(s), OPENBLAS_THREAD_TIMEOUT=" + (timeout ? timeout : "unset") + ")";
  } else {
    s += " (CLBlast, skinny kernels)";
  }
  s += std::string("; SIMPLI_GEMM=") + toString(gemmBackendSetting()) + ", " +
       (isCpuDevice(device) ? "CPU" : "non-CPU") + " device";
  return s;
}

namespace blas {
namespace {

// Batches of products smaller than this (m n k) stay on the device: a loop of tiny BLAS calls
// costs more in call overhead than one batched kernel launch.
constexpr int64_t kMinBatchedWork = 32 * 32 * 32;

// One mapped byte range of a buffer, shared by the operands that live in it.
struct Mapping {
  cl_mem mem = nullptr;
  std::size_t lo = 0, hi = 0; // bytes
  cl_map_flags flags = 0;
  char* ptr = nullptr;
};

class Mappings {
public:
  explicit Mappings(cl_command_queue queue) : queue_(queue) {}
  ~Mappings() {
    for (const Mapping& m : maps_)
      if (m.ptr)
        clEnqueueUnmapMemObject(queue_, m.mem, m.ptr, 0, nullptr, nullptr);
  }
  Mappings(const Mappings&) = delete;
  Mappings& operator=(const Mappings&) = delete;

  // Registers bytes [lo, hi) of `mem`; ranges of one buffer are merged.
  void need(cl_mem mem, std::size_t lo, std::size_t hi, cl_map_flags flags) {
    for (Mapping& m : maps_)
      if (m.mem == mem) {
        m.lo = std::min(m.lo, lo);
        m.hi = std::max(m.hi, hi);
        m.flags |= flags;
        return;
      }
    maps_.push_back({mem, lo, hi, flags, nullptr});
  }

  // Maps every range (blocking: waits for the queue's earlier commands).
  void map(const char* what) {
    for (Mapping& m : maps_) {
      cl_int status = CL_SUCCESS;
      void* p = clEnqueueMapBuffer(queue_, m.mem, CL_TRUE, m.flags, m.lo, m.hi - m.lo, 0, nullptr,
                                   nullptr, &status);
      checkCl(status, what);
      m.ptr = static_cast<char*>(p);
    }
  }

  // Host address of byte `offset` of `mem` (registered and mapped).
  char* at(cl_mem mem, std::size_t offset) const {
    for (const Mapping& m : maps_)
      if (m.mem == mem)
        return m.ptr + (offset - m.lo);
    return nullptr;
  }

private:
  cl_command_queue queue_;
  std::vector<Mapping> maps_;
};

// Elements [offset, last + 1) of a rows x cols block with leading dimension ld, `batch` times
// `stride` apart.
std::size_t endIndex(std::size_t offset, std::size_t stride, int64_t batch, int64_t rows,
                     int64_t cols, std::size_t ld) {
  return offset + std::size_t(batch - 1) * stride + std::size_t(rows - 1) * ld + std::size_t(cols);
}

bool fitsBlasInt(int64_t m, int64_t n, int64_t k, std::size_t lda, std::size_t ldb,
                 std::size_t ldc) {
  constexpr auto kMax = static_cast<std::size_t>(std::numeric_limits<int>::max());
  return std::size_t(m) <= kMax && std::size_t(n) <= kMax && std::size_t(k) <= kMax &&
         lda <= kMax && ldb <= kMax && ldc <= kMax;
}

CBLAS_TRANSPOSE cblasTrans(bool t) {
  return t ? CblasTrans : CblasNoTrans;
}

template <typename T>
void runBlas(int64_t m, int64_t n, int64_t k, double alpha, bool ta, const T* a, int lda, bool tb,
             const T* b, int ldb, double beta, T* c, int ldc) {
  if constexpr (sizeof(T) == 8)
    cblas_dgemm(CblasRowMajor, cblasTrans(ta), cblasTrans(tb), int(m), int(n), int(k), alpha, a,
                lda, b, ldb, beta, c, ldc);
  else
    cblas_sgemm(CblasRowMajor, cblasTrans(ta), cblasTrans(tb), int(m), int(n), int(k),
                static_cast<float>(alpha), a, lda, b, ldb, static_cast<float>(beta), c, ldc);
}

std::string profileName(const Operand& a, const Operand& b, int64_t m, int64_t n, int64_t k,
                        int64_t batch) {
  std::string s = std::string("host.Gemm ") + (a.trans ? "T" : "N") + (b.trans ? "T" : "N") + " " +
                  std::to_string(m) + "x" + std::to_string(n) + "x" + std::to_string(k);
  return batch > 1 ? s + " x" + std::to_string(batch) : s;
}

template <typename T>
void hostGemmT(int64_t m, int64_t n, int64_t k, double alpha, const Operand& a, std::size_t strideA,
               const Operand& b, std::size_t strideB, double beta, cl_mem c, std::size_t cOffset,
               std::size_t ldc, std::size_t strideC, int64_t batch) {
  const Profiler::Scope profile(Profiler::enabled() ? profileName(a, b, m, n, k, batch)
                                                    : std::string());
  constexpr std::size_t E = sizeof(T);
  // BLAS wants ld >= max(1, columns) even where k = 0 leaves an operand empty.
  const std::size_t lda = std::max<std::size_t>(a.ld, 1), ldb = std::max<std::size_t>(b.ld, 1);
  Mappings maps(Device::current().queue());
  if (k > 0) {
    maps.need(a.mem, a.offset * E,
              endIndex(a.offset, strideA, batch, a.trans ? k : m, a.trans ? m : k, lda) * E,
              CL_MAP_READ);
    maps.need(b.mem, b.offset * E,
              endIndex(b.offset, strideB, batch, b.trans ? n : k, b.trans ? k : n, ldb) * E,
              CL_MAP_READ);
  }
  maps.need(c, cOffset * E, endIndex(cOffset, strideC, batch, m, n, ldc) * E,
            CL_MAP_READ | CL_MAP_WRITE);
  maps.map("host GEMM: clEnqueueMapBuffer");
  const T* pa = k > 0 ? reinterpret_cast<const T*>(maps.at(a.mem, a.offset * E)) : nullptr;
  const T* pb = k > 0 ? reinterpret_cast<const T*>(maps.at(b.mem, b.offset * E)) : nullptr;
  T* pc = reinterpret_cast<T*>(maps.at(c, cOffset * E));
  for (int64_t i = 0; i < batch; ++i) {
    const auto s = static_cast<std::size_t>(i);
    runBlas<T>(m, n, k, alpha, a.trans, pa ? pa + s * strideA : pa, int(lda), b.trans,
               pb ? pb + s * strideB : pb, int(ldb), beta, pc + s * strideC, int(ldc));
  }
}

} // namespace

bool hostGemmSelected() {
  return resolvedFor(Device::current()) == GemmBackend::Host;
}

bool tryHostGemm(Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha, const Operand& a,
                 std::size_t strideA, const Operand& b, std::size_t strideB, double beta, cl_mem c,
                 std::size_t cOffset, std::size_t ldc, std::size_t strideC, int64_t batch) {
  if (m <= 0 || n <= 0 || k < 0 || batch <= 0)
    return false;
  if (!hostGemmSelected())
    return false;
  if (batch > 1 && m * n * k < kMinBatchedWork)
    return false;
  if (!fitsBlasInt(m, n, k, std::max<std::size_t>(a.ld, 1), std::max<std::size_t>(b.ld, 1), ldc))
    return false;
  if (dtype == Dtype::F64)
    hostGemmT<double>(m, n, k, alpha, a, strideA, b, strideB, beta, c, cOffset, ldc, strideC,
                      batch);
  else
    hostGemmT<float>(m, n, k, alpha, a, strideA, b, strideB, beta, c, cOffset, ldc, strideC, batch);
  return true;
}

} // namespace blas
} // namespace simpli::ocl

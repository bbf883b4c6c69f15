#include "gemm_skinny.h"

#include "simpli/ocl/launch.h"
#include "simpli/ocl/profiler.h"
#include "simpli/ocl/tensor.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <string>

namespace simpli::ocl::blas {
namespace {

bool skinnyEnabled() {
  static const bool enabled = [] {
    const char* env = std::getenv("SIMPLI_GEMM_SKINNY");
    return !(env && std::string(env) == "0");
  }();
  return enabled;
}

// Largest element index an operand touches: offset + (batch - 1) stride + the last element of
// a rows x cols row-major block with leading dimension ld.
int64_t lastIndex(std::size_t offset, std::size_t stride, int64_t batch, int64_t rows, int64_t cols,
                  std::size_t ld) {
  return int64_t(offset) + (batch - 1) * int64_t(stride) + (rows - 1) * int64_t(ld) + cols - 1;
}

// Small outputs with a long k, split into chunks of k reduced in parallel (gemm_splitk.cl):
// gemm_dot_m when both operands run along k (A as is, B transposed) and m <= 32; gemm_outer
// when m x n <= 256 whatever the transposes. Sizes were checked to fit 32-bit indices.
bool trySplitK(Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha, const Operand& a,
               std::size_t strideA, const Operand& b, std::size_t strideB, double beta, cl_mem c,
               std::size_t cOffset, std::size_t ldc, std::size_t strideC, int64_t batch) {
  const bool dot = !a.trans && b.trans && m <= 32 && k >= 64;
  const bool outer = !dot && m * n <= 256 && k >= 2048;
  if (!dot && !outer)
    return false;
  const int chunk = dot ? 512 : 256;
  const int64_t chunks = (k + chunk - 1) / chunk;
  if (chunks * batch * m * n > std::numeric_limits<int>::max() || batch > 65535)
    return false;
  std::string options = std::string("-DTA=") + (a.trans ? "1" : "0") +
                        " -DTB=" + (b.trans ? "1" : "0") + " -DKCHUNK=" + std::to_string(chunk);
  options += dot ? " -DSKINNY=" + std::to_string(m)
                 : " -DSM=" + std::to_string(m) + " -DSN=" + std::to_string(n);
  const Tensor part = Tensor::empty({batch * chunks * m * n}, dtype);
  Launch partial("gemm_splitk", dot ? "gemm_dot_m" : "gemm_outer", dtype, options);
  partial.arg(static_cast<int>(m)).arg(static_cast<int>(n)).arg(static_cast<int>(k));
  partial.arg(a.mem).arg(static_cast<int>(a.offset)).arg(static_cast<int>(a.ld));
  partial.arg(static_cast<int>(strideA));
  partial.arg(b.mem).arg(static_cast<int>(b.offset)).arg(static_cast<int>(b.ld));
  partial.arg(static_cast<int>(strideB)).arg(static_cast<int>(chunks)).arg(part);
  if (dot)
    partial.run3(n, chunks, batch, 16, 1, 1);
  else
    partial.run2(chunks, batch, 16, 1);
  Launch finish("gemm_splitk", "gemm_splitk_finish", dtype, options);
  finish.arg(static_cast<int>(m)).arg(static_cast<int>(n)).arg(static_cast<int>(chunks));
  finish.real(alpha).arg(part).real(beta).arg(c).arg(static_cast<int>(cOffset));
  finish.arg(static_cast<int>(ldc)).arg(static_cast<int>(strideC));
  finish.run3(n, m, batch, 16, 1, 1);
  return true;
}

bool fitsInt(const Operand& a, std::size_t strideA, const Operand& b, std::size_t strideB,
             std::size_t cOffset, std::size_t ldc, std::size_t strideC, int64_t m, int64_t n,
             int64_t k, int64_t batch) {
  constexpr int64_t kMax = std::numeric_limits<int>::max();
  const int64_t aRows = a.trans ? k : m, aCols = a.trans ? m : k;
  const int64_t bRows = b.trans ? n : k, bCols = b.trans ? k : n;
  return lastIndex(a.offset, strideA, batch, aRows, aCols, a.ld) <= kMax &&
         lastIndex(b.offset, strideB, batch, bRows, bCols, b.ld) <= kMax &&
         lastIndex(cOffset, strideC, batch, m, n, ldc) <= kMax && m <= kMax && n <= kMax &&
         k <= kMax;
}

// One launch of a gemm_skinny.cl kernel with the small dimension `small` compiled in, over
// `items` work items per batch entry.
void launchSkinny(const char* kernel, Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha,
                  const Operand& a, std::size_t strideA, const Operand& b, std::size_t strideB,
                  double beta, cl_mem c, std::size_t cOffset, std::size_t ldc, std::size_t strideC,
                  int64_t batch, int64_t small, int64_t items) {
  const std::string options = "-DSKINNY=" + std::to_string(small) +
                              " -DTA=" + (a.trans ? "1" : "0") + " -DTB=" + (b.trans ? "1" : "0");
  Launch launch("gemm_skinny", kernel, dtype, options);
  launch.arg(static_cast<int>(m)).arg(static_cast<int>(n)).arg(static_cast<int>(k)).real(alpha);
  launch.arg(a.mem).arg(static_cast<int>(a.offset)).arg(static_cast<int>(a.ld));
  launch.arg(a.trans ? 1 : 0).arg(static_cast<int>(strideA));
  launch.arg(b.mem).arg(static_cast<int>(b.offset)).arg(static_cast<int>(b.ld));
  launch.arg(b.trans ? 1 : 0).arg(static_cast<int>(strideB)).real(beta);
  launch.arg(c).arg(static_cast<int>(cOffset)).arg(static_cast<int>(ldc));
  launch.arg(static_cast<int>(strideC));
  launch.run2(items, batch, 64, 1);
}

} // namespace

bool trySkinnyGemm(Dtype dtype, int64_t m, int64_t n, int64_t k, double alpha, const Operand& a,
                   std::size_t strideA, const Operand& b, std::size_t strideB, double beta,
                   cl_mem c, std::size_t cOffset, std::size_t ldc, std::size_t strideC,
                   int64_t batch) {
  if (!skinnyEnabled() || m <= 0 || n <= 0 || k <= 0 || batch <= 0 ||
      !fitsInt(a, strideA, b, strideB, cOffset, ldc, strideC, m, n, k, batch))
    return false;
  if (trySplitK(dtype, m, n, k, alpha, a, strideA, b, strideB, beta, c, cOffset, ldc, strideC,
                batch))
    return true;
  const bool fewRows = m <= n;
  const int64_t small = fewRows ? m : n, large = fewRows ? n : m;
  if (batch > 65535)
    return false;
  // Few rows over contiguous columns (weights x columns, W^T x gradients): 8 columns per item
  // in vectors; up to 256 rows in blocks of 32 (each block one launch re-reading B).
  if (fewRows && !b.trans && m <= 256 && (m <= 32 || n * batch >= 1024)) {
    for (int64_t r0 = 0; r0 < m; r0 += 32) {
      const int64_t rows = std::min<int64_t>(32, m - r0);
      Operand ab = a;
      ab.offset += static_cast<std::size_t>(r0) * (a.trans ? 1 : a.ld);
      launchSkinny("gemm_skinny_m8", dtype, rows, n, k, alpha, ab, strideA, b, strideB, beta, c,
                   cOffset + static_cast<std::size_t>(r0) * ldc, ldc, strideC, batch, rows,
                   (n + 7) / 8);
    }
    return true;
  }
  // Few work items with a long k each: CLBlast's tiles parallelise better.
  if (small > 32 || (large * batch < 256 && k > 64))
    return false;
  const char* kernel = fewRows
                           ? "gemm_skinny_m"
                           : (!a.trans && b.trans && k >= 16 ? "gemm_skinny_n8" : "gemm_skinny_n");
  launchSkinny(kernel, dtype, m, n, k, alpha, a, strideA, b, strideB, beta, c, cOffset, ldc,
               strideC, batch, small, large);
  return true;
}

} // namespace simpli::ocl::blas

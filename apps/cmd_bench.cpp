// `simpli bench ops`: times the engine's heavy ops (CLBlast GEMM, im2col + GEMM convolutions)
// on the selected OpenCL device and, in the same run on the same cores, OpenBLAS doing the same
// work (sgemm; im2col + sgemm for the convolutions). Prints the median time, GFLOP/s, the
// speed ratio device / OpenBLAS and the largest relative difference of the two results.
// Measures, never asserts: CI runs `--quick` as a smoke test only.
//
// OpenBLAS chooses its kernel once, when the library loads, and honours OPENBLAS_CORETYPE (and
// OPENBLAS_L2_SIZE) from the environment; an environment that forces an older kernel (this
// machine's sets Haswell on an AVX-512 CPU) would make the reference look 2.5x slower than the
// real library. So `bench ops`, `bench infer` and `bench train` re-execute themselves with those
// variables removed before anything else runs (blas_environment.h, called first in main) and
// print the kernel OpenBLAS picked. SIMPLI_BENCH_BLAS_ENV=keep keeps the environment as it is.
#include "blas_environment.h"
#include "commands.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/gemm_backend.h"
#include "simpli/ocl/ops_conv.h"
#include "simpli/ocl/ops_linalg.h"
#include <CLI/CLI.hpp>
#include <cblas.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

namespace simpli::app {
namespace {

using Clock = std::chrono::steady_clock;

struct Timing {
  double medianMs = 0.0;
};

// Median wall time of `repeat` calls after `warmup` calls (the first calls compile kernels).
Timing timeIt(const std::function<void()>& run, int warmup, int repeat) {
  for (int i = 0; i < warmup; ++i)
    run();
  std::vector<double> ms;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = Clock::now();
    run();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  const std::size_t n = ms.size();
  return {n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2])};
}

double maxRelativeDifference(const std::vector<float>& a, const std::vector<float>& ref) {
  double maxRef = 1e-30, maxDiff = 0.0;
  for (std::size_t i = 0; i < ref.size() && i < a.size(); ++i) {
    maxRef = std::max(maxRef, std::fabs(static_cast<double>(ref[i])));
    maxDiff = std::max(maxDiff, std::fabs(static_cast<double>(a[i]) - ref[i]));
  }
  return a.size() == ref.size() ? maxDiff / maxRef : INFINITY;
}

// ---- the CPU reference: im2col + OpenBLAS sgemm, in column blocks like the device path ----

struct ConvShape {
  int64_t C, D, H, W, O, K; // cubic (3-D) or square (2-D, D = 1 and kd = 1) kernel of size K
  bool threeD, replicate;
  int64_t kd() const { return threeD ? K : 1; }
  int64_t pd() const { return threeD ? K / 2 : 0; }
  int64_t ck() const { return C * kd() * K * K; }
  int64_t outP() const { return D * H * W; } // stride 1, "same" padding
  double flops() const { return 2.0 * O * ck() * outP(); }
};

void im2colCpu(const ConvShape& s, const float* x, int64_t row0, int64_t rows, float* col,
               int threads) {
  const int64_t ck = s.ck(), chunk = rows * s.W, p = s.K / 2;
  auto work = [&](int64_t r0, int64_t r1) {
    for (int64_t r = r0; r < r1; ++r) {
      const int64_t l = r % s.K, j = (r / s.K) % s.K, i = (r / (s.K * s.K)) % s.kd();
      const int64_t c = r / (s.K * s.K * s.kd());
      float* out = col + r * chunk;
      for (int64_t rl = 0; rl < rows; ++rl) {
        const int64_t row = row0 + rl, od = row / s.H, oh = row % s.H;
        int64_t z = od - s.pd() + i, y = oh - p + j;
        const bool rowInside = z >= 0 && z < s.D && y >= 0 && y < s.H;
        if (s.replicate) {
          z = std::clamp<int64_t>(z, 0, s.D - 1);
          y = std::clamp<int64_t>(y, 0, s.H - 1);
        }
        const float* in = x + ((c * s.D + z) * s.H + y) * s.W;
        for (int64_t ow = 0; ow < s.W; ++ow) {
          int64_t xx = ow - p + l;
          if (s.replicate)
            out[rl * s.W + ow] = in[std::clamp<int64_t>(xx, 0, s.W - 1)];
          else
            out[rl * s.W + ow] = (rowInside && xx >= 0 && xx < s.W) ? in[xx] : 0.0f;
        }
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back(work, ck * t / threads, ck * (t + 1) / threads);
  for (auto& t : pool)
    t.join();
}

void convCpu(const ConvShape& s, const std::vector<float>& x, const std::vector<float>& w,
             std::vector<float>& y, std::vector<float>& col, int64_t rowsPerBlock, int threads) {
  const int64_t ck = s.ck(), P = s.outP(), totalRows = s.D * s.H;
  for (int64_t row0 = 0; row0 < totalRows; row0 += rowsPerBlock) {
    const int64_t rows = std::min(rowsPerBlock, totalRows - row0), chunk = rows * s.W;
    im2colCpu(s, x.data(), row0, rows, col.data(), threads);
    cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, static_cast<int>(s.O),
                static_cast<int>(chunk), static_cast<int>(ck), 1.0f, w.data(), static_cast<int>(ck),
                col.data(), static_cast<int>(chunk), 0.0f, y.data() + row0 * s.W,
                static_cast<int>(P));
  }
}

// ---- the benchmarks ----------------------------------------------------------------------

struct Row {
  std::string name;
  double flops = 0, deviceMs = 0, blasMs = 0, difference = 0;
};

void printRow(const Row& r) {
  std::printf("%-44s %10.2f %9.1f %12.2f %9.1f %7.2f %11.1e\n", r.name.c_str(), r.deviceMs,
              r.flops / r.deviceMs * 1e-6, r.blasMs, r.flops / r.blasMs * 1e-6,
              r.blasMs / r.deviceMs, r.difference);
  std::fflush(stdout);
}

// C = A B, or with transposedB C = A B^T (B stored [n, k]: a weight gradient, gy x col^T).
Row benchGemm(int64_t m, int64_t n, int64_t k, int warmup, int repeat, bool transposedB = false) {
  Row row;
  row.name = std::string(transposedB ? "gemm NT " : "gemm ") + std::to_string(m) + "x" +
             std::to_string(n) + "x" + std::to_string(k) + " (MxNxK)";
  row.flops = 2.0 * m * n * k;
  auto a = ocl::Tensor::uniform({m, k}, -1, 1, 11);
  auto b = ocl::Tensor::uniform(transposedB ? ocl::Shape{n, k} : ocl::Shape{k, n}, -1, 1, 12);
  ocl::Tensor c;
  row.deviceMs = timeIt(
                     [&] {
                       c = ocl::matmul(a, b, false, transposedB);
                       ocl::Device::current().finish();
                     },
                     warmup, repeat)
                     .medianMs;
  const auto ha = a.toVectorF32(), hb = b.toVectorF32();
  std::vector<float> hc(static_cast<std::size_t>(m * n));
  row.blasMs =
      timeIt(
          [&] {
            cblas_sgemm(CblasRowMajor, CblasNoTrans, transposedB ? CblasTrans : CblasNoTrans,
                        static_cast<int>(m), static_cast<int>(n), static_cast<int>(k), 1.0f,
                        ha.data(), static_cast<int>(k), hb.data(),
                        static_cast<int>(transposedB ? k : n), 0.0f, hc.data(),
                        static_cast<int>(n));
          },
          warmup, repeat)
          .medianMs;
  row.difference = maxRelativeDifference(c.toVectorF32(), hc);
  return row;
}

Row benchConv(const ConvShape& s, int warmup, int repeat, int threads) {
  Row row;
  const std::string k = std::to_string(s.K);
  row.name = std::string(s.threeD ? "conv3d " : "conv2d ") + std::to_string(s.C) + "->" +
             std::to_string(s.O) + " " + k + "x" + k + (s.threeD ? "x" + k : "") + " over " +
             (s.threeD ? std::to_string(s.D) + "x" : "") + std::to_string(s.H) + "x" +
             std::to_string(s.W) + (s.replicate ? " replicate" : " zeros");
  row.flops = s.flops();
  const ocl::Shape xs = s.threeD ? ocl::Shape{1, s.C, s.D, s.H, s.W} : ocl::Shape{1, s.C, s.H, s.W};
  const ocl::Shape ws =
      s.threeD ? ocl::Shape{s.O, s.C, s.K, s.K, s.K} : ocl::Shape{s.O, s.C, s.K, s.K};
  auto x = ocl::Tensor::uniform(xs, -1, 1, 21), w = ocl::Tensor::uniform(ws, -1, 1, 22);
  const auto mode = s.replicate ? ocl::PaddingMode::Replicate : ocl::PaddingMode::Zeros;
  const int pad = static_cast<int>(s.K / 2);
  ocl::Tensor y;
  row.deviceMs = timeIt(
                     [&] {
                       y = s.threeD ? ocl::conv3d(x, w, ocl::Tensor(), 1, pad, mode)
                                    : ocl::conv2d(x, w, ocl::Tensor(), 1, pad, mode);
                       ocl::Device::current().finish();
                     },
                     warmup, repeat)
                     .medianMs;
  // The CPU path uses the device path's 32 MiB column blocks (whole output rows).
  const int64_t rowsPerBlock =
      std::max<int64_t>(1, std::min<int64_t>(s.D * s.H, (int64_t{32} << 20) / (s.ck() * s.W * 4)));
  const auto hx = x.toVectorF32(), hw = w.toVectorF32();
  std::vector<float> hy(static_cast<std::size_t>(s.O * s.outP()));
  std::vector<float> col(static_cast<std::size_t>(s.ck() * rowsPerBlock * s.W));
  row.blasMs =
      timeIt([&] { convCpu(s, hx, hw, hy, col, rowsPerBlock, threads); }, warmup, repeat).medianMs;
  row.difference = maxRelativeDifference(y.toVectorF32(), hy);
  return row;
}

// ---- the convolution paths: lowered (im2col / col2im + GEMM) against direct ------------------

struct ConvCase {
  ocl::Shape x, w; // [N, C, H, W] / [O, C, k, k] or [N, C, D, H, W] / [O, C, k, k, k]
  bool replicate;
  std::string name() const {
    return ocl::toString(x) + " x " + ocl::toString(w) + (replicate ? " rep" : " zero");
  }
};

ocl::Tensor runCase(const ConvCase& c, const ocl::Tensor& x, const ocl::Tensor& w) {
  const auto mode = c.replicate ? ocl::PaddingMode::Replicate : ocl::PaddingMode::Zeros;
  const int pad = static_cast<int>(c.w.back() / 2);
  return c.x.size() == 5 ? ocl::conv3d(x, w, ocl::Tensor(), 1, pad, mode)
                         : ocl::conv2d(x, w, ocl::Tensor(), 1, pad, mode);
}

// The fastest of the timed runs, in ms, of the forward, of the input gradient alone (the
// backward of a convolution whose weight needs no gradient) and of the weight gradient alone,
// on one path. The minimum, not the median: on a machine shared with other jobs it is the
// figure that varies least between runs.
std::array<double, 3> timeConvPath(const ConvCase& c, ocl::ConvPath path, int warmup, int repeat) {
  const ocl::ConvPath previous = ocl::setConvPath(path);
  auto x = ocl::Tensor::uniform(c.x, -1, 1, 21), w = ocl::Tensor::uniform(c.w, -1, 1, 22);
  auto& device = ocl::Device::current();
  std::array<double, 3> best = {INFINITY, INFINITY, INFINITY};
  for (int i = 0; i < warmup + repeat; ++i) {
    const auto t0 = Clock::now();
    runCase(c, x, w);
    device.finish();
    if (i >= warmup)
      best[0] =
          std::min(best[0], std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  ocl::GradMode::setEnabled(true);
  for (int pass = 1; pass <= 2; ++pass) {
    ocl::Tensor& leaf = pass == 1 ? x : w;
    leaf.setRequiresGrad(true);
    for (int i = 0; i < warmup + repeat; ++i) {
      const ocl::Tensor y = runCase(c, x, w);
      const ocl::Tensor gy = ocl::Tensor::uniform(y.shape(), -1, 1, 23);
      device.finish();
      const auto t0 = Clock::now();
      y.backward(gy);
      device.finish();
      if (i >= warmup)
        best[pass] = std::min(best[pass],
                              std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      leaf.zeroGrad();
    }
    leaf.setRequiresGrad(false);
  }
  ocl::GradMode::setEnabled(false);
  ocl::setConvPath(previous);
  return best;
}

void benchConvPaths(const std::vector<ConvCase>& cases, int warmup, int repeat) {
  std::printf("\nconvolution paths: lowered (im2col / col2im + GEMM) vs direct, fastest of %d "
              "run(s) in ms; ratio = lowered / direct\n",
              repeat);
  std::printf("%-44s %8s %8s %5s %8s %8s %5s %8s %8s %5s\n", "x x w", "fwd low", "fwd dir", "ratio",
              "dx low", "dx dir", "ratio", "dw low", "dw dir", "ratio");
  for (const auto& c : cases) {
    const auto low = timeConvPath(c, ocl::ConvPath::Lowered, warmup, repeat);
    const auto dir = timeConvPath(c, ocl::ConvPath::Direct, warmup, repeat);
    std::printf("%-44s", c.name().c_str());
    for (int i = 0; i < 3; ++i)
      std::printf(" %8.2f %8.2f %5.2f", low[i], dir[i], low[i] / dir[i]);
    std::printf("\n");
    std::fflush(stdout);
  }
}

void runConvPaths(bool quick, int warmup, int repeat) {
  if (quick) {
    benchConvPaths({{{1, 4, 12, 16}, {4, 4, 3, 3}, true}}, warmup, repeat);
    return;
  }
  // The tiny configs' convolutions in a training step at 128x96 (the first five take most of
  // their time), then wider ones up to the official configs' widths, where the rule in
  // ops_conv.cpp hands over to the lowered path.
  benchConvPaths({{{4, 16, 96, 128}, {16, 16, 3, 3}, true},
                  {{1, 16, 17, 24, 32}, {16, 16, 3, 3, 3}, true},
                  {{4, 40, 96, 128}, {16, 40, 3, 3}, true},
                  {{17, 16, 48, 64}, {16, 16, 3, 3}, true},
                  {{1, 36, 17, 24, 32}, {16, 36, 3, 3, 3}, true},
                  {{4, 3, 96, 128}, {16, 3, 3, 3}, false},
                  {{4, 16, 24, 32}, {32, 16, 3, 3}, false},
                  {{4, 32, 24, 32}, {32, 32, 3, 3}, false},
                  {{4, 32, 12, 16}, {32, 32, 3, 3}, false},
                  {{4, 64, 48, 64}, {16, 64, 3, 3}, false},
                  {{4, 16, 48, 64}, {64, 16, 3, 3}, false},
                  {{4, 32, 48, 64}, {32, 32, 3, 3}, false},
                  {{4, 96, 48, 64}, {64, 96, 3, 3}, false},
                  {{1, 64, 96, 128}, {64, 64, 3, 3}, false},
                  {{1, 128, 48, 64}, {128, 128, 3, 3}, false},
                  {{1, 256, 24, 32}, {256, 256, 3, 3}, false}},
                 warmup, repeat);
}

// One line on the OpenBLAS build, the kernel it runs and where the choice came from.
void printBlasKernel(int threads) {
  std::printf("openblas %s, %d thread(s)\n", openblas_get_config(), threads);
  const char* removed = removedBlasVariables();
  const char* forced = std::getenv("OPENBLAS_CORETYPE");
  if (removed && *removed)
    std::printf("kernel   %s (native: removed %s for this process)\n", openblas_get_corename(),
                removed);
  else if (forced)
    std::printf("kernel   %s (forced by OPENBLAS_CORETYPE=%s; SIMPLI_BENCH_BLAS_ENV=keep)\n",
                openblas_get_corename(), forced);
  else
    std::printf("kernel   %s (native)\n", openblas_get_corename());
}

void runOps(int repeat, bool quick, bool pathsOnly, const std::string& selector) {
  if (repeat < 1)
    fail("bench ops: --repeat must be at least 1, got ", repeat);
  if (!selector.empty()) {
    auto [p, d] = ocl::Device::parseSelector(selector, "--device");
    ocl::Device::select(p, d);
  }
  const auto& info = ocl::Device::current().info();
  // OpenBLAS gets as many threads as the OpenCL CPU device has compute units (PoCL runs one
  // worker per core), so both use the same cores; for a GPU, all hardware threads.
  const int threads = std::max(1, info.isGpu ? static_cast<int>(std::thread::hardware_concurrency())
                                             : info.computeUnits);
  openblas_set_num_threads(threads);
  ocl::NoGradGuard inference;
  std::printf("device   %d:%d %s [%s, %s]\n", info.platformIndex, info.deviceIndex,
              info.deviceName.c_str(), info.platformName.c_str(), info.deviceVersion.c_str());
  std::printf("tuning   %s\n", ocl::clblastTuningSummary().c_str());
  printBlasKernel(threads);
  std::printf("gemm     %s\n", ocl::gemmBackendSummary().c_str());
  const int warmup = 1;
  if (pathsOnly) {
    runConvPaths(quick, warmup, repeat);
    return;
  }
  std::printf("median of %d run(s) after warm-up; ratio = OpenBLAS time / device time\n\n", repeat);
  std::printf("%-44s %10s %9s %12s %9s %7s %11s\n", "op", "device ms", "GFLOP/s", "OpenBLAS ms",
              "GFLOP/s", "ratio", "max rel diff");
  if (quick) {
    printRow(benchGemm(128, 128, 128, warmup, repeat));
    printRow(benchGemm(256, 512, 32, warmup, repeat));
    printRow(benchGemm(8, 72, 4096, warmup, repeat, true));
    printRow(benchConv({8, 1, 24, 32, 8, 3, false, false}, warmup, repeat, threads));
    printRow(benchConv({4, 5, 12, 16, 4, 3, true, true}, warmup, repeat, threads));
  } else {
    printRow(benchGemm(512, 512, 512, warmup, repeat));
    printRow(benchGemm(2048, 4096, 32, warmup, repeat));
    printRow(benchConv({32, 1, 192, 256, 32, 3, false, false}, warmup, repeat, threads));
    printRow(benchConv({36, 41, 96, 128, 32, 3, true, true}, warmup, repeat, threads));
    // The feature extractor at 512x384 (reference section 4.2): conv1b 64->64 at full size and
    // convDa 384->256 at half size (three quarters of its work).
    printRow(benchConv({64, 1, 384, 512, 64, 3, false, false}, warmup, repeat, threads));
    printRow(benchConv({384, 1, 192, 256, 256, 3, false, false}, warmup, repeat, threads));
    // Skinny shapes of the small configs (one dimension <= 32: the engine's own GEMM kernels
    // unless SIMPLI_GEMM_SKINNY=0): a 16-channel 3x3 conv at 128x192 and a per-pixel linear
    // layer 7 -> 16 over 4 layers of 128x192.
    printRow(benchGemm(16, 24576, 144, warmup, repeat));
    printRow(benchGemm(98304, 16, 7, warmup, repeat));
    // The weight gradient of a 16-channel 3x3 conv at 256x192 (gy [16, P] x col [144, P]^T):
    // the training step's largest GEMM kind (split along k, gemm_splitk.cl).
    printRow(benchGemm(16, 144, 49152, warmup, repeat, true));
    printRow(benchConv({16, 1, 128, 192, 16, 3, false, false}, warmup, repeat, threads));
  }
  runConvPaths(quick, warmup, repeat);
}

} // namespace

void addBenchInferCommand(CLI::App& bench); // cmd_bench_infer.cpp
void addBenchTrainCommand(CLI::App& bench); // cmd_bench_train.cpp
#if SIMPLI_BENCH_RENDER
void addBenchRenderCommand(CLI::App& bench); // cmd_bench_render.cpp
#else
// Built without VTK's rendering modules: the command exists and says so.
void addBenchRenderCommand(CLI::App& bench) {
  bench.add_subcommand("render", "Time VTK/OpenGL rendering of an MLI (not built here)")
      ->allow_extras()
      ->callback([] {
        fail("bench render: this simpli was built without VTK's rendering modules "
             "(SIMPLI_WITH_VTK=OFF, or VTK without RenderingOpenGL2 / RenderingUI / X11)");
      });
}
#endif

void addBenchCommand(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Measure speed against reference implementations");
  bench->require_subcommand(1);
  auto* ops = bench->add_subcommand(
      "ops", "Time GEMM and convolutions on the OpenCL device against OpenBLAS on the CPU");
  auto repeat = std::make_shared<int>(5);
  auto quick = std::make_shared<bool>(false);
  auto pathsOnly = std::make_shared<bool>(false);
  auto selector = std::make_shared<std::string>();
  ops->add_option("--repeat", *repeat, "Timed runs per op (median reported)")
      ->capture_default_str();
  ops->add_flag("--quick", *quick, "Small sizes: a smoke test, not a measurement");
  ops->add_option("--device", *selector,
                  "Device as platform:device (default: $SIMPLI_CL_DEVICE, else first GPU, "
                  "else first CPU)");
  ops->add_flag("--conv-paths", *pathsOnly,
                "Only the convolution paths (lowered vs direct, forward and input gradient)");
  ops->callback(
      [repeat, quick, pathsOnly, selector] { runOps(*repeat, *quick, *pathsOnly, *selector); });
  addBenchInferCommand(*bench);
  addBenchTrainCommand(*bench);
  addBenchRenderCommand(*bench);
}

} // namespace simpli::app

// Timings of the geometry ops at the sizes of a 384x512 inference with 8 views (reference §3):
// level 0 (96x128, 41 planes, 12 channels), level 1 (MPI rendered into the 8 sources at 192x256,
// weighted aggregation at 192x256) and the layer unprojection of levels 2-4 (4 layers at
// 384x512, 6 channels). Disabled by default; run with
//   simpli_geometry_tests --gtest_also_run_disabled_tests --gtest_filter='*Benchmark*'
// Prints times, asserts nothing about them.
#include "geometry_reference.h"

#include "simpli/model/geometry/layer_unproject.h"
#include "simpli/model/geometry/mpi_render.h"
#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/model/geometry/planes.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_reduce.h"

#include <gtest/gtest.h>

#include <chrono>
#include <ctime>
#include <functional>

namespace simpli {
namespace {

using ocl::Tensor;

// Wall and process CPU seconds (all threads) of one call, after a warm-up call that builds the
// kernels; best of `repeats`. CPU time is reported too because wall time means little when
// other jobs share the cores.
struct Timing {
  double wall = 1e30, cpu = 1e30;
};

Timing timeIt(const std::function<void()>& f, int repeats = 2) {
  f();
  ocl::Device::current().finish();
  Timing best;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    f();
    ocl::Device::current().finish();
    best.cpu = std::min(best.cpu, double(std::clock() - c0) / CLOCKS_PER_SEC);
    best.wall = std::min(
        best.wall, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

void report(const char* what, const Timing& fwd, const Timing& both) {
  std::printf("[bench] %s\n        forward %.3f s wall (%.3f s cpu), forward+backward %.3f s wall "
              "(%.3f s cpu)\n",
              what, fwd.wall, fwd.cpu, both.wall, both.cpu);
}

TEST(GeometryBenchmark, DISABLED_Inference384x512) {
  std::mt19937_64 rng(1);
  const scene::Camera ref = geomtest::referenceCamera();
  std::vector<scene::Camera> views;
  for (int v = 0; v < 8; ++v)
    views.push_back(geomtest::randomCamera(rng, 0.03, 0.1));
  const std::vector<double> depths = geometry::planeDepths();
  const auto& info = ocl::Device::current().info();
  std::printf("[bench] device: %s (%d compute units)\n", info.deviceName.c_str(),
              info.computeUnits);

  // Level 0: 8 maps [12, 96, 128], 41 planes at 96x128.
  Tensor f0 = Tensor::uniform({8, 12, 96, 128}, -1, 1, 1);
  Timing fwd = timeIt([&] {
    ocl::NoGradGuard g;
    geometry::planeSweepMeanVar(f0, ref, views, depths, 96, 128);
  });
  f0.setRequiresGrad();
  Timing both = timeIt([&] {
    f0.zeroGrad();
    ocl::sumAll(geometry::planeSweepMeanVar(f0, ref, views, depths, 96, 128)).backward();
  });
  report("level 0 planeSweepMeanVar, 41 planes at 96x128, V = 8, C = 12", fwd, both);

  // Level 1: fMPI0 [41, 13, 96, 128] rendered into the 8 sources at 192x256.
  Tensor mpi = Tensor::uniform({41, 13, 96, 128}, 0, 1, 2);
  fwd = timeIt([&] {
    ocl::NoGradGuard g;
    geometry::renderMpi(mpi, depths, ref, views, 192, 256);
  });
  mpi.setRequiresGrad();
  both = timeIt([&] {
    mpi.zeroGrad();
    const geometry::MpiRendering r = geometry::renderMpi(mpi, depths, ref, views, 192, 256);
    ocl::sumAll(r.color).backward();
  });
  report("level 1 renderMpi, MPI 41x13x96x128 into 8 targets at 192x256", fwd, both);

  // Level 1: weighted aggregation of 8 error maps [12, 192, 256] with weights [8, 41, 1, ...].
  Tensor e1 = Tensor::uniform({8, 12, 192, 256}, -1, 1, 3);
  Tensor w1 = Tensor::uniform({8, 41, 1, 192, 256}, 0, 1, 4);
  fwd = timeIt([&] {
    ocl::NoGradGuard g;
    geometry::planeSweepMeanVar(e1, ref, views, depths, 192, 256, w1);
  });
  e1.setRequiresGrad();
  w1.setRequiresGrad();
  both = timeIt([&] {
    e1.zeroGrad();
    w1.zeroGrad();
    ocl::sumAll(geometry::planeSweepMeanVar(e1, ref, views, depths, 192, 256, w1)).backward();
  });
  report("level 1 planeSweepMeanVar (weighted), 41 planes at 192x256, V = 8, C = 12", fwd, both);

  // Levels 2-4: 4 layers at 384x512 from 8 maps [6, 384, 512].
  Tensor f2 = Tensor::uniform({8, 6, 384, 512}, -1, 1, 5);
  Tensor depth = Tensor::uniform({4, 384, 512}, 1.5, 4.0, 6);
  fwd = timeIt([&] {
    ocl::NoGradGuard g;
    geometry::unprojectLayersMeanVar(f2, depth, ref, views);
  });
  f2.setRequiresGrad();
  depth.setRequiresGrad();
  both = timeIt([&] {
    f2.zeroGrad();
    depth.zeroGrad();
    ocl::sumAll(geometry::unprojectLayersMeanVar(f2, depth, ref, views)).backward();
  });
  report("levels 2-4 unprojectLayersMeanVar, 4 layers at 384x512, V = 8, C = 6", fwd, both);
}

} // namespace
} // namespace simpli

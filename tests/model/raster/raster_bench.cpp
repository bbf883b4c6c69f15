// Render timings of the MLI rasterizer (not a test; prints seconds after a warm-up).
// Usage: simpli_raster_bench [layers H W Ht Wt views tile]
// Default: 4 layers of 192 x 256 texels into 8 views of 384 x 512, float32, tile 8.
#include "simpli/error.h"
#include "simpli/model/raster/rasterizer.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

using namespace simpli;

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Process CPU time over all threads: on a shared machine it tracks the work done better than
// the wall clock.
double cpuNow() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

// Smoothly varying layers (depth 1..100 in disparity order, as the network produces).
void makeLayers(int L, int H, int W, std::vector<double>& depth, std::vector<double>& rgba) {
  depth.resize(std::size_t(L) * H * W);
  rgba.resize(std::size_t(L) * 4 * H * W);
  for (int k = 0; k < L; ++k)
    for (int i = 0; i < H; ++i)
      for (int j = 0; j < W; ++j) {
        const std::size_t p = std::size_t(i) * W + j;
        const double disparity = 0.01 + 0.99 * (k + 0.5 + 0.3 * std::sin(0.05 * i + 0.07 * j)) / L;
        depth[std::size_t(k) * H * W + p] = 1.0 / disparity;
        for (int c = 0; c < 4; ++c)
          rgba[(std::size_t(k) * 4 + c) * H * W + p] =
              0.5 + 0.4 * std::sin(0.1 * (c + 1) * i + 0.13 * j + k);
      }
}

} // namespace

int main(int argc, char** argv) {
  try {
    const int L = argc > 1 ? std::atoi(argv[1]) : 4;
    const int H = argc > 2 ? std::atoi(argv[2]) : 192;
    const int W = argc > 3 ? std::atoi(argv[3]) : 256;
    const int Ht = argc > 4 ? std::atoi(argv[4]) : 384;
    const int Wt = argc > 5 ? std::atoi(argv[5]) : 512;
    const int views = argc > 6 ? std::atoi(argv[6]) : 8;
    raster::RasterSettings settings;
    settings.tileSize = argc > 7 ? std::atoi(argv[7]) : 8;
    std::vector<double> depth, rgba;
    makeLayers(L, H, W, depth, rgba);
    scene::Camera ref;
    ref.fx = 0.92;
    ref.fy = 1.23;
    ref.width = W;
    ref.height = H;
    ocl::Tensor d = ocl::Tensor::fromHost(depth, {L, H, W}, ocl::Dtype::F32);
    ocl::Tensor a = ocl::Tensor::fromHost(rgba, {L, 4, H, W}, ocl::Dtype::F32);
    std::vector<scene::Camera> targets;
    for (int v = 0; v < views; ++v) {
      scene::Camera c = ref;
      const double angle = 2 * M_PI * v / views;
      c.t = Eigen::Vector3d(0.15 * std::cos(angle), 0.1 * std::sin(angle), 0.05 * v / views);
      c.R = Eigen::AngleAxisd(0.02 * std::sin(angle), Eigen::Vector3d::UnitY()).toRotationMatrix();
      c.width = Wt;
      c.height = Ht;
      targets.push_back(c);
    }
    std::printf("device: %s\n", ocl::Device::current().info().deviceName.c_str());
    std::printf("%d layers %dx%d (%lld triangles) -> %d views %dx%d, tile %d, f32\n", L, H, W,
                static_cast<long long>(int64_t(L) * 2 * (H - 1) * (W - 1)), views, Ht, Wt,
                settings.tileSize);
    {
      ocl::NoGradGuard noGrad; // warm-up: kernel builds
      raster::renderLayers(d, a, ref, targets[0], settings).colour.toVector();
    }
    double tRaster = 0, tShade = 0, tBackward = 0;
    double cRaster = 0, cShade = 0, cBackward = 0;
    for (const scene::Camera& c : targets) {
      double c0 = cpuNow(), t0 = now();
      const raster::RasterFragments f = raster::rasterizeLayers(d, ref, c, settings);
      ocl::Device::current().finish();
      double c1 = cpuNow(), t1 = now();
      a.setRequiresGrad(true);
      d.setRequiresGrad(true);
      const raster::RenderedLayers r = raster::shadeFragments(f, d, a);
      ocl::Device::current().finish();
      double c2 = cpuNow(), t2 = now();
      (ocl::sumAll(r.colour) + ocl::sumAll(r.depth)).backward();
      ocl::Device::current().finish();
      double c3 = cpuNow(), t3 = now();
      a.zeroGrad();
      d.zeroGrad();
      tRaster += t1 - t0;
      tShade += t2 - t1;
      tBackward += t3 - t2;
      cRaster += c1 - c0;
      cShade += c2 - c1;
      cBackward += c3 - c2;
    }
    std::printf(
        "per view: rasterize %.1f ms, shade %.1f ms, backward (attributes and depths) %.1f ms\n",
        1e3 * tRaster / views, 1e3 * tShade / views, 1e3 * tBackward / views);
    std::printf("per view CPU time (all threads): rasterize %.1f ms, shade %.1f ms, backward "
                "%.1f ms\n",
                1e3 * cRaster / views, 1e3 * cShade / views, 1e3 * cBackward / views);
    std::printf("all %d views forward: %.1f ms wall\n", views, 1e3 * (tRaster + tShade));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "simpli_raster_bench: %s\n", e.what());
    return 1;
  }
}

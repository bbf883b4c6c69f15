// Every geometry op through the engine's op harness: float32 forward against the plain C++
// double reference (geometry_reference.h), float64 forward to 1e-10, and float64 backward
// against central finite differences (random cameras with small baselines; layer depths are
// nudged so that no sample lies near a bilinear kink or the validity border).
#include "geometry_reference.h"
#include "op_harness.h"

#include "simpli/model/geometry/layer_unproject.h"
#include "simpli/model/geometry/mpi_render.h"
#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include <gtest/gtest.h>

#include <cmath>

namespace simpli {
namespace {

using geomtest::CpuSamples;
using ocl::Tensor;
using test::HostInputs;
using test::OpCase;

struct Scene {
  scene::Camera ref = geomtest::referenceCamera();
  std::vector<scene::Camera> views;
};

Scene randomScene(int V, uint64_t seed, double angle = 0.03, double baseline = 0.1) {
  std::mt19937_64 rng(seed);
  Scene s;
  for (int v = 0; v < V; ++v)
    s.views.push_back(geomtest::randomCamera(rng, angle, baseline));
  return s;
}

constexpr int kV = 3, kC = 2, kHs = 7, kWs = 9; // source maps
constexpr int kH = 5, kW = 6;                   // reference grid
const std::vector<double> kDepths{1.5, 2.5, 6.0};

geomtest::PointFn planes(const Scene& s, const std::vector<double>& depths, int h, int w) {
  return [&s, depths, h, w](int p, int x, int y) {
    return geomtest::planePoint(s.ref, x, y, h, w, depths[p]);
  };
}

geomtest::PointFn layers(const Scene& s, const std::vector<double>& depth, int h, int w) {
  return [&s, &depth, h, w](int k, int x, int y) {
    return geomtest::layerPoint(s.ref, x, y, h, w, depth[(std::size_t(k) * h + y) * w + x]);
  };
}

// Moves every layer depth until all its samples are >= 0.02 source pixels away from bilinear
// kinks and the validity border, so central differences see a smooth function.
void smoothDepths(std::vector<double>& depth, const Scene& s, int L, int h, int w) {
  for (int k = 0; k < L; ++k)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double& d = depth[(std::size_t(k) * h + y) * w + x];
        for (int attempt = 0; attempt < 200; ++attempt) {
          double margin = 1e9;
          const Eigen::Vector3d X = geomtest::layerPoint(s.ref, x, y, h, w, d);
          for (const scene::Camera& v : s.views) {
            const Eigen::Vector2d g = geomtest::gridOf(v, X);
            margin = std::min(
                {margin, geomtest::kinkMargin(g.x(), kWs), geomtest::kinkMargin(g.y(), kHs)});
          }
          if (margin >= 0.02)
            break;
          d *= 1.004;
        }
      }
}

TEST(GeometryGradients, PlaneSweepSamples) {
  const Scene s = randomScene(kV, 11);
  OpCase c;
  c.name = "planeSweep";
  c.inputShapes = {{kV, kC, kHs, kWs}};
  c.device = [&](const std::vector<Tensor>& in) {
    return geometry::planeSweep(in[0], s.ref, s.views, kDepths, kH, kW).samples;
  };
  c.reference = [&](const HostInputs& in) {
    return geomtest::sampleSurfaces(in[0], false, kC, kHs, kWs, s.views, 3, kH, kW,
                                    planes(s, kDepths, kH, kW))
        .samples;
  };
  test::checkOp(c);
}

TEST(GeometryGradients, PlaneSweepPerPlaneSources) {
  const Scene s = randomScene(kV, 12);
  OpCase c;
  c.name = "planeSweep per-plane sources";
  c.inputShapes = {{kV, 3, kC, kHs, kWs}};
  c.device = [&](const std::vector<Tensor>& in) {
    return geometry::planeSweep(in[0], s.ref, s.views, kDepths, kH, kW).samples;
  };
  c.reference = [&](const HostInputs& in) {
    return geomtest::sampleSurfaces(in[0], true, kC, kHs, kWs, s.views, 3, kH, kW,
                                    planes(s, kDepths, kH, kW))
        .samples;
  };
  test::checkOp(c);
}

TEST(GeometryGradients, PlaneSweepMask) {
  const Scene s = randomScene(kV, 13, 0.05, 0.3);
  const std::vector<double> src = geomtest::randomValues(kV * kC * kHs * kWs, -1, 1, 5);
  const CpuSamples cpu = geomtest::sampleSurfaces(src, false, kC, kHs, kWs, s.views, 3, kH, kW,
                                                  planes(s, kDepths, kH, kW));
  for (ocl::Dtype dtype : {ocl::Dtype::F32, ocl::Dtype::F64}) {
    const geometry::SurfaceSamples out = geometry::planeSweep(
        Tensor::fromHost(src, {kV, kC, kHs, kWs}, dtype), s.ref, s.views, kDepths, kH, kW);
    EXPECT_EQ(out.mask.toVector(), cpu.mask);
  }
  double valid = 0;
  for (double m : cpu.mask)
    valid += m;
  // The scene must exercise both outcomes.
  EXPECT_GT(valid, 0);
  EXPECT_LT(valid, static_cast<double>(cpu.mask.size()));
}

TEST(GeometryGradients, PlaneSweepMeanVar) {
  const Scene s = randomScene(kV, 14);
  OpCase c;
  c.name = "planeSweepMeanVar";
  c.inputShapes = {{kV, kC, kHs, kWs}};
  c.device = [&](const std::vector<Tensor>& in) {
    return geometry::planeSweepMeanVar(in[0], s.ref, s.views, kDepths, kH, kW);
  };
  c.reference = [&](const HostInputs& in) {
    const CpuSamples smp = geomtest::sampleSurfaces(in[0], false, kC, kHs, kWs, s.views, 3, kH, kW,
                                                    planes(s, kDepths, kH, kW));
    return geomtest::meanVar(smp, {}, kV, 3, kC, kH, kW);
  };
  test::checkOp(c);
}

TEST(GeometryGradients, PlaneSweepMeanVarWeighted) {
  const Scene s = randomScene(kV, 15);
  OpCase c;
  c.name = "planeSweepMeanVar weighted";
  c.inputShapes = {{kV, kC, kHs, kWs}, {kV, 3, 1, kHs, kWs}};
  c.prepare = [](HostInputs& in) {
    for (double& w : in[1])
      w = 0.25 * (w + 2); // weights in [0, 1]
  };
  c.device = [&](const std::vector<Tensor>& in) {
    return geometry::planeSweepMeanVar(in[0], s.ref, s.views, kDepths, kH, kW, in[1]);
  };
  c.reference = [&](const HostInputs& in) {
    const CpuSamples smp = geomtest::sampleSurfaces(in[0], false, kC, kHs, kWs, s.views, 3, kH, kW,
                                                    planes(s, kDepths, kH, kW));
    const CpuSamples w = geomtest::sampleSurfaces(in[1], true, 1, kHs, kWs, s.views, 3, kH, kW,
                                                  planes(s, kDepths, kH, kW));
    return geomtest::meanVar(smp, w.samples, kV, 3, kC, kH, kW);
  };
  test::checkOp(c);
}

OpCase layerCase(const Scene& s, bool fused) {
  OpCase c;
  c.name = fused ? "unprojectLayersMeanVar" : "unprojectLayers";
  c.inputShapes = {{kV, kC, kHs, kWs}, {2, kH, kW}};
  c.prepare = [&s](HostInputs& in) {
    for (double& d : in[1])
      d = 2.75 + 0.6 * d; // depths in [1.55, 3.95]
    smoothDepths(in[1], s, 2, kH, kW);
  };
  c.device = [&s, fused](const std::vector<Tensor>& in) {
    return fused ? geometry::unprojectLayersMeanVar(in[0], in[1], s.ref, s.views)
                 : geometry::unprojectLayers(in[0], in[1], s.ref, s.views).samples;
  };
  c.reference = [&s, fused](const HostInputs& in) {
    const CpuSamples smp = geomtest::sampleSurfaces(in[0], false, kC, kHs, kWs, s.views, 2, kH, kW,
                                                    layers(s, in[1], kH, kW));
    return fused ? geomtest::meanVar(smp, {}, kV, 2, kC, kH, kW) : smp.samples;
  };
  return c;
}

TEST(GeometryGradients, LayerSamples) {
  const Scene s = randomScene(kV, 16);
  OpCase c = layerCase(s, false);
  c.maxGradientProbes = 60;
  test::checkOp(c);
}

TEST(GeometryGradients, LayerMeanVar) {
  const Scene s = randomScene(kV, 17);
  OpCase c = layerCase(s, true);
  c.maxGradientProbes = 60;
  test::checkOp(c);
}

// Gradients requested for one input only take the other code paths of the backward kernels;
// they must equal the corresponding part of the full gradient.
TEST(GeometryGradients, PartialGradientsMatchFull) {
  const Scene s = randomScene(kV, 18);
  OpCase lc = layerCase(s, true);
  HostInputs in = test::makeInputs(lc);
  const std::vector<double> wv = geomtest::randomValues(kV * 3 * kHs * kWs, 0, 1, 9);
  auto grads = [&](bool src, bool second, bool layersOp) {
    Tensor a = Tensor::fromHost(in[0], {kV, kC, kHs, kWs}, ocl::Dtype::F64);
    Tensor b = layersOp ? Tensor::fromHost(in[1], {2, kH, kW}, ocl::Dtype::F64)
                        : Tensor::fromHost(wv, {kV, 3, 1, kHs, kWs}, ocl::Dtype::F64);
    a.setRequiresGrad(src);
    b.setRequiresGrad(second);
    Tensor out = layersOp ? geometry::unprojectLayersMeanVar(a, b, s.ref, s.views)
                          : geometry::planeSweepMeanVar(a, s.ref, s.views, kDepths, kH, kW, b);
    Tensor wgt = Tensor::fromHost(geomtest::randomValues(out.numel(), -1, 1, 3), out.shape(),
                                  ocl::Dtype::F64);
    ocl::sumAll(ocl::mul(out, wgt)).backward();
    return std::pair{src ? a.grad().toVector() : std::vector<double>(),
                     second ? b.grad().toVector() : std::vector<double>()};
  };
  for (bool layersOp : {true, false}) {
    SCOPED_TRACE(layersOp ? "layers" : "weighted planes");
    const auto full = grads(true, true, layersOp);
    EXPECT_LE(geomtest::relError(grads(true, false, layersOp).first, full.first), 1e-12);
    EXPECT_LE(geomtest::relError(grads(false, true, layersOp).second, full.second), 1e-12);
  }
  // Plain layer samples: depth only.
  Tensor a = Tensor::fromHost(in[0], {kV, kC, kHs, kWs}, ocl::Dtype::F64);
  Tensor d1 = Tensor::fromHost(in[1], {2, kH, kW}, ocl::Dtype::F64).setRequiresGrad();
  Tensor d2 = Tensor::fromHost(in[1], {2, kH, kW}, ocl::Dtype::F64).setRequiresGrad();
  Tensor a2 = Tensor::fromHost(in[0], {kV, kC, kHs, kWs}, ocl::Dtype::F64).setRequiresGrad();
  ocl::sumAll(geometry::unprojectLayers(a, d1, s.ref, s.views).samples).backward();
  ocl::sumAll(geometry::unprojectLayers(a2, d2, s.ref, s.views).samples).backward();
  EXPECT_LE(geomtest::relError(d1.grad().toVector(), d2.grad().toVector()), 1e-12);
}

TEST(GeometryGradients, MpiRender) {
  const Scene s = randomScene(2, 19, 0.03, 0.15);
  const std::vector<double> depths{8.0, 4.0, 2.5, 1.5};
  constexpr int P = 4, C1 = 3, h = 6, w = 7, Ht = 5, Wt = 6;
  OpCase c;
  c.name = "renderMpi";
  c.inputShapes = {{P, C1, h, w}};
  c.prepare = [](HostInputs& in) {
    // Alphas inside (0.05, 0.95): away from the clamp's kinks.
    for (int p = 0; p < P; ++p)
      for (int i = 0; i < h * w; ++i) {
        double& a = in[0][(std::size_t(p) * C1 + C1 - 1) * h * w + i];
        a = 0.5 + 0.225 * a;
      }
  };
  c.device = [&](const std::vector<Tensor>& in) {
    const geometry::MpiRendering r = geometry::renderMpi(in[0], depths, s.ref, s.views, Ht, Wt);
    return ocl::concat(
        {ocl::reshape(r.color, {-1}), ocl::reshape(r.opacity, {-1}), ocl::reshape(r.weights, {-1})},
        0);
  };
  c.reference = [&](const HostInputs& in) {
    const geomtest::CpuRender r =
        geomtest::renderMpi(in[0], P, C1, h, w, depths, s.ref, s.views, Ht, Wt);
    std::vector<double> out = r.color;
    out.insert(out.end(), r.opacity.begin(), r.opacity.end());
    out.insert(out.end(), r.weights.begin(), r.weights.end());
    return out;
  };
  c.maxGradientProbes = 80;
  test::checkOp(c);
}

} // namespace
} // namespace simpli

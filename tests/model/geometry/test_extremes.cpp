// Extreme configurations of the geometry ops: depth range 1e-3..1e6, planes behind a source
// camera and at its centre, zero baseline, grazing planes, 1 and 16 views, alphas exactly 0 and
// 1, and float32 vs float64 agreement.
#include "geometry_reference.h"
#include "op_harness.h"

#include "simpli/model/geometry/layer_unproject.h"
#include "simpli/model/geometry/mpi_render.h"
#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/model/geometry/planes.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include <gtest/gtest.h>

#include <cmath>

namespace simpli {
namespace {

using geomtest::CpuSamples;
using ocl::Dtype;
using ocl::Tensor;

std::vector<scene::Camera> randomViews(int V, uint64_t seed, double angle = 0.03,
                                       double baseline = 0.1) {
  std::mt19937_64 rng(seed);
  std::vector<scene::Camera> views;
  for (int v = 0; v < V; ++v)
    views.push_back(geomtest::randomCamera(rng, angle, baseline));
  return views;
}

geomtest::PointFn planes(const scene::Camera& ref, const std::vector<double>& depths, int h,
                         int w) {
  return [ref, depths, h, w](int p, int x, int y) {
    return geomtest::planePoint(ref, x, y, h, w, depths[p]);
  };
}

// Backward of sum(out * random) w.r.t. `leaf`, as host values.
std::vector<double> gradientOf(const Tensor& out, const Tensor& leaf, uint64_t seed) {
  Tensor w =
      Tensor::fromHost(geomtest::randomValues(out.numel(), -1, 1, seed), out.shape(), out.dtype());
  ocl::sumAll(ocl::mul(out, w)).backward();
  return leaf.grad().toVector();
}

// Plain and fused plane sweep in both precisions against the CPU reference; returns the float32
// errors (samples, mean/var). Masks must match exactly; everything must be finite, gradients
// included.
std::pair<double, double> sweepAgainstReference(const scene::Camera& ref,
                                                const std::vector<scene::Camera>& views,
                                                const std::vector<double>& depths, int C, int Hs,
                                                int Ws, int h, int w, uint64_t seed) {
  const int V = static_cast<int>(views.size()), P = static_cast<int>(depths.size());
  const std::vector<double> src = geomtest::randomValues(std::size_t(V) * C * Hs * Ws, -1, 1, seed);
  const CpuSamples cpu =
      geomtest::sampleSurfaces(src, false, C, Hs, Ws, views, P, h, w, planes(ref, depths, h, w));
  const std::vector<double> cpuMv = geomtest::meanVar(cpu, {}, V, P, C, h, w);
  std::pair<double, double> f32Errors;
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    SCOPED_TRACE(dtype == Dtype::F32 ? "float32" : "float64");
    const double tol = dtype == Dtype::F32 ? 1e-5 : 1e-9;
    Tensor maps = Tensor::fromHost(src, {V, C, Hs, Ws}, dtype).setRequiresGrad();
    const geometry::SurfaceSamples s = geometry::planeSweep(maps, ref, views, depths, h, w);
    EXPECT_EQ(s.mask.toVector(), cpu.mask);
    const double e1 = geomtest::relError(s.samples.toVector(), cpu.samples);
    EXPECT_LE(e1, tol) << "plain samples";
    EXPECT_TRUE(geomtest::allFinite(gradientOf(s.samples, maps, seed + 1)));
    Tensor maps2 = Tensor::fromHost(src, {V, C, Hs, Ws}, dtype).setRequiresGrad();
    const Tensor mv = geometry::planeSweepMeanVar(maps2, ref, views, depths, h, w);
    const double e2 = geomtest::relError(mv.toVector(), cpuMv);
    EXPECT_LE(e2, tol) << "mean/var";
    EXPECT_TRUE(geomtest::allFinite(gradientOf(mv, maps2, seed + 2)));
    if (dtype == Dtype::F32)
      f32Errors = {e1, e2};
  }
  return f32Errors;
}

// renderMpi in both precisions against the CPU reference; everything finite.
double renderAgainstReference(const std::vector<double>& mpi, int P, int C1, int h, int w,
                              const std::vector<double>& depths, const scene::Camera& ref,
                              const std::vector<scene::Camera>& targets, int Ht, int Wt,
                              double tol32, double tol64) {
  const geomtest::CpuRender cpu =
      geomtest::renderMpi(mpi, P, C1, h, w, depths, ref, targets, Ht, Wt);
  double f32Error = 0;
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    SCOPED_TRACE(dtype == Dtype::F32 ? "float32" : "float64");
    Tensor m = Tensor::fromHost(mpi, {P, C1, h, w}, dtype).setRequiresGrad();
    const geometry::MpiRendering r = geometry::renderMpi(m, depths, ref, targets, Ht, Wt);
    // Opacity relative to its natural scale 1: with no alpha anywhere it is
    // 1 - (1 + 1e-6)^P ~ -5e-6, whose float32 rounding (of 1 + 1e-6) is ~5% of itself.
    const double e = std::max({geomtest::relError(r.color.toVector(), cpu.color),
                               geomtest::relError(r.opacity.toVector(), cpu.opacity, 1.0),
                               geomtest::relError(r.weights.toVector(), cpu.weights)});
    EXPECT_LE(e, dtype == Dtype::F32 ? tol32 : tol64);
    const Tensor all = ocl::concat(
        {ocl::reshape(r.color, {-1}), ocl::reshape(r.opacity, {-1}), ocl::reshape(r.weights, {-1})},
        0);
    EXPECT_TRUE(geomtest::allFinite(gradientOf(all, m, 77)));
    if (dtype == Dtype::F32)
      f32Error = e;
  }
  return f32Error;
}

std::vector<double> randomMpi(int P, int C1, int h, int w, uint64_t seed) {
  std::vector<double> mpi = geomtest::randomValues(std::size_t(P) * C1 * h * w, -1, 1, seed);
  for (int p = 0; p < P; ++p)
    for (int i = 0; i < h * w; ++i) {
      double& a = mpi[(std::size_t(p) * C1 + C1 - 1) * h * w + i];
      a = 0.5 + 0.45 * a;
    }
  return mpi;
}

TEST(GeometryExtremes, DepthRange1em3To1e6) {
  const std::vector<double> depths = geometry::planeDepths(9, 1e-3, 1e6);
  EXPECT_DOUBLE_EQ(depths.front(), 1e6);
  EXPECT_DOUBLE_EQ(depths.back(), 1e-3);
  const scene::Camera ref = geomtest::referenceCamera();
  const auto [e1, e2] =
      sweepAgainstReference(ref, randomViews(3, 21), depths, 3, 12, 16, 10, 14, 5);
  const double e3 = renderAgainstReference(randomMpi(9, 4, 10, 14, 6), 9, 4, 10, 14, depths, ref,
                                           randomViews(2, 22), 12, 16, 1e-4, 1e-9);
  std::printf("[extremes] depth 1e-3..1e6, float32 vs reference: samples %.3g, mean/var %.3g, "
              "render %.3g\n",
              e1, e2, e3);
}

// A source camera 5 units in front of the reference, looking the same way: planes at depth < 5
// lie behind it (the reference does not reject them: only the in-image test applies), the
// plane at depth 5 passes through its centre (z clamped to 1e-6: projected far outside).
TEST(GeometryExtremes, PlanesBehindSourceCamera) {
  const scene::Camera ref = geomtest::referenceCamera();
  scene::Camera ahead = ref;
  ahead.t = -Eigen::Vector3d(0.02, -0.01, 5.0);
  const std::vector<double> depths{1.0, 2.5, 5.0, 8.0, 20.0};
  constexpr int C = 3, Hs = 12, Ws = 14, h = 8, w = 10;
  sweepAgainstReference(ref, {ahead, randomViews(1, 23)[0]}, depths, C, Hs, Ws, h, w, 7);
  const geometry::SurfaceSamples s =
      geometry::planeSweep(Tensor::fromHost(geomtest::randomValues(2 * C * Hs * Ws, -1, 1, 8),
                                            {2, C, Hs, Ws}, Dtype::F32),
                           ref, {ahead, ahead}, depths, h, w);
  const std::vector<double> mask = s.mask.toVector();
  for (int i = 0; i < h * w; ++i)
    EXPECT_EQ(mask[2 * h * w + i], 0.0) << "plane through the source centre, pixel " << i;
  // Rendering into the camera ahead: rays meet the planes behind it at negative tau.
  renderAgainstReference(randomMpi(5, 4, h, w, 9), 5, 4, h, w, depths, ref, {ahead}, 9, 11, 1e-5,
                         1e-9);
}

// A source camera identical to the reference: every plane returns the source map resampled on
// the reference grid (exactly the map at equal size, the 2x2 box mean at twice the size), all
// valid; identical views give variance 0.
TEST(GeometryExtremes, ZeroBaseline) {
  const scene::Camera ref = geomtest::referenceCamera();
  const std::vector<double> depths{1.0, 3.0, 100.0};
  constexpr int C = 2, h = 6, w = 8;
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    const double tol = dtype == Dtype::F32 ? 2e-6 : 1e-12;
    const std::vector<double> map = geomtest::randomValues(C * h * w, -1, 1, 31);
    const geometry::SurfaceSamples s =
        geometry::planeSweep(Tensor::fromHost(map, {1, C, h, w}, dtype), ref, {ref}, depths, h, w);
    const std::vector<double> got = s.samples.toVector();
    for (int p = 0; p < 3; ++p)
      EXPECT_LE(geomtest::relError(std::vector<double>(got.begin() + p * C * h * w,
                                                       got.begin() + (p + 1) * C * h * w),
                                   map),
                tol)
          << "plane " << p;
    for (double m : s.mask.toVector())
      EXPECT_EQ(m, 1.0);

    const std::vector<double> big = geomtest::randomValues(C * 4 * h * w, -1, 1, 32);
    const std::vector<double> got2 =
        geometry::planeSweep(Tensor::fromHost(big, {1, C, 2 * h, 2 * w}, dtype), ref, {ref}, depths,
                             h, w)
            .samples.toVector();
    std::vector<double> box(std::size_t(3) * C * h * w);
    for (int p = 0; p < 3; ++p)
      for (int c = 0; c < C; ++c)
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            auto at = [&](int yy, int xx) { return big[(c * 2 * h + yy) * 2 * w + xx]; };
            box[((p * C + c) * h + y) * w + x] =
                0.25 * (at(2 * y, 2 * x) + at(2 * y, 2 * x + 1) + at(2 * y + 1, 2 * x) +
                        at(2 * y + 1, 2 * x + 1));
          }
    EXPECT_LE(geomtest::relError(got2, box), tol) << "2x2 box mean";

    // Two identical views with identical maps: mean = map * 2 / (2 + 1e-7), variance 0.
    std::vector<double> twice = map;
    twice.insert(twice.end(), map.begin(), map.end());
    const std::vector<double> mv =
        geometry::planeSweepMeanVar(Tensor::fromHost(twice, {2, C, h, w}, dtype), ref, {ref, ref},
                                    depths, h, w)
            .toVector();
    for (int p = 0; p < 3; ++p)
      for (int c = 0; c < C; ++c)
        for (int i = 0; i < h * w; ++i) {
          const double mean = mv[((p * 2 * C) + c) * h * w + i];
          const double var = mv[((p * 2 * C) + C + c) * h * w + i];
          EXPECT_NEAR(mean, map[c * h * w + i] * 2 / (2 + 1e-7), tol);
          EXPECT_NEAR(var, 0.0, tol);
        }
  }
}

// A source camera turned ~90 degrees sees the fronto-parallel planes edge-on: the plane
// homography is nearly singular. Outputs (and gradients) must stay finite, float64 must still
// match the reference.
TEST(GeometryExtremes, GrazingPlane) {
  const scene::Camera ref = geomtest::referenceCamera();
  scene::Camera side = ref;
  side.R = geomtest::rotation(M_PI / 2 - 1e-4, 0.0, 0.0);
  side.t = -side.R * Eigen::Vector3d(0.3, 0.0, 2.0);
  const std::vector<double> depths{1.0, 2.0, 2.0 + 1e-9, 4.0};
  constexpr int C = 2, Hs = 10, Ws = 12, h = 7, w = 9;
  const std::vector<double> src = geomtest::randomValues(2 * C * Hs * Ws, -1, 1, 41);
  const std::vector<scene::Camera> views{side, randomViews(1, 42)[0]};
  const CpuSamples cpu =
      geomtest::sampleSurfaces(src, false, C, Hs, Ws, views, 4, h, w, planes(ref, depths, h, w));
  double valid = 0;
  for (int i = 0; i < 4 * h * w; ++i)
    valid += cpu.mask[i];
  EXPECT_GT(valid, 0) << "the grazing view must see part of the planes";
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    Tensor maps = Tensor::fromHost(src, {2, C, Hs, Ws}, dtype).setRequiresGrad();
    const geometry::SurfaceSamples s = geometry::planeSweep(maps, ref, views, depths, h, w);
    const Tensor mv = geometry::planeSweepMeanVar(maps, ref, views, depths, h, w);
    EXPECT_TRUE(geomtest::allFinite(s.samples.toVector()));
    EXPECT_TRUE(geomtest::allFinite(mv.toVector()));
    EXPECT_TRUE(geomtest::allFinite(
        gradientOf(ocl::add(ocl::sumAll(s.samples), ocl::sumAll(mv)), maps, 43)));
    if (dtype == Dtype::F64) {
      EXPECT_EQ(s.mask.toVector(), cpu.mask);
      EXPECT_LE(geomtest::relError(s.samples.toVector(), cpu.samples), 1e-8);
    }
  }
  // Rendering: a target at the reference centre turned exactly 90 degrees about x; its middle
  // row of rays is parallel to the planes (n.r = 0, tau = d / 1e-7, z clamped).
  scene::Camera down = ref;
  down.R << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  renderAgainstReference(randomMpi(3, 3, 6, 8, 44), 3, 3, 6, 8, {8.0, 3.0, 1.5}, ref,
                         {down, views[1]}, 5, 7, 1e-5, 1e-9);
}

test::OpCase meanVarCase(int V, uint64_t seed) {
  test::OpCase c;
  c.name = "planeSweepMeanVar V=" + std::to_string(V);
  static std::vector<scene::Camera> views; // stable storage for the lambdas of this case
  views = randomViews(V, seed);
  const scene::Camera ref = geomtest::referenceCamera();
  const std::vector<double> depths{1.5, 4.0};
  c.inputShapes = {{V, 2, 6, 7}, {V, 2, 1, 6, 7}};
  c.prepare = [](test::HostInputs& in) {
    for (double& w : in[1])
      w = 0.25 * (w + 2);
  };
  c.device = [ref, depths](const std::vector<Tensor>& in) {
    return geometry::planeSweepMeanVar(in[0], ref, views, depths, 4, 5, in[1]);
  };
  c.reference = [ref, depths, V](const test::HostInputs& in) {
    const CpuSamples s =
        geomtest::sampleSurfaces(in[0], false, 2, 6, 7, views, 2, 4, 5, planes(ref, depths, 4, 5));
    const CpuSamples w =
        geomtest::sampleSurfaces(in[1], true, 1, 6, 7, views, 2, 4, 5, planes(ref, depths, 4, 5));
    return geomtest::meanVar(s, w.samples, V, 2, 2, 4, 5);
  };
  c.maxGradientProbes = 24;
  return c;
}

TEST(GeometryExtremes, SingleView) {
  test::checkOp(meanVarCase(1, 51));
}

TEST(GeometryExtremes, SixteenViews) {
  test::checkOp(meanVarCase(16, 52));
}

// Alphas exactly 0 everywhere: nothing is hit (colour 0, weights 0, back plane not forced,
// opacity 1 - (1 + 1e-6)^P). Exactly 1 everywhere: the front plane hides the rest. Gradients
// stay finite; at alpha = 0 they equal the one-sided (inward) finite differences, as PyTorch's
// clamp passes gradients at its bounds.
TEST(GeometryExtremes, AlphaExactlyZeroAndOne) {
  constexpr int P = 5, C1 = 3, h = 6, w = 7, Ht = 5, Wt = 6;
  const scene::Camera ref = geomtest::referenceCamera();
  const std::vector<scene::Camera> targets = randomViews(2, 61);
  const std::vector<double> depths{9.0, 5.0, 3.0, 2.0, 1.5};
  for (double alpha : {0.0, 1.0}) {
    SCOPED_TRACE("alpha = " + std::to_string(alpha));
    std::vector<double> mpi = randomMpi(P, C1, h, w, 62);
    for (int p = 0; p < P; ++p)
      for (int i = 0; i < h * w; ++i)
        mpi[(std::size_t(p) * C1 + C1 - 1) * h * w + i] = alpha;
    renderAgainstReference(mpi, P, C1, h, w, depths, ref, targets, Ht, Wt, 1e-5, 1e-12);
    Tensor m = Tensor::fromHost(mpi, {P, C1, h, w}, Dtype::F64).setRequiresGrad();
    const geometry::MpiRendering r = geometry::renderMpi(m, depths, ref, targets, Ht, Wt);
    const std::vector<double> opacity = r.opacity.toVector();
    if (alpha == 0.0) {
      for (double c : r.color.toVector())
        EXPECT_EQ(c, 0.0);
      for (double o : opacity)
        EXPECT_NEAR(o, 1 - std::pow(1 + 1e-6, P), 1e-15);
    } else {
      // Rays that hit the MPI: the forced back plane leaves at most ~1e-6 transmittance.
      for (double o : opacity) {
        if (o > 0.5) {
          EXPECT_NEAR(o, 1.0, 1.1e-6);
        }
      }
    }
    // One-sided differences of L = sum(out * W) for alpha entries (inward) and features.
    const Tensor all = ocl::concat(
        {ocl::reshape(r.color, {-1}), ocl::reshape(r.opacity, {-1}), ocl::reshape(r.weights, {-1})},
        0);
    const std::vector<double> W = geomtest::randomValues(all.numel(), -1, 1, 63);
    ocl::sumAll(ocl::mul(all, Tensor::fromHost(W, all.shape(), Dtype::F64))).backward();
    const std::vector<double> grad = m.grad().toVector();
    EXPECT_TRUE(geomtest::allFinite(grad));
    auto loss = [&](const std::vector<double>& values) {
      ocl::NoGradGuard noGrad;
      const geometry::MpiRendering q = geometry::renderMpi(
          Tensor::fromHost(values, {P, C1, h, w}, Dtype::F64), depths, ref, targets, Ht, Wt);
      std::vector<double> out = q.color.toVector();
      for (const Tensor& t : {q.opacity, q.weights}) {
        const std::vector<double> v = t.toVector();
        out.insert(out.end(), v.begin(), v.end());
      }
      double s = 0;
      for (std::size_t i = 0; i < out.size(); ++i)
        s += out[i] * W[i];
      return s;
    };
    const double base = loss(mpi);
    double maxDiff = 0, maxRef = 1e-12;
    for (std::size_t k = 0; k < mpi.size(); k += 7) {
      const bool isAlpha = (k / (h * w)) % C1 == C1 - 1;
      if (isAlpha && alpha == 1.0)
        continue; // at 1 the gathered alpha may round to 1 + 1e-16: a kink, no checkable slope
      const double step = isAlpha ? 1e-7 : 1e-6; // alpha: inward, below the 1e-6 threshold
      std::vector<double> plus = mpi;
      plus[k] += step;
      const double numeric = (loss(plus) - base) / step;
      maxDiff = std::max(maxDiff, std::fabs(numeric - grad[k]));
      maxRef = std::max({maxRef, std::fabs(numeric), std::fabs(grad[k])});
    }
    EXPECT_LE(maxDiff / maxRef, 1e-5);
  }
}

// The same scene in float32 and float64 agrees to 1e-5 relative (max over the output).
TEST(GeometryExtremes, Float32MatchesFloat64) {
  const scene::Camera ref = geomtest::referenceCamera();
  const std::vector<scene::Camera> views = randomViews(4, 71);
  const std::vector<double> depths = geometry::planeDepths(7, 1.0, 100.0);
  constexpr int C = 5, Hs = 24, Ws = 32, h = 12, w = 16;
  const std::vector<double> maps = geomtest::randomValues(4 * C * Hs * Ws, -1, 1, 72);
  const std::vector<double> weights = geomtest::randomValues(4 * 7 * Hs * Ws, 0, 1, 73);
  std::vector<double> depth = geomtest::randomValues(2 * Hs * Ws, 1.5, 3.0, 74);
  const std::vector<double> mpi = randomMpi(7, C + 1, h, w, 75);
  std::vector<std::vector<double>> results[2];
  for (int k = 0; k < 2; ++k) {
    const Dtype dtype = k == 0 ? Dtype::F32 : Dtype::F64;
    const Tensor m = Tensor::fromHost(maps, {4, C, Hs, Ws}, dtype);
    results[k].push_back(
        geometry::planeSweepMeanVar(m, ref, views, depths, h, w,
                                    Tensor::fromHost(weights, {4, 7, 1, Hs, Ws}, dtype))
            .toVector());
    results[k].push_back(
        geometry::unprojectLayersMeanVar(m, Tensor::fromHost(depth, {2, Hs, Ws}, dtype), ref, views)
            .toVector());
    const geometry::MpiRendering r = geometry::renderMpi(
        Tensor::fromHost(mpi, {7, C + 1, h, w}, dtype), depths, ref, views, Hs, Ws);
    results[k].push_back(r.color.toVector());
    results[k].push_back(r.weights.toVector());
  }
  const char* names[] = {"weighted plane mean/var", "layer mean/var", "render colour",
                         "render weights"};
  for (int i = 0; i < 4; ++i) {
    const double e = geomtest::relError(results[0][i], results[1][i]);
    std::printf("[extremes] float32 vs float64 %s: %.3g\n", names[i], e);
    EXPECT_LE(e, 1e-5) << names[i];
  }
}

} // namespace
} // namespace simpli

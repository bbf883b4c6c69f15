// Analytic cases checked against closed-form plane homographies computed on the CPU (no rays,
// no ray-plane intersection): an opaque textured plane rendered into a translated camera, an
// opaque plane at (near) infinity rendered into a rotated camera, and the plane sweep itself.
#include "geometry_reference.h"

#include "simpli/model/geometry/mpi_render.h"
#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_reduce.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace simpli {
namespace {

using ocl::Dtype;
using ocl::Tensor;

// Homography taking homogeneous relative pixel coordinates of camera `from` to those of camera
// `to` for points on the plane z = d of camera `plane` (z = reference-camera depth):
// X_to = R X_from + t, plane n^T X_from = d_from with n = R_pf^T e_z, ...
Eigen::Matrix3d planeHomography(const scene::Camera& from, const scene::Camera& to,
                                const scene::Camera& plane, double d) {
  // from-camera coordinates -> to-camera and -> plane-camera coordinates.
  const Eigen::Matrix3d Rto = to.R * from.R.transpose();
  const Eigen::Vector3d tto = to.t - Rto * from.t;
  const Eigen::Matrix3d Rpl = plane.R * from.R.transpose();
  const Eigen::Vector3d tpl = plane.t - Rpl * from.t;
  // Plane e_z^T (Rpl X + tpl) = d  <=>  n^T X = dn with n = Rpl^T e_z, dn = d - tpl_z.
  const Eigen::Vector3d n = Rpl.transpose() * Eigen::Vector3d::UnitZ();
  const double dn = d - tpl.z();
  return to.relativeK() * (Rto + tto * n.transpose() / dn) * from.relativeK().inverse();
}

// Grid coordinates in `to` of the centre of pixel (x, y) of a W x H image of `from`.
Eigen::Vector2d mapPixel(const Eigen::Matrix3d& H, int x, int y, int W, int Hh) {
  const Eigen::Vector3d p = H * Eigen::Vector3d((x + 0.5) / W, (y + 0.5) / Hh, 1.0);
  return {2 * p.x() / p.z() - 1, 2 * p.y() / p.z() - 1};
}

// A single-plane textured MPI with alpha 1, depth d, rendered into `target`: the colour is the
// texture warped by the plane homography (bilinear, zero outside), the weight 1 on hits; the
// optional transparent planes in front multiply it by (1 + 1e-6) each (the composer's epsilon).
void checkOpaquePlane(const scene::Camera& target, double depth,
                      const std::vector<double>& frontDepths, double tol32, double tol64) {
  const scene::Camera ref = geomtest::referenceCamera();
  constexpr int C = 3, h = 24, w = 32, Ht = 20, Wt = 28;
  const int P = 1 + static_cast<int>(frontDepths.size());
  const std::vector<double> texture = geomtest::randomValues(C * h * w, -1, 1, 81);
  std::vector<double> mpi(std::size_t(P) * (C + 1) * h * w, 0.0);
  std::copy(texture.begin(), texture.end(), mpi.begin());
  std::fill(mpi.begin() + C * h * w, mpi.begin() + (C + 1) * h * w, 1.0); // back plane alpha
  for (int p = 1; p < P; ++p) // features of the transparent planes: must not show
    for (int i = 0; i < C * h * w; ++i)
      mpi[std::size_t(p) * (C + 1) * h * w + i] = 5.0;
  std::vector<double> depths{depth};
  depths.insert(depths.end(), frontDepths.begin(), frontDepths.end());

  const Eigen::Matrix3d H = planeHomography(target, ref, ref, depth);
  const double gain = std::pow(1 + 1e-6, P - 1);
  std::vector<double> expected(std::size_t(C) * Ht * Wt);
  int hits = 0;
  for (int y = 0; y < Ht; ++y)
    for (int x = 0; x < Wt; ++x) {
      const Eigen::Vector2d g = mapPixel(H, x, y, Wt, Ht);
      hits += std::fabs(g.x()) < 1 && std::fabs(g.y()) < 1;
      for (int c = 0; c < C; ++c)
        expected[(std::size_t(c) * Ht + y) * Wt + x] =
            gain * geomtest::gridSample(texture.data() + c * h * w, h, w, g.x(), g.y());
    }
  ASSERT_GT(hits, Ht * Wt / 2) << "the plane must cover most of the target";
  ASSERT_LT(hits, Ht * Wt) << "the target should also see past the plane's edge";
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    ocl::NoGradGuard noGrad;
    const geometry::MpiRendering r = geometry::renderMpi(
        Tensor::fromHost(mpi, {P, C + 1, h, w}, dtype), depths, ref, {target}, Ht, Wt);
    const double err = geomtest::relError(r.color.toVector(), expected);
    std::printf("[analytic] %s: colour vs closed-form homography %.3g\n",
                dtype == Dtype::F32 ? "float32" : "float64", err);
    EXPECT_LE(err, dtype == Dtype::F32 ? tol32 : tol64);
  }
}

// Translated camera (and other intrinsics). The reference's tau = d / (n.r + 1e-7) moves the
// hit along the target ray by ~1e-7 relative, i.e. ~3e-7 of a texel here, hence 2e-6 even in
// float64.
TEST(GeometryAnalytic, OpaquePlaneIsExactHomographyWarp) {
  scene::Camera target;
  target.fx = 0.9;
  target.fy = 1.2;
  target.cx = 0.48;
  target.cy = 0.52;
  target.t = -Eigen::Vector3d(0.15, -0.1, 0.3);
  checkOpaquePlane(target, 3.0, {}, 1e-5, 2e-6);
  checkOpaquePlane(target, 3.0, {2.0, 1.2}, 1e-5, 2e-6); // transparent planes in front
}

// The only opaque plane at depth 1e8: translation no longer matters, the warp is the pure
// rotation homography K_ref R K_t^-1.
TEST(GeometryAnalytic, PlaneAtInfinityIsPureRotation) {
  scene::Camera target;
  target.fx = 1.1;
  target.fy = 1.4;
  target.R = geomtest::rotation(0.07, -0.05, 0.03);
  target.t = -target.R * Eigen::Vector3d(0.2, 0.1, -0.1);
  const scene::Camera ref = geomtest::referenceCamera();
  // Sanity check of the claim: the plane homography at 1e8 equals the rotation homography.
  scene::Camera rotationOnly = target;
  rotationOnly.t.setZero();
  const Eigen::Matrix3d Hinf = planeHomography(rotationOnly, ref, ref, 1.0);
  EXPECT_LE((planeHomography(target, ref, ref, 1e8) - Hinf).norm(), 1e-8);
  checkOpaquePlane(target, 1e8, {5.0}, 1e-5, 1e-9);
}

// Each plane-sweep sample is the view's map at the closed-form homography
// K_v (R_rel + t_rel e_z^T / d) K_ref^-1 of the reference pixel (§6.3), with the depth the
// reference's ray-plane intersection actually uses, d |q|^-1 / (|q|^-1 + 1e-7) for the
// reference ray q = K_ref^-1 (u, v, 1) (tau = d / (n.r + 1e-7)).
TEST(GeometryAnalytic, PlaneSweepIsClosedFormHomography) {
  std::mt19937_64 rng(91);
  const scene::Camera ref = geomtest::referenceCamera();
  std::vector<scene::Camera> views;
  for (int v = 0; v < 3; ++v)
    views.push_back(geomtest::randomCamera(rng, 0.05, 0.2));
  const std::vector<double> depths{1.2, 2.0, 7.0};
  constexpr int C = 2, Hs = 16, Ws = 20, h = 9, w = 11;
  const std::vector<double> maps = geomtest::randomValues(3 * C * Hs * Ws, -1, 1, 92);
  std::vector<double> expected(std::size_t(3) * 3 * C * h * w);
  for (int v = 0; v < 3; ++v)
    for (int p = 0; p < 3; ++p)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const Eigen::Vector3d q =
              ref.relativeK().inverse() * Eigen::Vector3d((x + 0.5) / w, (y + 0.5) / h, 1.0);
          const double nr = 1 / q.norm();
          const Eigen::Matrix3d H =
              planeHomography(ref, views[v], ref, depths[p] * nr / (nr + 1e-7));
          const Eigen::Vector2d g = mapPixel(H, x, y, w, h);
          for (int c = 0; c < C; ++c)
            expected[(((std::size_t(v) * 3 + p) * C + c) * h + y) * w + x] = geomtest::gridSample(
                maps.data() + (std::size_t(v) * C + c) * Hs * Ws, Hs, Ws, g.x(), g.y());
        }
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    ocl::NoGradGuard noGrad;
    const geometry::SurfaceSamples s = geometry::planeSweep(
        Tensor::fromHost(maps, {3, C, Hs, Ws}, dtype), ref, views, depths, h, w);
    const double err = geomtest::relError(s.samples.toVector(), expected);
    std::printf("[analytic] %s: plane sweep vs closed-form homography %.3g\n",
                dtype == Dtype::F32 ? "float32" : "float64", err);
    EXPECT_LE(err, dtype == Dtype::F32 ? 1e-5 : 1e-10);
  }
}

// Plane-sweep coverage counts the views in which the closed-form homography of each reference
// pixel lands inside the image (|g| <= 1), and equals the sweep's mask summed over views. Wide
// baselines and near planes, so counts from 0 to V occur; pixels within 1e-5 of an image edge
// are skipped in that comparison (float32 rounding decides them).
TEST(GeometryAnalytic, PlaneSweepCoverageCountsTheViewsInsideTheImage) {
  std::mt19937_64 rng(93);
  const scene::Camera ref = geomtest::referenceCamera();
  std::vector<scene::Camera> views;
  for (int v = 0; v < 4; ++v)
    views.push_back(geomtest::randomCamera(rng, 0.15, 0.6));
  const std::vector<double> depths{0.8, 1.5, 4.0};
  constexpr int V = 4, P = 3, Hs = 12, Ws = 14, h = 17, w = 23;
  std::vector<double> expected(std::size_t(P) * h * w);
  std::vector<bool> decided(expected.size(), true);
  std::vector<int> histogram(V + 1, 0);
  for (int p = 0; p < P; ++p)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t i = (std::size_t(p) * h + y) * w + x;
        const Eigen::Vector3d q =
            ref.relativeK().inverse() * Eigen::Vector3d((x + 0.5) / w, (y + 0.5) / h, 1.0);
        const double nr = 1 / q.norm();
        int seen = 0;
        for (int v = 0; v < V; ++v) {
          const Eigen::Matrix3d H =
              planeHomography(ref, views[v], ref, depths[p] * nr / (nr + 1e-7));
          const Eigen::Vector2d g = mapPixel(H, x, y, w, h);
          const double edge = std::max(std::abs(g.x()), std::abs(g.y()));
          decided[i] = decided[i] && std::abs(edge - 1) > 1e-5;
          seen += edge <= 1;
        }
        expected[i] = seen;
        ++histogram[seen];
      }
  for (int n = 0; n <= V; ++n)
    EXPECT_GT(histogram[n], 0) << "no point seen by exactly " << n << " views: a weak case";
  const std::vector<double> maps = geomtest::randomValues(V * 2 * Hs * Ws, -1, 1, 94);
  for (Dtype dtype : {Dtype::F32, Dtype::F64}) {
    const Tensor sources = Tensor::fromHost(maps, {V, 2, Hs, Ws}, dtype);
    const std::vector<double> coverage =
        geometry::planeSweepCoverage(sources, ref, views, depths, h, w).toVector();
    ASSERT_EQ(coverage.size(), expected.size());
    int wrong = 0;
    for (std::size_t i = 0; i < expected.size(); ++i)
      wrong += decided[i] && coverage[i] != expected[i];
    EXPECT_EQ(wrong, 0) << (dtype == Dtype::F32 ? "float32" : "float64");
    const std::vector<double> maskSum =
        ocl::sum(geometry::planeSweep(sources, ref, views, depths, h, w).mask, 0).toVector();
    EXPECT_EQ(coverage, maskSum) << (dtype == Dtype::F32 ? "float32" : "float64");
  }
}

} // namespace
} // namespace simpli

#pragma once
// Plain C++ double-precision references for the geometry ops, written the way the reference
// implementation computes them (world coordinates: back-project, ray-plane intersection,
// project, grid_sample, composer), independently of the kernels' relative-transform form.
// Plus random cameras and small helpers shared by the geometry tests.
#include "simpli/model/scene/camera.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <random>
#include <vector>

namespace simpli::geomtest {

/// F.grid_sample (bilinear, zero padding, align_corners = False) of one H x W plane at grid
/// coordinates (gx, gy).
double gridSample(const double* plane, int H, int W, double gx, double gy);

/// Grid coordinates (2u - 1, 2v - 1) of a world point seen by `camera` (Camera::project keeps
/// the sign-preserving |z| >= 1e-6 clamp).
Eigen::Vector2d gridOf(const scene::Camera& camera, const Eigen::Vector3d& world);

/// World point of reference pixel (x, y) (centre grid of h x w) on the plane at depth d, by the
/// reference's ray-plane intersection: unit ray r, tau = d / (n.r + 1e-7).
Eigen::Vector3d planePoint(const scene::Camera& ref, int x, int y, int h, int w, double d);
/// World point of texel (x, y) (corner grid of h x w) at reference depth d.
Eigen::Vector3d layerPoint(const scene::Camera& ref, int x, int y, int h, int w, double d);

/// surface s, pixel (x, y) -> world point.
using PointFn = std::function<Eigen::Vector3d(int s, int x, int y)>;

struct CpuSamples {
  std::vector<double> samples; ///< [V, S, C, h, w]
  std::vector<double> mask;    ///< [V, S, 1, h, w]
};

/// Plain sampling: src [V, C, Hs, Ws] (or [V, S, C, Hs, Ws] when perSurface).
CpuSamples sampleSurfaces(const std::vector<double>& src, bool perSurface, int C, int Hs, int Ws,
                          const std::vector<scene::Camera>& views, int S, int h, int w,
                          const PointFn& point);

/// Fused mean / variance [S, 2C, h, w] from plain samples; `gatheredWeights` [V, S, 1, h, w]
/// multiplies the mask-normalised weights when not empty.
std::vector<double> meanVar(const CpuSamples& s, const std::vector<double>& gatheredWeights, int V,
                            int S, int C, int h, int w);

struct CpuRender {
  std::vector<double> color;   ///< [N, C, Ht, Wt]
  std::vector<double> opacity; ///< [N, 1, Ht, Wt]
  std::vector<double> weights; ///< [N, P, 1, Ht, Wt]
};

/// The reference's look_at (world-space rays) + ComposerStereoMagnification.
CpuRender renderMpi(const std::vector<double>& mpi, int P, int C1, int h, int w,
                    const std::vector<double>& depths, const scene::Camera& ref,
                    const std::vector<scene::Camera>& targets, int Ht, int Wt);

/// The composer alone: features [N, P, C1, Ht, Wt] (alpha last) -> colour, opacity, weights.
CpuRender compose(const std::vector<double>& features, int N, int P, int C1, int Ht, int Wt);

// ---- helpers -----------------------------------------------------------------------------------

/// Rotation about the camera axes by small angles (radians): Ry(a) Rx(b) Rz(c).
Eigen::Matrix3d rotation(double a, double b, double c);

/// A camera near the reference (identity pose): rotations up to `maxAngle` radians, centre
/// offsets up to `baseline`, relative intrinsics fx ~ 1.0, fy ~ 1.3, principal point ~ 0.5.
scene::Camera randomCamera(std::mt19937_64& rng, double maxAngle, double baseline);

/// Reference camera: identity pose, fx = 1.0, fy = 1.3, principal point (0.5, 0.5).
scene::Camera referenceCamera();

std::vector<double> randomValues(std::size_t n, double low, double high, uint64_t seed);

/// max |a - b| / max(max |b|, floor) (infinite for size mismatch or non-finite a).
double relError(const std::vector<double>& a, const std::vector<double>& b, double floor = 1e-30);
bool allFinite(const std::vector<double>& v);

/// Distance, in source pixels of an axis of n pixels, from grid coordinate g to the nearest
/// point where a gathered value is not smooth: a bilinear kink (integer source position) or the
/// validity border |g| = 1.
double kinkMargin(double g, int n);

} // namespace simpli::geomtest

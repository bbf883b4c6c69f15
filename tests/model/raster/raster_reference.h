#pragma once
// Plain C++ double-precision reference of the MLI rasterizer (rules in
// model/include/simpli/model/rasterizer.h), brute force per triangle and pixel, for the tests.
// Vertices go through world coordinates with the Camera methods (the device code composes the
// two cameras into one transform instead).
#include "simpli/model/raster/rasterizer.h"
#include "simpli/model/scene/camera.h"
#include "simpli/ocl/tensor.h"

#include <cstdint>
#include <vector>

namespace simpli::test {

struct LayerScene {
  int L = 1, H = 2, W = 2, A = 4;
  std::vector<double> depth;       ///< [L, H, W]
  std::vector<double> attrs;       ///< [L, A, H, W]
  scene::Camera reference, target; ///< target.width x target.height is the output size
  raster::RasterSettings settings;

  ocl::Tensor depthTensor(ocl::Dtype dtype) const;
  ocl::Tensor attrTensor(ocl::Dtype dtype) const;
};

struct ReferenceImage {
  int Ht = 0, Wt = 0, K = 0, A = 0;
  std::vector<double> colour;  ///< [A-1, Ht, Wt]
  std::vector<double> opacity; ///< [Ht, Wt]
  std::vector<double> depth;   ///< [Ht, Wt]
  std::vector<double> weights; ///< [K, Ht, Wt]
  std::vector<int> ids;        ///< [K, Ht, Wt] triangle ids, -1 empty
  /// Pixels whose result may legitimately differ between float and double (a centre within
  /// 1e-3 px of a silhouette or fold edge, fragments of near-equal depth, depth near the far
  /// cut, near-degenerate triangles): excluded from comparisons.
  std::vector<char> ambiguous; ///< [Ht, Wt]
  int ambiguousCount() const;
};

ReferenceImage referenceRender(const LayerScene& scene);

/// Rendered outputs downloaded to the host.
struct DeviceImage {
  std::vector<double> colour, opacity, depth, weights;
};
DeviceImage download(const raster::RenderedLayers& r);

/// Max over non-ambiguous pixels of |a - b| / max(1, |b|) for every output; also fails the
/// test on any non-finite device value.
double maxRelativeError(const DeviceImage& device, const ReferenceImage& ref);

/// A random rotation of at most `degrees` about a random axis (deterministic for a seed).
Eigen::Matrix3d smallRotation(double degrees, unsigned seed);

/// A camera with relative intrinsics (fx, fy, cx, cy), pose R, t and size.
scene::Camera makeCamera(double fx, double fy, double cx, double cy, int width, int height,
                         const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity(),
                         const Eigen::Vector3d& t = Eigen::Vector3d::Zero());

/// The camera whose W x H pixel centres are exactly the corner-grid vertex rays of `ref`
/// (same pose; intrinsics scaled by (W-1)/W and shifted half a pixel).
scene::Camera cornerGridCamera(const scene::Camera& ref, int W, int H);

/// Uniform random values in [lo, hi) (deterministic for a seed).
std::vector<double> randomValues(std::size_t n, double lo, double hi, unsigned seed);

} // namespace simpli::test

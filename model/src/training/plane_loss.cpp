// Level-0 plane supervision from true depth (training/plane_loss.h).
#include "simpli/model/training/plane_loss.h"

#include "simpli/error.h"

#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"

#include <algorithm>
#include <cmath>

namespace simpli::training {
namespace {

// Writes the distribution of disparity s over the planes (disparities ascending) at `out`,
// stepping `stride` between planes (the other planes keep their zeros).
void spreadOverPlanes(double s, const std::vector<double>& planeDisparity, double* out,
                      size_t stride) {
  const size_t P = planeDisparity.size();
  if (P == 1 || s <= planeDisparity.front()) {
    out[0] = 1;
    return;
  }
  if (s >= planeDisparity.back()) {
    out[(P - 1) * stride] = 1;
    return;
  }
  const size_t hi = size_t(std::upper_bound(planeDisparity.begin(), planeDisparity.end(), s) -
                           planeDisparity.begin());
  const size_t lo = hi - 1;
  const double t = (s - planeDisparity[lo]) / (planeDisparity[hi] - planeDisparity[lo]);
  out[lo * stride] = 1 - t;
  out[hi * stride] = t;
}

} // namespace

PlaneTargets planeTargets(const std::vector<double>& planeDepths, const scene::Camera& reference,
                          const std::vector<scene::Camera>& sources,
                          const std::vector<std::vector<float>>& depths, int depthWidth,
                          int depthHeight, int height, int width) {
  const char* op = "planeTargets";
  if (planeDepths.empty())
    fail(op, ": no planes");
  std::vector<double> disparity;
  for (double d : planeDepths) {
    if (!(d > 0) || !std::isfinite(d))
      fail(op, ": plane depth ", d, " must be finite and positive");
    disparity.push_back(1 / d);
  }
  if (!std::is_sorted(disparity.begin(), disparity.end()))
    fail(op, ": plane depths must go from the farthest to the nearest");
  if (depths.size() != sources.size())
    fail(op, ": ", depths.size(), " depth maps for ", sources.size(), " sources");
  if (height < 1 || width < 1 || depthWidth < 1 || depthHeight < 1)
    fail(op, ": sizes ", width, "x", height, " and depth maps ", depthWidth, "x", depthHeight,
         " must be positive");
  const size_t P = planeDepths.size(), plane = size_t(height) * size_t(width);
  PlaneTargets out;
  out.values.assign(sources.size() * P * plane, 0.0);
  for (size_t v = 0; v < sources.size(); ++v) {
    const std::vector<float>& depth = depths[v];
    if (depth.size() != size_t(depthWidth) * size_t(depthHeight))
      fail(op, ": depth map ", v, " has ", depth.size(), " values, not ", depthWidth, "x",
           depthHeight);
    const scene::Camera& c = sources[v];
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const double u = (x + 0.5) / width, w = (y + 0.5) / height;
        const int col = std::min(int(u * depthWidth), depthWidth - 1);
        const int row = std::min(int(w * depthHeight), depthHeight - 1);
        const double z = depth[size_t(row) * size_t(depthWidth) + size_t(col)];
        if (!(z >= 0) || !std::isfinite(z))
          continue;
        const Eigen::Vector3d ray((u - c.cx) / c.fx, (w - c.cy) / c.fy, 1);
        // z = 0: the ray met nothing, and the renderer coloured it by its direction alone (the
        // sky): a point at infinity, seen from the reference along the rotated ray.
        const Eigen::Vector3d inRef = z > 0 ? reference.worldToCamera(c.cameraToWorld(ray * z))
                                            : Eigen::Vector3d(reference.R * c.R.transpose() * ray);
        const double zRef = inRef.z();
        if (!(zRef > 0))
          continue;
        // A point outside the reference image lies outside the MPI, where every plane is
        // transparent: no weights could ever meet its target.
        const double ur = reference.fx * inRef.x() / zRef + reference.cx;
        const double vr = reference.fy * inRef.y() / zRef + reference.cy;
        if (!(ur >= 0 && ur <= 1 && vr >= 0 && vr <= 1))
          continue;
        double* at = out.values.data() + v * P * plane + size_t(y) * size_t(width) + size_t(x);
        spreadOverPlanes(z > 0 ? 1 / zRef : 0.0, disparity, at, plane);
        ++out.known;
      }
  }
  return out;
}

ocl::Tensor planeCrossEntropy(const ocl::Tensor& weights, const PlaneTargets& targets) {
  if (weights.dim() != 5 || weights.size(2) != 1 ||
      size_t(weights.numel()) != targets.values.size())
    fail("planeCrossEntropy: weights ", weights.describe(), " do not match ", targets.values.size(),
         " target values ([V, P, 1, H, W])");
  if (targets.known == 0)
    return ocl::Tensor::zeros({1}, weights.dtype());
  constexpr double eps = 1e-6; // log stays finite where a plane has no weight
  const ocl::Tensor t = ocl::Tensor::fromHost(targets.values, weights.shape(), weights.dtype());
  const ocl::Tensor logW = ocl::log(ocl::addScalar(weights, eps));
  return ocl::mulScalar(ocl::sumAll(ocl::mul(t, logW)), -1.0 / double(targets.known)); // [1]
}

} // namespace simpli::training

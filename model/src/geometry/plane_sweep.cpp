#include "simpli/model/geometry/plane_sweep.h"

#include "geometry/sampling.h"
#include "simpli/error.h"

#include <cmath>

namespace simpli::geometry {

namespace {

// Plane depths as a device tensor in the maps' dtype (constants: no gradient).
geometry::SurfaceSpec planeSpec(const char* op, const ocl::Tensor& sources,
                                const std::vector<double>& depths, int height, int width) {
  if (depths.empty())
    fail(op, ": no plane depths");
  for (std::size_t p = 0; p < depths.size(); ++p)
    if (!std::isfinite(depths[p]) || !(depths[p] > 0))
      fail(op, ": plane depth ", p, " = ", depths[p], " must be finite and positive");
  if (!sources.defined())
    fail(op, ": undefined source maps");
  geometry::SurfaceSpec spec;
  spec.op = op;
  spec.layers = false;
  spec.surfaces = static_cast<int>(depths.size());
  spec.height = height;
  spec.width = width;
  spec.depth =
      ocl::Tensor::fromHost(depths, {static_cast<int64_t>(depths.size())}, sources.dtype());
  return spec;
}

} // namespace

SurfaceSamples planeSweep(const ocl::Tensor& sources, const scene::Camera& reference,
                          const std::vector<scene::Camera>& views,
                          const std::vector<double>& depths, int height, int width) {
  return geometry::sampleSurfaces(sources, reference, views,
                                  planeSpec("planeSweep", sources, depths, height, width));
}

ocl::Tensor planeSweepCoverage(const ocl::Tensor& sources, const scene::Camera& reference,
                               const std::vector<scene::Camera>& views,
                               const std::vector<double>& depths, int height, int width) {
  return geometry::sampleSurfacesCoverage(
      sources, reference, views, planeSpec("planeSweepCoverage", sources, depths, height, width));
}

ocl::Tensor planeSweepMeanVar(const ocl::Tensor& sources, const scene::Camera& reference,
                              const std::vector<scene::Camera>& views,
                              const std::vector<double>& depths, int height, int width,
                              const ocl::Tensor& weights) {
  return geometry::sampleSurfacesMeanVar(
      sources, weights, reference, views,
      planeSpec("planeSweepMeanVar", sources, depths, height, width));
}

} // namespace simpli::geometry

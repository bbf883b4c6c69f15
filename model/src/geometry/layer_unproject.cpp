#include "simpli/model/geometry/layer_unproject.h"

#include "geometry/sampling.h"
#include "simpli/error.h"

#include "simpli/ocl/launch.h"

namespace simpli::geometry {

namespace {

geometry::SurfaceSpec layerSpec(const char* op, const ocl::Tensor& depth) {
  if (!depth.defined())
    fail(op, ": undefined depth");
  if (depth.dim() != 3)
    fail(op, ": depth ", depth.describe(), " must be [L, H, W]");
  if (depth.numel() == 0)
    fail(op, ": depth ", depth.describe(), " is empty");
  ocl::checkedInt(depth.numel(), op);
  geometry::SurfaceSpec spec;
  spec.op = op;
  spec.layers = true;
  spec.surfaces = static_cast<int>(depth.shape()[0]);
  spec.height = static_cast<int>(depth.shape()[1]);
  spec.width = static_cast<int>(depth.shape()[2]);
  spec.depth = depth;
  return spec;
}

} // namespace

SurfaceSamples unprojectLayers(const ocl::Tensor& sources, const ocl::Tensor& depth,
                               const scene::Camera& reference,
                               const std::vector<scene::Camera>& views) {
  return geometry::sampleSurfaces(sources, reference, views, layerSpec("unprojectLayers", depth));
}

ocl::Tensor unprojectLayersMeanVar(const ocl::Tensor& sources, const ocl::Tensor& depth,
                                   const scene::Camera& reference,
                                   const std::vector<scene::Camera>& views) {
  return geometry::sampleSurfacesMeanVar(sources, ocl::Tensor(), reference, views,
                                         layerSpec("unprojectLayersMeanVar", depth));
}

} // namespace simpli::geometry

#pragma once
// Shared host side of the surface-sampling ops (plane sweep and layer unprojection, both in
// kernels/sweep.cl): argument checks, the per-view camera blocks and the launches with their
// recorded backward passes.
#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/model/scene/camera.h"

#include "simpli/ocl/tensor.h"

#include <string>
#include <vector>

namespace simpli::geometry {

/// Throws simpli::Error naming op, role ("reference camera", "source camera 3", ...) and value
/// unless R, t are finite and the relative intrinsics are finite with fx, fy != 0.
void checkCamera(const scene::Camera& camera, const char* op, const std::string& role);

/// 16 values per view (kernels' CAM_STRIDE): R = R_v R_ref^T (row-major), t = t_v - R t_ref,
/// fx, fy, cx, cy of view v.
std::vector<double> viewBlocks(const scene::Camera& reference,
                               const std::vector<scene::Camera>& views);

/// Surfaces to sample: planes (depth [S], centre grid) or layers (depth [S, h, w], corner grid).
struct SurfaceSpec {
  const char* op = "";
  bool layers = false;
  int surfaces = 0, height = 0, width = 0;
  ocl::Tensor depth; ///< [S] plane depths or [S, h, w] layer depths, dtype of the maps
};

SurfaceSamples sampleSurfaces(const ocl::Tensor& sources, const scene::Camera& reference,
                              const std::vector<scene::Camera>& views, const SurfaceSpec& spec);

/// [S, 1, h, w]: the number of views whose mask is 1 at each surface point (no gradient);
/// `sources` give only the views' count and the dtype.
ocl::Tensor sampleSurfacesCoverage(const ocl::Tensor& sources, const scene::Camera& reference,
                                   const std::vector<scene::Camera>& views,
                                   const SurfaceSpec& spec);

/// [S, 2C, h, w] mean | variance; `weights` may be undefined.
ocl::Tensor sampleSurfacesMeanVar(const ocl::Tensor& sources, const ocl::Tensor& weights,
                                  const scene::Camera& reference,
                                  const std::vector<scene::Camera>& views, const SurfaceSpec& spec);

} // namespace simpli::geometry

#pragma once
// Bridges the CPU MLI type (mli/mli.h) and the OpenCL rasterizer (raster/rasterizer.h).
#include "simpli/model/mli/mli.h"
#include "simpli/model/raster/rasterizer.h"

#include "simpli/ocl/tensor.h"

namespace simpli::raster {

struct MLITensors {
  ocl::Tensor depth; ///< [L, H, W] reference-camera z, layer 0 = farthest (as the MLI)
  ocl::Tensor rgba;  ///< [L, 4, H, W] straight RGBA in [0, 1], alpha last
};

/// Uploads `mli` (validated first) as device tensors of `dtype`.
MLITensors mliTensors(const mli::MLI& mli, ocl::Dtype dtype = ocl::Dtype::F32);

/// Renders `mli` into `target` (its width x height is the output size); colour is RGB in
/// [0, 1] over a background of 0.
RenderedLayers renderMLI(const mli::MLI& mli, const scene::Camera& target,
                         const RasterSettings& settings = {}, ocl::Dtype dtype = ocl::Dtype::F32);

} // namespace simpli::raster

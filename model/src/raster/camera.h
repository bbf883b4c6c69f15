#pragma once
// Projection of MLI layer vertices into a target camera, shared by the rasterizer passes
// (raster/rasterizer.h): the parameter block the raster kernels read, and its checks.
#include "simpli/model/raster/rasterizer.h"
#include "simpli/model/scene/camera.h"

#include "simpli/ocl/tensor.h"

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace simpli::raster {

/// Throws simpli::Error naming `op`, `which` camera and the bad field unless the camera has
/// finite values, fx, fy > 0 and a proper rotation; `needSize` also requires width, height >= 1.
void checkCamera(const scene::Camera& camera, const char* op, const char* which, bool needSize);

/// Throws unless every setting is in range (naming `op`, the field and the value).
void checkSettings(const RasterSettings& settings, const char* op);

/// The kernels' parameter block (layout: PRM_* in model/kernels/raster.cl). A reference-camera
/// point Xr maps to Xt = M Xr + t in the target camera, M = R_t R_r^T, t = t_t - M t_r; target
/// intrinsics are in pixels of the target size. farZ <= 0 or infinite becomes `farDisabled`.
std::vector<double> projectionParameters(const scene::Camera& reference,
                                         const scene::Camera& target, double nearZ, double farZ,
                                         double farDisabled);

/// The parameter block as a tensor of `dtype` (farZ disabled -> the dtype's largest value).
ocl::Tensor parameterTensor(const scene::Camera& reference, const scene::Camera& target,
                            double nearZ, double farZ, ocl::Dtype dtype);

/// Throws unless `depth` is [L, H, W] with L >= 1, H, W >= 2 and 32-bit-indexable sizes.
void checkDepth(const ocl::Tensor& depth, const char* op);

/// [L*H*W, 4] = (x pixel, y pixel, target z, valid) per vertex (raster_project; not recorded).
/// Every kernel of the raster program is built with programOptions(maxFragments).
ocl::Tensor projectVertices(const ocl::Tensor& depth, const ocl::Tensor& params, int maxFragments);

/// Build options of the raster program for K fragments per pixel.
std::string programOptions(int maxFragments);

/// A device buffer of `count` int32 (from the engine's pool).
std::shared_ptr<ocl::Buffer> intBuffer(std::size_t count);

} // namespace simpli::raster

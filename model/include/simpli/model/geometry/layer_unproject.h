#pragma once
// Unprojection onto deformable layers (spec §6.5): texel (i, j) of layer k lives
// on the reference ray through the corner-grid coordinate (u, v) = (j / (W - 1), i / (H - 1))
// at reference-camera z = depth[k, i, j]; it is projected into each source view and gathered
// exactly as in the plane sweep (plane_sweep.h: sign-preserving |z| >= 1e-6 clamp, bilinear
// F.grid_sample semantics, validity |gx|, |gy| <= 1).
//
// Differentiable with respect to the source maps and to the depth (through the sampling
// coordinates; the validity mask is piecewise constant and passes no gradient). Runs in the
// dtype of `sources`; `depth` must have the same dtype.
#include "simpli/model/geometry/plane_sweep.h"
#include "simpli/model/scene/camera.h"

#include "simpli/ocl/tensor.h"

#include <vector>

namespace simpli::geometry {

/// sources [V, C, Hs, Ws] (or [V, L, C, Hs, Ws], layer k gathering its own slice),
/// depth [L, H, W] with H, W >= 2 -> samples [V, L, C, H, W] and mask [V, L, 1, H, W].
SurfaceSamples unprojectLayers(const ocl::Tensor& sources, const ocl::Tensor& depth,
                               const scene::Camera& reference,
                               const std::vector<scene::Camera>& views);

/// Fused mean / variance over the views (weights w_v = m_v / (sum_v m_v + 1e-7), as
/// planeSweepMeanVar without weight maps): sources [V, C, Hs, Ws], depth [L, H, W] ->
/// [L, 2C, H, W] = [mean | variance]. At most 64 views.
ocl::Tensor unprojectLayersMeanVar(const ocl::Tensor& sources, const ocl::Tensor& depth,
                                   const scene::Camera& reference,
                                   const std::vector<scene::Camera>& views);

} // namespace simpli::geometry

#pragma once
// Plane sweep ("unprojection onto planes", spec §6.3): the reference pixels
// (centre grid h x w) of every plane p are placed at depth d_p along their reference rays (the
// reference's ray-plane intersection, tau = d_p / (n.r + 1e-7)), projected into each source
// view (z pushed away from 0 keeping its sign, |z| >= 1e-6; points behind a view are not
// rejected) and bilinearly gathered from the view's map (F.grid_sample: zero padding,
// align_corners = False). A sample is valid when |gx| <= 1 and |gy| <= 1 (inclusive).
//
// All ops run in the dtype of `sources` (float32 or float64), are differentiable with respect
// to the maps (and weight maps) and are recorded on the autograd tape. Cameras use relative
// intrinsics (scene/camera.h); their image sizes are ignored.
#include "simpli/model/scene/camera.h"

#include "simpli/ocl/tensor.h"

#include <vector>

namespace simpli::geometry {

/// Per-view samples of a set of surfaces and their validity.
struct SurfaceSamples {
  ocl::Tensor samples; ///< [V, S, C, h, w], differentiable
  ocl::Tensor mask;    ///< [V, S, 1, h, w], 1 = valid, 0 = outside (not differentiable)
};

/// The plain plane-sweep volume. sources: [V, C, Hs, Ws] (one map per view, V = views.size()),
/// or [V, P, C, Hs, Ws] where plane p gathers its own slice (e.g. the level-1 composite weights).
/// depths: P plane depths (finite, > 0). Output grid: height x width (centre grid).
/// Materialises V x P x C x h x w values: for small cases and tests; the network uses
/// planeSweepMeanVar.
SurfaceSamples planeSweep(const ocl::Tensor& sources, const scene::Camera& reference,
                          const std::vector<scene::Camera>& views,
                          const std::vector<double>& depths, int height, int width);

/// How many views see each point of every plane: planeSweep's mask summed over views, [P, 1,
/// height, width], without gathering the maps (sources [V, C, Hs, Ws] give only the view count
/// and dtype). Not differentiable.
ocl::Tensor planeSweepCoverage(const ocl::Tensor& sources, const scene::Camera& reference,
                               const std::vector<scene::Camera>& views,
                               const std::vector<double>& depths, int height, int width);

/// The fused aggregation of the reference's TBlock (§3 step 2.4, §4.7), without materialising
/// the sweep: w_v = m_v / (sum_v m_v + 1e-7), times plane p's own slice of `weights`
/// [V, P, 1, Hs, Ws] gathered like the maps when `weights` is defined (level 1; not
/// renormalised); mean = sum_v w_v s_v, var = sum_v w_v (s_v - mean)^2 (not divided by sum w).
/// sources: [V, C, Hs, Ws]. Returns [P, 2C, height, width] = [mean (C) | variance (C)] per
/// plane. Differentiable with respect to sources and weights. At most 64 views.
ocl::Tensor planeSweepMeanVar(const ocl::Tensor& sources, const scene::Camera& reference,
                              const std::vector<scene::Camera>& views,
                              const std::vector<double>& depths, int height, int width,
                              const ocl::Tensor& weights = ocl::Tensor());

} // namespace simpli::geometry

#pragma once
// MPI rendering into other cameras (spec §6.4; the reference's
// SurfacesMPI.look_at + ComposerStereoMagnification). For every target pixel (centre grid) the
// unit ray r from the target centre C_c meets plane p {X : n.(X - C_ref) = d_p} at
// tau = (d_p + n.(C_ref - C_c)) / (n.r + 1e-7); the hit is projected into the reference camera
// (|z| >= 1e-6, sign kept) and the plane's C features + alpha are gathered bilinearly (zero
// outside the MPI). Compositing in plane-index order (0 = back): alphas are clamped to [0, 1];
// where their sum exceeds 1e-6 the back plane's alpha becomes 1, otherwise 0 (the reference
// composer's masked background, so rays that miss the MPI stay 0);
// T_p = prod_{q>p} (1 - a_q + 1e-6), w_p = a_p T_p, colour = sum_p w_p f_p,
// opacity = 1 - prod_q (1 - a_q + 1e-6).
#include "simpli/model/scene/camera.h"

#include "simpli/ocl/tensor.h"

#include <vector>

namespace simpli::geometry {

struct MpiRendering {
  ocl::Tensor color;   ///< [N, C, Ht, Wt]
  ocl::Tensor opacity; ///< [N, 1, Ht, Wt]
  ocl::Tensor weights; ///< [N, P, 1, Ht, Wt], the per-plane compositing weights w_p
};

/// mpi [P, C + 1, h, w] (C >= 1 feature channels, alpha last) of `reference` with plane depths
/// `depths` (P values, finite, > 0; index 0 = back), rendered into the N = targets.size()
/// cameras at height x width. Differentiable with respect to the MPI (features and alphas);
/// runs in the MPI's dtype.
MpiRendering renderMpi(const ocl::Tensor& mpi, const std::vector<double>& depths,
                       const scene::Camera& reference, const std::vector<scene::Camera>& targets,
                       int height, int width);

} // namespace simpli::geometry

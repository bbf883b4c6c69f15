#pragma once
// Geometry supervision at level 0 (optional, not in the reference; issue 10 item 3): the
// level-0 MPI composited into the source views (the render intermediate loss 0 compares) gives
// every source pixel a distribution over the planes, the compositing weights w_p. Synthetic
// scenes know where that pixel's surface is; this term asks the weights to put their mass on
// the planes around it. A direct, per-plane signal to the stage that decides geometry, where
// the novel-view depth term reaches it only through the layers and the corrections.
#include "simpli/model/scene/camera.h"
#include "simpli/ocl/tensor.h"

#include <cstdint>
#include <vector>

namespace simpli::training {

struct PlaneTargets {
  /// [V, P, 1, height, width] as the MPI render's weights: per known pixel a distribution over
  /// the planes (sums to 1), zero elsewhere.
  std::vector<double> values;
  int64_t known = 0; ///< pixels with a surface (the term's denominator)
};

/// For every pixel of every source at height x width (centre grid, as renderMpi's targets): the
/// surface point from the true depth (`depths[v]`, depthWidth x depthHeight source-camera z;
/// nearest texel), its reference-camera z, and the two planes around its disparity 1/z,
/// weighted linearly in disparity (all mass on the back or front plane beyond the range).
/// `planeDepths` are the generator's (index 0 = back, the farthest). Depth 0 is the synthetic
/// renderer's "the ray met nothing" (the sky, coloured by direction alone): a point at
/// infinity, whose target is the back plane. Pixels whose point lies behind the reference
/// camera or outside its image (outside the MPI, where no plane has weight), or whose depth is
/// negative or not finite, get no target.
PlaneTargets planeTargets(const std::vector<double>& planeDepths, const scene::Camera& reference,
                          const std::vector<scene::Camera>& sources,
                          const std::vector<std::vector<float>>& depths, int depthWidth,
                          int depthHeight, int height, int width);

/// -sum_p t_p log(w_p + 1e-6) summed over the pixels and divided by targets.known (0 when no
/// pixel is known): the cross-entropy of the compositing weights `weights` [V, P, 1, H, W]
/// against the targets. Differentiable with respect to the weights.
ocl::Tensor planeCrossEntropy(const ocl::Tensor& weights, const PlaneTargets& targets);

} // namespace simpli::training

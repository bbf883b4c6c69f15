#pragma once
// The training losses of the reference (spec §8.1), by key name:
//  l1                     masked L1 on the novel views, mask = rendered opacity (ops_loss.h)
//  perceptual             VGG-19 loss (training/vgg.h), same mask; only with a VGG weights file
//  intermediate_loss_0_l1 mean L1: level-1 MPI render (channels 9-11, H/2) vs the clean sources
//                         nearest-downsampled to H/2 (F.interpolate's default mode)
//  intermediate_loss_k_l1 (k = 1..3) mean L1: the mesh render that fed correction k vs the
//                         clean sources at H
//  smooth_layers          smoothLayersLoss of the final layer depths [1, L, H, W]
//  depth                  not in the reference, off by default (weight 0): where the true depth
//                         of the novel views is known (synthetic scenes), depthLoss of the
//                         rendered depth and opacity against it
//  mpi_depth              not in the reference, off by default: planeCrossEntropy (plane_loss.h)
//  ssim                   not in the reference, off by default: ssimLossOfSignedImages of the
//                         novel views
// total = sum of weight * term over the terms with a positive weight.
#include "simpli/model/generator/generator.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/plane_loss.h"
#include "simpli/model/training/vgg.h"

#include "simpli/ocl/tensor.h"

#include <string>
#include <utility>
#include <vector>

namespace simpli::training {

struct LossTerms {
  /// Every term that was computed (unweighted), in lossTermNames() order.
  std::vector<std::pair<std::string, ocl::Tensor>> terms;
  ocl::Tensor total; ///< [1]

  /// The value of a computed term, NaN when it was not computed.
  double value(const std::string& name) const;
};

/// Nearest-neighbour resize of x [..., H, W] to outH x outW as F.interpolate(mode='nearest'):
/// source index floor(dst * in / out). Differentiable (a gather).
ocl::Tensor resizeNearest(const ocl::Tensor& x, int64_t outH, int64_t outW);

/// Depth supervision of a render: the opacity-weighted error of the log expected depth,
///   mean over the pixels with a known surface of A | log((D + eps) / (A + eps)) - log z |
/// with D [N, 1, H, W] the composited depth sum_k w_k z_k, A [N, 1, H, W] the opacity sum_k w_k
/// (so D / A is the expected depth zhat, a convex combination of the layer depths), z the true
/// depth given as inverseDepth = 1 / z (0 = no surface: not counted) and eps = 1e-6. A log
/// error is a relative one, so near and far surfaces weigh alike on scenes whose depths span
/// 1:100 (an error in z itself, or in z scaled by 1/z^2, lets the far range dominate); the
/// gradient is bounded: A / D = 1 / zhat for D, |log(zhat / z)| + 1 for A. A transparent pixel
/// (A = 0) costs nothing.
ocl::Tensor depthLoss(const ocl::Tensor& renderedDepth, const ocl::Tensor& renderedOpacity,
                      const ocl::Tensor& inverseDepth);

/// 1 - SSIM of rendered and target images [N, 3, H, W] in [-1, 1], mapped to [0, 1] first: one
/// minus the evaluation metric (metrics::ssim, 11 x 11 Gaussian window of sigma 1.5, valid
/// windows), differentiable. Not masked by the rendered opacity: a render with a reference margin
/// covers the novel views, and an uncovered pixel is an error the metric counts too.
ocl::Tensor ssimLossOfSignedImages(const ocl::Tensor& rendered, const ocl::Tensor& target);

/// novelColour [N, 3, H, W], novelOpacity [N, 1, H, W], novelTargets [N, 3, H, W],
/// cleanSources [V, 3, H, W]; `output` must carry intermediateSourceRenders (keepIntermediates)
/// for the intermediate terms (terms without a render are skipped). `vgg` may be null or
/// unloaded: then the perceptual term is skipped. The depth term is computed when
/// novelInverseDepth [N, 1, H, W] is given (with novelDepth, the rendered depth [N, 1, H, W]);
/// the mpi_depth term when `planes` is given (targets of output.level0SourceWeights).
LossTerms computeLosses(const TrainingConfig& config, const generator::GeneratorOutput& output,
                        const ocl::Tensor& novelColour, const ocl::Tensor& novelOpacity,
                        const ocl::Tensor& novelTargets, const ocl::Tensor& cleanSources,
                        const Vgg19Features* vgg, const ocl::Tensor& novelDepth = {},
                        const ocl::Tensor& novelInverseDepth = {},
                        const PlaneTargets* planes = nullptr);

} // namespace simpli::training

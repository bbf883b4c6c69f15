#pragma once
// Training losses of the reference (§8.1) and two generic ones. Each returns a one-element
// tensor (shape [1]) and is differentiable with respect to every input. Inputs must have the
// same dtype; shape mismatches throw naming the loss and the shapes.
#include "simpli/ocl/tensor.h"

#include <vector>

namespace simpli::ocl {

/// mean |a - b| over all elements (a, b of equal shape). The gradient of |0| is 0.
Tensor l1Loss(const Tensor& a, const Tensor& b);
/// mean (a - b)^2 over all elements (a, b of equal shape).
Tensor mseLoss(const Tensor& a, const Tensor& b);

/// The reference's masked L1: pred and target [N, C, H, W], mask [N, 1, H, W] (shared by all
/// channels) or [N, C, H, W]. Per image n and channel c:
///   S = sum_hw |pred - target| * mask,  Z = sum_hw mask + 1e-6,  loss_nc = S / Z,
/// and the result is the mean of loss_nc over n and c. Differentiable in all three inputs.
Tensor maskedL1(const Tensor& pred, const Tensor& target, const Tensor& mask);

/// Total variation of x [..., H, W]: mean |x[i+1, j] - x[i, j]| + mean |x[i, j+1] - x[i, j]|,
/// each mean over all images (leading dims) and pairs. A direction of size 1 has no pairs and
/// contributes 0.
Tensor totalVariation(const Tensor& x);

/// The reference's `smooth_layers` loss on depths D [B, L, H, W]:
///   sqrt(sum (D[i+1, j] - D[i, j])^2 + sum (D[i, j+1] - D[i, j])^2 + 1e-6) / (B * L * H * W),
/// one global L2 norm of the depth gradients.
Tensor smoothLayersLoss(const Tensor& depth);

/// The window and constants of SSIM (Wang et al. 2004): an n x n Gaussian window, and
/// C1 = (k1 L)^2, C2 = (k2 L)^2 for data range L.
struct SsimOptions {
  int windowSize = 11;    ///< odd, >= 1
  double sigma = 1.5;     ///< Gaussian window standard deviation in pixels, > 0
  double dataRange = 1.0; ///< L, the dynamic range of the values
  double k1 = 0.01;       ///< C1 = (k1 L)^2
  double k2 = 0.03;       ///< C2 = (k2 L)^2
};

/// 1 - SSIM of a and b [N, C, H, W] (not in the reference): the SSIM map over the valid windows
/// (no padding; H and W at least the window) of every image and channel, averaged, as the
/// evaluation metric computes it (metrics/image_quality.h). Differentiable in both inputs.
Tensor ssimLoss(const Tensor& a, const Tensor& b, const SsimOptions& options = {});

/// The normalised 1-D Gaussian window of SSIM: `size` taps (odd, >= 1) of exp(-d^2 / 2 sigma^2)
/// about the centre, summing to 1. The separable 2-D window is its outer product; the metric
/// (metrics/image_quality.h) uses the same taps, so loss and metric cannot drift apart.
std::vector<double> ssimWindow(int size, double sigma);

} // namespace simpli::ocl

#pragma once
// Image-quality metrics of the paper's evaluation protocol (WACV 2023, "Metrics"): PSNR and SSIM
// between a rendered view and the held-out photo, on a central crop that keeps 90 % of the
// image area (MPI/MLI methods cannot fill the border outside the reference frustum).
//
// Conventions:
// - Images are interleaved H x W x C floats with values in [0, 1] (MetricImage). Network images
//   (io/image.h: planar, [-1, 1]) convert with metricImageFromImage. Values are not clamped: what
//   is passed is compared.
// - PSNR = 10 log10(peak^2 / MSE), MSE over all pixels and channels; +infinity for identical
//   images.
// - SSIM is Wang et al. 2004 (IEEE TIP, "Image quality assessment: from error visibility to
//   structural similarity"), as in their reference ssim_index.m: an 11 x 11 Gaussian window
//   with sigma 1.5 (normalised to sum 1), weighted local means, variances and covariance
//   (E[x^2] - mu^2, no sample correction), C1 = (K1 L)^2, C2 = (K2 L)^2 with K1 = 0.01,
//   K2 = 0.03, L = 1, the SSIM map over the "valid" positions only (the window never leaves the
//   image, no padding) and its mean; no automatic down-sampling. Colour images: the mean of the
//   per-channel SSIMs.
// - Crop: each side loses round(size (1 - sqrt(0.9)) / 2) pixels, per axis, so width and height
//   shrink by the same factor sqrt(0.9) and the kept area is 90 % (up to rounding).
// All functions compute in double and throw simpli::Error (naming the function, the sizes or
// the value at fault) on mismatched or malformed input.
#include <limits>
#include <vector>

#include "simpli/ocl/ops_loss.h"

#include "simpli/model/io/image.h"

namespace simpli::metrics {

struct MetricImage {
  int width = 0, height = 0, channels = 0;
  std::vector<float> data; ///< height x width x channels, row-major, interleaved

  MetricImage() = default;
  /// Zero-filled; throws simpli::Error for negative sizes or channels < 1.
  MetricImage(int width, int height, int channels);

  float& at(int y, int x, int c) {
    return data[(static_cast<std::size_t>(y) * width + x) * channels + c];
  }
  float at(int y, int x, int c) const {
    return data[(static_cast<std::size_t>(y) * width + x) * channels + c];
  }
};

/// A network image (planar RGB in [-1, 1]) as a metric image: v -> (v + 1) / 2.
MetricImage metricImageFromImage(const io::Image& image);

/// A rectangle of pixels: columns x .. x + width - 1, rows y .. y + height - 1.
struct CropWindow {
  int x = 0, y = 0, width = 0, height = 0;
};

/// The paper's central crop of a width x height image keeping `keptArea` of the area (default
/// 0.9): margin round(size (1 - sqrt(keptArea)) / 2) on each side of each axis. keptArea must
/// be in (0, 1]; throws if the crop would be empty.
CropWindow centralCrop(int width, int height, double keptArea = 0.9);

/// The pixels of `image` inside `window` (which must lie inside the image).
MetricImage cropImage(const MetricImage& image, const CropWindow& window);

/// Mean of (a - b)^2 over all pixels and channels.
double meanSquaredError(const MetricImage& a, const MetricImage& b);

/// 10 log10(peak^2 / MSE); +infinity when the images are identical.
double psnr(const MetricImage& a, const MetricImage& b, double peak = 1.0);

/// The window and constants of SSIM: the engine's, which the training term (ocl::ssimLoss) uses
/// too, so the loss and the reported metric are one definition.
using SSIMOptions = ocl::SsimOptions;

/// Mean SSIM (see the header comment). Both images need at least windowSize pixels in each
/// direction.
double ssim(const MetricImage& a, const MetricImage& b, const SSIMOptions& options = {});

struct ImageQuality {
  double psnr = 0.0;
  double ssim = 0.0;
};

/// The paper's protocol for one view: crop both images with centralCrop(keptArea), then PSNR
/// and SSIM (default options) on [0, 1] data.
ImageQuality evaluateImageQuality(const MetricImage& rendered, const MetricImage& truth,
                                  double keptArea = 0.9);

struct MeanStd {
  double mean = std::numeric_limits<double>::quiet_NaN();
  double std = std::numeric_limits<double>::quiet_NaN();
};

/// Mean and population standard deviation (divide by n, as numpy.std), the "mean_std" of the
/// paper's tables. NaN for an empty list; an infinite value (a PSNR of identical images) makes
/// the mean infinite and the standard deviation NaN.
MeanStd meanAndStd(const std::vector<double>& values);

} // namespace simpli::metrics

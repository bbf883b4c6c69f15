#pragma once
// `--layers auto` (simpli infer, simpli bench trade): the smallest MLI whose quality on the
// source views stays within a margin of the full one's. Every layer costs the same bytes in
// either MLI form (mli/files.h), so "smallest" is "fewest layers".
//
// Search: backward elimination. Starting from every layer, each round tries leaving out each
// remaining layer, renders the rest into every source view (raster::renderMLI, straight RGBA,
// the farthest fragment opaque) and scores it with PSNR on the paper's central crop
// (metrics::evaluateImageQuality, mean over the views); the layer whose removal costs least is
// dropped when the result is still within maxLossDb of the full MLI's PSNR, else the search
// stops. L layers take at most L (L + 1) / 2 renders per view. The source views are what the
// network saw, so this measures what leaving a layer out loses of the input, not of novel views
// (which a layer that only fills disocclusions may still help).
#include "simpli/model/io/image.h"
#include "simpli/model/metrics/image_quality.h"
#include "simpli/model/mli/mli.h"
#include "simpli/model/raster/rasterizer.h"
#include "simpli/model/scene/camera.h"

#include <vector>

namespace simpli::generator {

struct LayerChoiceOptions {
  double maxLossDb = 0.2; ///< largest PSNR loss against the full MLI (dB, >= 0)
  double keptArea = 0.9;  ///< the central crop scored
  raster::RasterSettings raster;
};

struct LayerChoice {
  std::vector<int> kept; ///< indices of the input's layers kept, farthest first
  mli::MLI mli;          ///< those layers (camera unchanged)
  double fullPsnr = 0;   ///< mean PSNR over the views with every layer (dB)
  double chosenPsnr = 0; ///< with the kept layers
  int renders = 0;       ///< layer subsets rendered (for reports)
};

/// The choice for `mli` seen by `cameras` (any size; each is rendered at its own width x
/// height) against `images` (the photos of those views, io::Image planar RGB in [-1, 1], of the
/// cameras' sizes). Throws simpli::Error for mismatched counts or sizes, no views, or a
/// negative margin.
LayerChoice chooseLayers(const mli::MLI& mli, const std::vector<scene::Camera>& cameras,
                         const std::vector<io::Image>& images,
                         const LayerChoiceOptions& options = {});

/// Mean PSNR / SSIM (central crop) of `mli` rendered into `cameras` against `images` (as
/// chooseLayers scores).
metrics::ImageQuality meanQualityOfMLI(const mli::MLI& mli,
                                       const std::vector<scene::Camera>& cameras,
                                       const std::vector<io::Image>& images, double keptArea = 0.9,
                                       const raster::RasterSettings& raster = {});

/// A rendered colour [3, H, W] in [0, 1] (raster::renderMLI's) as a metric image.
metrics::MetricImage metricImageFromColour(const ocl::Tensor& colour);

} // namespace simpli::generator

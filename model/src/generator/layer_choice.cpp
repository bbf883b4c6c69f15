// `--layers auto`: the fewest layers within a PSNR margin on the source views
// (generator/layer_choice.h).
#include "simpli/model/generator/layer_choice.h"

#include "simpli/error.h"
#include "simpli/model/raster/render_mli.h"
#include "simpli/ocl/autograd.h"

#include <cmath>
#include <cstddef>
#include <limits>

namespace simpli::generator {

metrics::MetricImage metricImageFromColour(const ocl::Tensor& colour) {
  if (colour.dim() != 3 || colour.size(0) != 3)
    fail("metricImageFromColour: colour ", colour.describe(), " is not [3, H, W]");
  const int H = static_cast<int>(colour.size(1)), W = static_cast<int>(colour.size(2));
  const std::vector<float> v = colour.toVectorF32();
  metrics::MetricImage m(W, H, 3);
  const std::size_t n = static_cast<std::size_t>(H) * W;
  for (std::size_t p = 0; p < n; ++p)
    for (std::size_t c = 0; c < 3; ++c)
      m.data[3 * p + c] = v[c * n + p];
  return m;
}

metrics::ImageQuality meanQualityOfMLI(const mli::MLI& mli,
                                       const std::vector<scene::Camera>& cameras,
                                       const std::vector<io::Image>& images, double keptArea,
                                       const raster::RasterSettings& raster) {
  if (cameras.empty() || cameras.size() != images.size())
    fail("meanQualityOfMLI: ", cameras.size(), " cameras and ", images.size(),
         " images; need the same number, at least 1");
  ocl::NoGradGuard noGrad;
  const raster::MLITensors t = raster::mliTensors(mli);
  metrics::ImageQuality mean;
  for (std::size_t v = 0; v < cameras.size(); ++v) {
    if (images[v].width != cameras[v].width || images[v].height != cameras[v].height)
      fail("meanQualityOfMLI: view ", v, ": image ", images[v].width, " x ", images[v].height,
           " but camera ", cameras[v].width, " x ", cameras[v].height);
    const raster::RenderedLayers r =
        raster::renderLayers(t.depth, t.rgba, mli.camera, cameras[v], raster);
    const metrics::ImageQuality q = metrics::evaluateImageQuality(
        metricImageFromColour(r.colour), metrics::metricImageFromImage(images[v]), keptArea);
    mean.psnr += q.psnr / static_cast<double>(cameras.size());
    mean.ssim += q.ssim / static_cast<double>(cameras.size());
  }
  return mean;
}

LayerChoice chooseLayers(const mli::MLI& mli, const std::vector<scene::Camera>& cameras,
                         const std::vector<io::Image>& images, const LayerChoiceOptions& o) {
  if (!(o.maxLossDb >= 0) || !std::isfinite(o.maxLossDb))
    fail("chooseLayers: the PSNR margin ", o.maxLossDb, " dB must be finite and >= 0");
  mli::validateMLI(mli, "chooseLayers");
  auto subset = [&](const std::vector<int>& kept) {
    mli::MLI m;
    m.camera = mli.camera;
    for (int k : kept)
      m.layers.push_back(mli.layers[static_cast<std::size_t>(k)]);
    return m;
  };
  LayerChoice choice;
  for (int k = 0; k < mli.numLayers(); ++k)
    choice.kept.push_back(k);
  choice.fullPsnr = meanQualityOfMLI(mli, cameras, images, o.keptArea, o.raster).psnr;
  choice.chosenPsnr = choice.fullPsnr;
  choice.renders = 1;
  while (choice.kept.size() > 1) {
    double best = -std::numeric_limits<double>::infinity();
    std::size_t bestIndex = 0;
    for (std::size_t i = 0; i < choice.kept.size(); ++i) {
      std::vector<int> without = choice.kept;
      without.erase(without.begin() + static_cast<std::ptrdiff_t>(i));
      const double p =
          meanQualityOfMLI(subset(without), cameras, images, o.keptArea, o.raster).psnr;
      ++choice.renders;
      if (p > best) {
        best = p;
        bestIndex = i;
      }
    }
    // An infinite full PSNR (the views reproduced exactly) keeps what reproduces them exactly.
    if (!(best >= choice.fullPsnr - o.maxLossDb))
      break;
    choice.kept.erase(choice.kept.begin() + static_cast<std::ptrdiff_t>(bestIndex));
    choice.chosenPsnr = best;
  }
  choice.mli = subset(choice.kept);
  return choice;
}

} // namespace simpli::generator

// The reference's training losses (training/losses.h).
#include "simpli/model/training/losses.h"

#include "simpli/error.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_loss.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace simpli::training {

double LossTerms::value(const std::string& name) const {
  for (const auto& [n, t] : terms)
    if (n == name)
      return t.item();
  return std::numeric_limits<double>::quiet_NaN();
}

ocl::Tensor resizeNearest(const ocl::Tensor& x, int64_t outH, int64_t outW) {
  if (x.dim() < 2 || outH < 1 || outW < 1)
    fail("resizeNearest: input ", x.describe(), " to ", outH, "x", outW);
  const int64_t H = x.size(-2), W = x.size(-1);
  std::vector<int64_t> rows(static_cast<size_t>(outH)), cols(static_cast<size_t>(outW));
  // PyTorch's legacy 'nearest': src = floor(dst * (in / out)), clamped (computed in integers).
  for (int64_t i = 0; i < outH; ++i)
    rows[size_t(i)] = std::min(i * H / outH, H - 1);
  for (int64_t j = 0; j < outW; ++j)
    cols[size_t(j)] = std::min(j * W / outW, W - 1);
  return ocl::indexSelect(ocl::indexSelect(x, x.dim() - 2, rows), x.dim() - 1, cols);
}

ocl::Tensor depthLoss(const ocl::Tensor& renderedDepth, const ocl::Tensor& renderedOpacity,
                      const ocl::Tensor& inverseDepth) {
  if (renderedDepth.shape() != inverseDepth.shape() ||
      renderedOpacity.shape() != inverseDepth.shape())
    fail("depthLoss: rendered depth ", renderedDepth.describe(), ", opacity ",
         renderedOpacity.describe(), " and inverse depth ", inverseDepth.describe(),
         " must have one shape");
  // Pixels with a surface: inverse depth > 0 (counted on the host: the mask is data).
  const std::vector<double> inv = inverseDepth.toVector();
  const double known =
      double(std::count_if(inv.begin(), inv.end(), [](double v) { return v > 0; }));
  if (known == 0)
    return ocl::Tensor::zeros({1}, renderedDepth.dtype());
  constexpr double eps = 1e-6; // keeps log finite where nothing is rendered (D = A = 0)
  // log z = -log(1 / z); pixels without a surface get log z = 0 here and drop out below.
  const std::vector<double>& invHost = inv;
  std::vector<double> logZ(invHost.size(), 0.0);
  for (size_t k = 0; k < invHost.size(); ++k)
    if (invHost[k] > 0)
      logZ[k] = -std::log(invHost[k]);
  const ocl::Tensor logDepth = ocl::sub(ocl::log(ocl::addScalar(renderedDepth, eps)),
                                        ocl::log(ocl::addScalar(renderedOpacity, eps)));
  const ocl::Tensor error = ocl::abs(
      ocl::sub(logDepth, ocl::Tensor::fromHost(logZ, inverseDepth.shape(), inverseDepth.dtype())));
  std::vector<double> mask(invHost.size());
  for (size_t k = 0; k < invHost.size(); ++k)
    mask[k] = invHost[k] > 0 ? 1.0 : 0.0;
  const ocl::Tensor weighted =
      ocl::mul(ocl::mul(error, renderedOpacity),
               ocl::Tensor::fromHost(mask, inverseDepth.shape(), inverseDepth.dtype()));
  return ocl::mulScalar(ocl::sumAll(weighted), 1.0 / known); // [1]
}

ocl::Tensor ssimLossOfSignedImages(const ocl::Tensor& rendered, const ocl::Tensor& target) {
  // Images are in [-1, 1]; the metric's SSIM reads [0, 1] (its luminance term is not
  // shift-invariant), so map them there first.
  auto toUnit = [](const ocl::Tensor& x) { return ocl::mulScalar(ocl::addScalar(x, 1.0), 0.5); };
  // The default options are the metric's (metrics::SSIMOptions is ocl::SsimOptions).
  return ocl::ssimLoss(toUnit(rendered), toUnit(target));
}

LossTerms computeLosses(const TrainingConfig& config, const generator::GeneratorOutput& output,
                        const ocl::Tensor& novelColour, const ocl::Tensor& novelOpacity,
                        const ocl::Tensor& novelTargets, const ocl::Tensor& cleanSources,
                        const Vgg19Features* vgg, const ocl::Tensor& novelDepth,
                        const ocl::Tensor& novelInverseDepth, const PlaneTargets* planes) {
  LossTerms out;
  auto addTerm = [&](const std::string& name, const ocl::Tensor& t) {
    out.terms.emplace_back(name, t);
    const double w = config.weight(name);
    if (w > 0) {
      const ocl::Tensor weighted = ocl::mulScalar(t, w);
      out.total = out.total.defined() ? ocl::add(out.total, weighted) : weighted;
    }
  };
  addTerm("l1", ocl::maskedL1(novelColour, novelTargets, novelOpacity));
  if (vgg && vgg->loaded() && config.weight("perceptual") > 0)
    addTerm("perceptual", perceptualLoss(*vgg, novelColour, novelTargets, novelOpacity));
  const std::vector<ocl::Tensor>& renders = output.intermediateSourceRenders;
  for (size_t k = 0; k < renders.size() && k < 4; ++k) {
    const ocl::Tensor& r = renders[k];
    if (r.dim() != 4 || r.size(0) != cleanSources.size(0) || r.size(1) != 3)
      fail("computeLosses: intermediate render ", k, " ", r.describe(),
           " does not fit the sources ", cleanSources.describe());
    const ocl::Tensor target =
        r.size(2) == cleanSources.size(2) && r.size(3) == cleanSources.size(3)
            ? cleanSources
            : resizeNearest(cleanSources, r.size(2), r.size(3));
    addTerm("intermediate_loss_" + std::to_string(k) + "_l1", ocl::l1Loss(r, target));
  }
  const ocl::Tensor& D = output.depth;
  addTerm("smooth_layers", ocl::smoothLayersLoss(ocl::unsqueeze(D, 0)));
  if (novelInverseDepth.defined())
    addTerm("depth", depthLoss(novelDepth, novelOpacity, novelInverseDepth));
  if (planes) {
    if (!output.level0SourceWeights.defined())
      fail("computeLosses: the mpi_depth term needs the level-0 render's weights "
           "(keepIntermediates)");
    addTerm("mpi_depth", planeCrossEntropy(output.level0SourceWeights, *planes));
  }
  if (config.weight("ssim") > 0)
    addTerm("ssim", ssimLossOfSignedImages(novelColour, novelTargets));
  // Keep lossTermNames() order in the list (perceptual may be missing; order is preserved).
  if (!out.total.defined())
    out.total = ocl::Tensor::zeros({1}, novelColour.dtype());
  return out;
}

} // namespace simpli::training

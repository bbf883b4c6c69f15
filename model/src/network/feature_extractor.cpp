// The feature extractor (reference §4.2).
#include "simpli/model/network/feature_extractor.h"

#include "simpli/error.h"

#include "simpli/ocl/ops_pool.h"
#include "simpli/ocl/ops_resample.h"
#include "simpli/ocl/ops_shape.h"

namespace simpli::network {

FeatureExtractor::FeatureExtractor(ParameterStore& store, const std::string& prefix,
                                   const FeatureExtractorConfig& config)
    : inChannels_(config.inChannels), descriptors_(config.descriptors) {
  if (config.widths.size() != 4)
    fail("FeatureExtractor ", prefix, ": ", config.widths.size(), " widths, expected 4");
  ConvBlock::Options o3;
  o3.kernel = 3;
  o3.padding = ocl::PaddingMode::Zeros;
  o3.norm = true;
  o3.activation = Activation::Elu;
  ConvBlock::Options o1 = o3;
  o1.kernel = 1;
  const std::vector<int>& w = config.widths;
  const std::string p = prefix + ".";
  conv1a_ = ConvBlock(store, p + "conv1a", config.inChannels, w[0], o3);
  conv1b_ = ConvBlock(store, p + "conv1b", w[0], w[0], o3);
  conv2a_ = ConvBlock(store, p + "conv2a", w[0], w[1], o3);
  conv2b_ = ConvBlock(store, p + "conv2b", w[1], w[1], o3);
  conv3a_ = ConvBlock(store, p + "conv3a", w[1], w[2], o3);
  conv3b_ = ConvBlock(store, p + "conv3b", w[2], w[2], o3);
  conv4a_ = ConvBlock(store, p + "conv4a", w[2], w[3], o3);
  conv4b_ = ConvBlock(store, p + "conv4b", w[3], w[3], o3);
  // The skip x1 is the pooled conv1b output (w[0] channels), then x2 (w[1]), x3 (w[2]), x4 (w[3]).
  convDa_ = ConvBlock(store, p + "convDa", w[0] + w[1] + w[2] + w[3], config.headWidth, o3);
  convDb_ = ConvBlock(store, p + "convDb", config.headWidth, config.descriptors, o1);
}

ocl::Tensor FeatureExtractor::forward(const ocl::Tensor& images) const {
  if (!images.defined() || images.dim() != 4 || images.size(1) != inChannels_)
    fail("FeatureExtractor: images ", images.defined() ? images.describe() : "undefined",
         " must be [V, ", inChannels_, ", H, W]");
  const int64_t H = images.size(2), W = images.size(3);
  // Three 2x2 max-pools and x2 / x4 upsampling back to H/2 need H, W divisible by 8 (§1.5).
  if (H % 8 != 0 || W % 8 != 0 || H == 0 || W == 0)
    fail("FeatureExtractor: image size ", H, "x", W, " (", images.describe(),
         ") must be a positive multiple of 8 in both dimensions");
  const int64_t h = H / 2, w = W / 2;
  const ocl::Tensor x1 = ocl::maxPool2d(conv1b_.forward(conv1a_.forward(images)), 2, 2);
  const ocl::Tensor x2 = conv2b_.forward(conv2a_.forward(x1));
  ocl::Tensor x3 = conv3b_.forward(conv3a_.forward(ocl::maxPool2d(x2, 2, 2)));
  ocl::Tensor x4 = conv4b_.forward(conv4a_.forward(ocl::maxPool2d(x3, 2, 2)));
  x3 = ocl::resizeBilinear(x3, h, w);
  x4 = ocl::resizeBilinear(x4, h, w);
  const ocl::Tensor merged = ocl::concat({x1, x2, x3, x4}, 1);
  const ocl::Tensor descriptors = convDb_.forward(convDa_.forward(merged));
  // Bilinear x0.5 with align_corners = False on even sizes is exactly the 2x2 box mean.
  return ocl::concat({descriptors, ocl::resizeBilinear(images, h, w)}, 1);
}

} // namespace simpli::network

#pragma once
// SuperPointsFeatExtractor (`features_extractor`, spec §4.2): a SuperPoint-like
// encoder with LayerNormTotal + ELU after every convolution (zero padding), whose multi-scale
// maps are merged at half resolution; the output appends the 2x2-box-downsampled input image.
#include "simpli/model/network/config.h"
#include "simpli/model/network/layers.h"

#include "simpli/ocl/tensor.h"

namespace simpli::network {

class FeatureExtractor {
public:
  FeatureExtractor() = default;
  FeatureExtractor(ParameterStore& store, const std::string& prefix,
                   const FeatureExtractorConfig& config);

  /// images [V, 3, H, W] (RGB in [-1, 1], H and W multiples of 8) ->
  /// [V, descriptors + 3, H/2, W/2] = [descriptors | bilinear x0.5 (box mean) of the image].
  /// Every view is normalised on its own (LayerNormTotal per sample).
  ocl::Tensor forward(const ocl::Tensor& images) const;
  int outChannels() const { return descriptors_ + inChannels_; }

private:
  int inChannels_ = 3, descriptors_ = 9;
  ConvBlock conv1a_, conv1b_, conv2a_, conv2b_, conv3a_, conv3b_, conv4a_, conv4b_, convDa_,
      convDb_;
};

} // namespace simpli::network

#pragma once
// Function-preserving widening of a trained network (Net2WiderNet, Chen et al. 2016): every
// internal width of the config is multiplied by an integer factor and the weights are mapped so
// that the wider network computes what the narrower one does. A network trained to a plateau
// can then grow capacity without starting again from random weights.
//
// Widened: the feature extractor's conv widths and head, the [inner, out] widths of every
// post-aggregation block (the last block's output stays), the decoders' hidden widths.
// Unchanged (interfaces between modules and inputs the config fixes): descriptors, state and
// output channels, view-attention width, the planes deformer, planes and layers.
//
// How the function is kept: each widened channel c gets `factor` copies (channel c + k C of the
// new layer is copy k of c); a layer reading copies divides the old weight among them. Every
// normalisation is LayerNormTotal, global per sample, so copies keep its mean and variance
// (up to the unbiased estimator: relative 1 / (4 N) for N normalised elements, < 1e-4 here).
// Copies with identical weights would get identical gradients forever; the readers' shares are
// perturbed by +-noise (summing to zero over the copies of a channel, so the function stays).
#include "simpli/model/network/network.h"

#include <cstdint>
#include <memory>
#include <string>

namespace simpli::network {

struct WidenOptions {
  int factor = 2;      ///< every internal width x factor, 2..8
  double noise = 0.01; ///< perturbation of the copies' shares, x the weight tensor's RMS, >= 0
  uint64_t seed = 0;   ///< draws the perturbation
};

/// Throws simpli::Error naming the field unless 2 <= factor <= 8 and noise is finite and >= 0.
void checkWidenOptions(const WidenOptions& options);

/// `config` with every internal width (above) multiplied by `factor`; the name gets "-x<factor>".
/// Throws simpli::Error unless 2 <= factor <= 8.
NetworkConfig widenedConfig(const NetworkConfig& config, int factor);

/// A network of widenedConfig(from.config(), factor) in from's dtype computing the same function
/// as `from`. Throws simpli::Error naming the field for bad options, and naming the block when a
/// residual 1x1 convolution would become an identity (a block whose fixed input width equals its
/// widened output: the widening cannot keep that block's function).
std::unique_ptr<SimpliNetwork> widenNetwork(const SimpliNetwork& from, const WidenOptions& options);

/// Loads into `net` (config with lvl0_photo_prior) the weights of the same config without it:
/// every parameter as stored, and the level-0 block's convolutions that read its input get a
/// zero weight on the prior channel, so the network computes what the file's network does.
/// Throws simpli::Error when net's config has no prior, or for what ParameterStore::load
/// rejects in the file (naming it).
LoadReport loadWithoutLvl0Prior(SimpliNetwork& net, const std::string& path);

} // namespace simpli::network

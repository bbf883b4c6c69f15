// SimpliNetwork: every module of a config, registered under the reference's names.
#include "simpli/model/network/network.h"

#include "simpli/error.h"

namespace simpli::network {

std::vector<BlockDims> postAggregateDims(const TBlockConfig& config) {
  std::vector<BlockDims> dims = config.blocks;
  const int lastOut = dims.empty() ? config.outChannels : dims.back().out;
  dims.push_back({lastOut, config.outChannels});
  return dims;
}

TBlock::TBlock(ParameterStore& store, const std::string& prefix, int spatialDims,
               int stateChannels_, int sourceChannels_, const TBlockConfig& config,
               int extraChannels_)
    : stateChannels(stateChannels_), sourceChannels(sourceChannels_),
      extraChannels(extraChannels_) {
  const bool withAttention = config.attentionHidden > 0;
  // [state | mean | var] or [state | mean | var | attended mean | attended var] (§4.7 step 8),
  // then any extra inputs.
  inChannels = stateChannels + (withAttention ? 4 : 2) * sourceChannels + extraChannels;
  postAggregate = DoubleConvResnet(store, prefix + ".post_aggregate_block", spatialDims, inChannels,
                                   postAggregateDims(config));
  if (withAttention)
    attention =
        ViewAttention(store, prefix + ".attention_agg", sourceChannels, config.attentionHidden);
}

SimpliNetwork::SimpliNetwork(const NetworkConfig& config, ocl::Dtype dtype, uint64_t seed)
    : config_(config), store_(std::make_unique<ParameterStore>(dtype, seed)) {
  config_.validate(config_.name.empty() ? "network config" : config_.name);
  ParameterStore& s = *store_;
  const int features = config_.featureChannels();
  const int surface = config_.surfaceChannels();

  sampiLvl0 = TBlock(s, "sampi_block_lvl0", 3, config_.sampiLvl0.stateChannels, features,
                     config_.sampiLvl0, config_.lvl0PhotoPrior ? 1 : 0);
  alphaDecoderLvl0 =
      ConvMLP(s, "alpha_decoder_lvl0", config_.sampiLvl0.outChannels, config_.alphaDecoder, 1);
  // Level-1 state: fMPI0 = level-0 features + alpha; sources: the 12-channel discrepancy.
  sampiLvl1 = TBlock(s, "sampi_block_lvl1", 2, config_.sampiLvl0.outChannels + 1, features,
                     config_.sampiLvl1);
  if (!config_.mpiOnly) {
    planesDeformer = AnchoredRayAttention(s, "planes_deformer_lvl1", surface, config_.numLayers,
                                          config_.deformerHeads, config_.deformerHeadDim);
    depthDecoder =
        ConvMLP(s, "depth_decoder_lvl1", surface, config_.depthDecoder, config_.groupSize());
  }
  rgbaDecoders.emplace_back(s, "rgba_decoder_lvl1", surface, config_.rgbaDecoder, 4);
  for (int i = 0; i < config_.mliCorrections(); ++i) {
    const std::string level = std::to_string(i + 2);
    // State: fMLI0 (bicubic-resized) at level 2, then the previous level's output.
    samliBlocks.emplace_back(s, "samli_block_lvl" + level, 2, surface, config_.mliSourceChannels(),
                             config_.samliBlocks[i]);
    rgbaDecoders.emplace_back(s, "rgba_decoder_lvl" + level, config_.samliBlocks[i].outChannels,
                              config_.rgbaDecoder, 4);
  }
  featuresExtractor = FeatureExtractor(s, "features_extractor", config_.featuresExtractor);
}

} // namespace simpli::network

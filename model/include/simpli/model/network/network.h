#pragma once
// All modules of a SIMPLI network, built from a NetworkConfig into one ParameterStore with the
// reference's state-dict names (spec §2, §5). This is the parameter side of the
// generator: the geometric steps (plane sweep, MPI rendering, mesh rendering) that connect the
// modules live in model/geometry and the generator.
#include "simpli/model/network/attention.h"
#include "simpli/model/network/config.h"
#include "simpli/model/network/feature_extractor.h"
#include "simpli/model/network/layers.h"
#include "simpli/model/network/parameter_store.h"

#include <memory>
#include <optional>
#include <vector>

namespace simpli::network {

/// The [inner, out] widths of a TBlock's post-aggregation stack: config.blocks and the final
/// [last out -> last out -> out_channels] block the TBlock appends (§4.3).
std::vector<BlockDims> postAggregateDims(const TBlockConfig& config);

/// An aggregation module (the reference's TBlock, §4.7): the post-aggregation stack
/// (<prefix>.post_aggregate_block, with the final [last out -> out] block appended) and, for
/// the MLI levels, the view self-attention (<prefix>.attention_agg).
struct TBlock {
  DoubleConvResnet postAggregate;
  std::optional<ViewAttention> attention;
  int stateChannels = 0;  ///< channels of the surfaces' state
  int sourceChannels = 0; ///< per-view channels that are aggregated
  int extraChannels = 0;  ///< inputs after the aggregates (the level-0 photo prior: 1)
  int inChannels = 0;     ///< post-aggregation input: state + 2 (or 4 with attention) x source
                          ///< + extra

  TBlock() = default;
  TBlock(ParameterStore& store, const std::string& prefix, int spatialDims, int stateChannels,
         int sourceChannels, const TBlockConfig& config, int extraChannels = 0);
};

class SimpliNetwork {
public:
  /// Builds every module of `config` with parameters in `dtype`, initialised with `seed`.
  explicit SimpliNetwork(const NetworkConfig& config, ocl::Dtype dtype = ocl::Dtype::F32,
                         uint64_t seed = 0);
  SimpliNetwork(const SimpliNetwork&) = delete;
  SimpliNetwork& operator=(const SimpliNetwork&) = delete;

  const NetworkConfig& config() const { return config_; }
  ParameterStore& parameters() { return *store_; }
  const ParameterStore& parameters() const { return *store_; }

  FeatureExtractor featuresExtractor;                 ///< features_extractor
  TBlock sampiLvl0;                                   ///< sampi_block_lvl0 (3-D)
  ConvMLP alphaDecoderLvl0;                           ///< alpha_decoder_lvl0
  TBlock sampiLvl1;                                   ///< sampi_block_lvl1
  std::optional<AnchoredRayAttention> planesDeformer; ///< planes_deformer_lvl1 (not MPI-only)
  std::optional<ConvMLP> depthDecoder;                ///< depth_decoder_lvl1 (not MPI-only)
  std::vector<ConvMLP> rgbaDecoders;                  ///< rgba_decoder_lvl1 .. lvl(1 + corrections)
  std::vector<TBlock> samliBlocks;                    ///< samli_block_lvl2 .. lvl(1 + corrections)

private:
  NetworkConfig config_;
  std::unique_ptr<ParameterStore> store_;
};

} // namespace simpli::network

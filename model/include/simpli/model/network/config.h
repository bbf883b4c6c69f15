#pragma once
// The architecture of a SIMPLI network, read from JSON (model/configs/*.json). The configs
// "official-4l" and "official-8l" reproduce the reference's tblock4.yaml / tblock8.yaml
// exactly (spec §2, §4, §5: 1,879,343 and 1,879,362 parameters, identical
// state-dict keys and shapes); smaller configs trade quality for CPU training speed.
//
// JSON layout (every key is required unless marked optional; unknown keys are errors, so a
// typo cannot silently fall back to a default):
// {
//   "name": "official-4l",
//   "num_layers": 4, "num_planes": 41, "min_depth": 1, "max_depth": 100,
//   "scale_feat_extractor": 1, "scale_lvl0": 0.25, "scale_lvl1": 0.5, "scale_lvl2": 1,
//   "mpi_only": false,                  // DeepView-dagger baseline: no planes -> layers step
//   "lvl0_tanh_planes": 3,              // the reference's tanh quirk (§3 step 8); 0 = off
//   "mli_error_with_image": true,       // MLI aggregators see [error | image] (6 ch) or error
//   "lvl0_photo_prior": false,          // optional, not in the reference: level 0 also sees
//                                       // the plane-sweep stereo distribution (below)
//   "features_extractor": {"widths": [64, 64, 128, 128], "head_width": 256, "descriptors": 9},
//   "sampi_block_lvl0": {"state_channels": 12, "blocks": [[32, 32], ...], "out_channels": 12},
//   "alpha_decoder_lvl0": {"hidden": [12, 12], "activation": "elu"},
//   "sampi_block_lvl1": {"blocks": [[32, 32], [32, 16]], "out_channels": 16},
//   "planes_deformer_lvl1": {"heads": 2, "head_dim": 10},          // optional if mpi_only
//   "depth_decoder_lvl1": {"hidden": [16, 8], "activation": "relu"}, // optional if mpi_only
//   "rgba_decoder": {"hidden": [16, 8], "activation": "relu"},
//   "samli_blocks": [{"blocks": [[32, 32], [16, 16]], "out_channels": 16,
//                     "attention_hidden": 16}, ...]      // one per MLI correction step
// }
// "blocks" lists [inner, out] per DoubleConv block; the stack always ends with the block
// [last out -> last out -> out_channels] that the reference's TBlock appends.
#include <string>
#include <vector>

namespace simpli::network {

enum class Activation { None, Relu, Elu };

/// "none" | "relu" | "elu"; throws simpli::Error naming `what` otherwise.
Activation parseActivation(const std::string& text, const std::string& what);
const char* toString(Activation activation);

struct FeatureExtractorConfig {
  int inChannels = 3;                        ///< RGB (fixed)
  std::vector<int> widths{64, 64, 128, 128}; ///< conv1..conv4 channels (4 entries)
  int headWidth = 256;                       ///< convDa
  int descriptors = 9;                       ///< convDb; the output adds inChannels RGB channels
};

/// One DoubleConv block of a post-aggregation stack.
struct BlockDims {
  int inner = 0;
  int out = 0;
  bool operator==(const BlockDims& o) const { return inner == o.inner && out == o.out; }
};

/// An aggregation module (the reference's TBlock): its post-aggregation stack and, for the MLI
/// levels, the view self-attention.
struct TBlockConfig {
  std::vector<BlockDims> blocks; ///< before the final block the TBlock appends
  int outChannels = 0;
  int stateChannels = 0;   ///< level 0 only (the positional-code state); derived elsewhere
  int attentionHidden = 0; ///< view-attention width (MLI levels), 0 = no attention
};

struct DecoderConfig {
  std::vector<int> hidden;
  Activation activation = Activation::Relu;
};

struct NetworkConfig {
  std::string name;
  int numLayers = 4;
  int numPlanes = 41;
  double minDepth = 1.0, maxDepth = 100.0;
  double scaleFeatExtractor = 1.0, scaleLvl0 = 0.25, scaleLvl1 = 0.5, scaleLvl2 = 1.0;
  bool mpiOnly = false;
  int lvl0TanhPlanes = 3;
  bool mliErrorWithImage = true;
  /// Not in the reference: the level-0 block also reads, per plane and cell, the softmin
  /// distribution of classical plane-sweep stereo over the planes (baselines/plane_sweep_stereo.h:
  /// windowed RGB variance of the full-size sources, area-averaged to the level-0 grid), as one
  /// more input channel after [state | mean | var]. The tiny networks match flower no better than
  /// that fixed matcher does (README); with the prior they start from its geometry. Weights of the
  /// same config without it load into it with a zero weight on the channel
  /// (loadWithoutLvl0Prior), so the function starts unchanged.
  bool lvl0PhotoPrior = false;
  FeatureExtractorConfig featuresExtractor;
  TBlockConfig sampiLvl0, sampiLvl1;
  DecoderConfig alphaDecoder, depthDecoder, rgbaDecoder;
  int deformerHeads = 2, deformerHeadDim = 10;
  std::vector<TBlockConfig> samliBlocks; ///< one per MLI correction (levels 2, 3, ...)

  // ---- derived sizes ----------------------------------------------------------------------
  /// Feature-extractor output: descriptors + RGB (12 in the reference).
  int featureChannels() const {
    return featuresExtractor.descriptors + featuresExtractor.inChannels;
  }
  int mliCorrections() const { return static_cast<int>(samliBlocks.size()); }
  /// Per-view channels the MLI aggregators gather: error (3) [+ image (3)].
  int mliSourceChannels() const { return mliErrorWithImage ? 6 : 3; }
  /// Group opacities per layer: ceil(P / L) (11 for 41 / 4).
  int groupSize() const { return (numPlanes + numLayers - 1) / numLayers; }
  /// Plane stride between consecutive groups: floor(P / L) (10 for 41 / 4).
  int groupStride() const { return numPlanes / numLayers; }
  /// Channels of the representation the MLI corrections refine (fMLI0 or, MPI-only, fMPI1).
  int surfaceChannels() const { return sampiLvl1.outChannels; }
  /// Number of surfaces the corrections work on: L layers, or the P planes when MPI-only.
  int surfaces() const { return mpiOnly ? numPlanes : numLayers; }

  /// Throws simpli::Error naming `source` and the field for any inconsistency.
  void validate(const std::string& source) const;
};

/// Parses a JSON config; `source` names it in error messages (a file path or "<string>").
NetworkConfig parseNetworkConfig(const std::string& jsonText, const std::string& source);
/// Reads and parses a JSON config file.
NetworkConfig loadNetworkConfig(const std::string& path);
/// The JSON text of a config (parseNetworkConfig reads it back to an equal config).
std::string toJson(const NetworkConfig& config);
/// The reference architecture with 4 or 8 layers (tblock4 / tblock8); throws otherwise.
NetworkConfig officialConfig(int layers);

bool operator==(const NetworkConfig& a, const NetworkConfig& b);

} // namespace simpli::network

// NetworkConfig: JSON reading (strict: every key checked, unknown keys rejected), writing,
// validation and the two reference architectures.
#include "simpli/model/network/config.h"

#include "io/json_object_reader.h"
#include "simpli/error.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace simpli::network {
namespace {

using json = nlohmann::json;

using io::jsonExcerpt;
using io::JsonObjectReader;

constexpr int kMaxChannels = 1 << 16;

std::vector<BlockDims> readBlocks(io::JsonObjectReader& r) {
  const json& v = r.require("blocks");
  if (!v.is_array())
    fail(r.source(), ": ", r.where("blocks"), " is ", io::jsonExcerpt(v),
         ", expected an array of [inner, out] pairs");
  std::vector<BlockDims> blocks;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string what = r.where("blocks[" + std::to_string(i) + "]");
    if (!v[i].is_array() || v[i].size() != 2)
      fail(r.source(), ": ", what, " is ", io::jsonExcerpt(v[i]), ", expected [inner, out]");
    blocks.push_back({r.integerValue(v[i][0], what + "[0]", 1, kMaxChannels),
                      r.integerValue(v[i][1], what + "[1]", 1, kMaxChannels)});
  }
  return blocks;
}

TBlockConfig readTBlock(io::JsonObjectReader r, bool withState, bool withAttention) {
  TBlockConfig c;
  c.blocks = readBlocks(r);
  c.outChannels = r.integer("out_channels", 1, kMaxChannels);
  if (withState)
    c.stateChannels = r.integer("state_channels", 1, kMaxChannels);
  if (withAttention)
    c.attentionHidden = r.integer("attention_hidden", 0, kMaxChannels);
  r.finish();
  return c;
}

DecoderConfig readDecoder(io::JsonObjectReader r) {
  DecoderConfig c;
  c.hidden = r.integers("hidden", 0, 64);
  c.activation = parseActivation(r.string("activation"), r.source() + ": " + r.where("activation"));
  r.finish();
  return c;
}

json blocksJson(const std::vector<BlockDims>& blocks) {
  json a = json::array();
  for (const BlockDims& b : blocks)
    a.push_back({b.inner, b.out});
  return a;
}

json decoderJson(const DecoderConfig& d) {
  return {{"hidden", d.hidden}, {"activation", toString(d.activation)}};
}

bool sameTBlock(const TBlockConfig& a, const TBlockConfig& b) {
  return a.blocks == b.blocks && a.outChannels == b.outChannels &&
         a.stateChannels == b.stateChannels && a.attentionHidden == b.attentionHidden;
}

bool sameDecoder(const DecoderConfig& a, const DecoderConfig& b) {
  return a.hidden == b.hidden && a.activation == b.activation;
}

} // namespace

Activation parseActivation(const std::string& text, const std::string& what) {
  if (text == "none")
    return Activation::None;
  if (text == "relu")
    return Activation::Relu;
  if (text == "elu")
    return Activation::Elu;
  fail(what, " is \"", text, "\", expected \"none\", \"relu\" or \"elu\"");
}

const char* toString(Activation activation) {
  switch (activation) {
  case Activation::None:
    return "none";
  case Activation::Relu:
    return "relu";
  case Activation::Elu:
    return "elu";
  }
  return "?";
}

void NetworkConfig::validate(const std::string& source) const {
  if (numPlanes < 2)
    fail(source, ": field \"num_planes\" = ", numPlanes, ", at least 2 needed");
  if (numLayers < 1 || numLayers > numPlanes)
    fail(source, ": field \"num_layers\" = ", numLayers, " must be in [1, num_planes = ", numPlanes,
         "]");
  // The depth of layer k composites planes k*s .. k*s + G - 1 (reference §4.9); with
  // P mod L > 1 the last planes would belong to no group.
  if (!mpiOnly && numPlanes % numLayers > 1)
    fail(source, ": num_planes = ", numPlanes, " and num_layers = ", numLayers, " leave planes ",
         (numLayers - 1) * groupStride() + groupSize(), "..", numPlanes - 1,
         " outside every layer's plane group (need num_planes mod num_layers <= 1)");
  if (!(minDepth > 0.0) || !(maxDepth > minDepth))
    fail(source, ": depth range [", minDepth, ", ", maxDepth,
         "] is invalid (need 0 < min_depth < max_depth)");
  const std::pair<const char*, double> scales[] = {{"scale_feat_extractor", scaleFeatExtractor},
                                                   {"scale_lvl0", scaleLvl0},
                                                   {"scale_lvl1", scaleLvl1},
                                                   {"scale_lvl2", scaleLvl2}};
  for (const auto& [key, value] : scales)
    if (!(value > 0.0) || value > 8.0)
      fail(source, ": field \"", key, "\" = ", value, " must be in (0, 8]");
  if (lvl0TanhPlanes < 0 || lvl0TanhPlanes > numPlanes)
    fail(source, ": field \"lvl0_tanh_planes\" = ", lvl0TanhPlanes, " must be in [0, ", numPlanes,
         "]");
  if (featuresExtractor.widths.size() != 4)
    fail(source, ": field \"features_extractor.widths\" has ", featuresExtractor.widths.size(),
         " entries, expected 4");
  if (sampiLvl0.stateChannels < 1)
    fail(source, ": field \"sampi_block_lvl0.state_channels\" = ", sampiLvl0.stateChannels,
         " must be positive");
  if (deformerHeads < 1 || deformerHeadDim < 1)
    fail(source, ": planes_deformer_lvl1 heads = ", deformerHeads, ", head_dim = ", deformerHeadDim,
         " must be positive");
  for (std::size_t i = 0; i < samliBlocks.size(); ++i)
    if (samliBlocks[i].outChannels != surfaceChannels())
      // The RGBA decoders and the next level's state read these channels.
      fail(source, ": field \"samli_blocks[", i, "].out_channels\" = ", samliBlocks[i].outChannels,
           " must equal sampi_block_lvl1.out_channels = ", surfaceChannels());
}

NetworkConfig parseNetworkConfig(const std::string& jsonText, const std::string& source) {
  const json root = io::parseJson(jsonText, source);
  io::JsonObjectReader r(root, source, "");
  NetworkConfig c;
  c.name = r.string("name");
  c.numLayers = r.integer("num_layers", 1, 1024);
  c.numPlanes = r.integer("num_planes", 2, 4096);
  c.minDepth = r.number("min_depth");
  c.maxDepth = r.number("max_depth");
  c.scaleFeatExtractor = r.number("scale_feat_extractor");
  c.scaleLvl0 = r.number("scale_lvl0");
  c.scaleLvl1 = r.number("scale_lvl1");
  c.scaleLvl2 = r.number("scale_lvl2");
  c.mpiOnly = r.boolean("mpi_only");
  c.lvl0TanhPlanes = r.integer("lvl0_tanh_planes", 0, 4096);
  c.mliErrorWithImage = r.boolean("mli_error_with_image");
  if (r.has("lvl0_photo_prior"))
    c.lvl0PhotoPrior = r.boolean("lvl0_photo_prior");
  {
    io::JsonObjectReader fe = r.object("features_extractor");
    c.featuresExtractor.widths = fe.integers("widths", 4, 4);
    c.featuresExtractor.headWidth = fe.integer("head_width", 1, kMaxChannels);
    c.featuresExtractor.descriptors = fe.integer("descriptors", 1, kMaxChannels);
    fe.finish();
  }
  c.sampiLvl0 = readTBlock(r.object("sampi_block_lvl0"), true, false);
  c.alphaDecoder = readDecoder(r.object("alpha_decoder_lvl0"));
  c.sampiLvl1 = readTBlock(r.object("sampi_block_lvl1"), false, false);
  // The planes -> layers modules do not exist in the MPI-only baseline, so their sections
  // may be left out there.
  if (!c.mpiOnly || r.has("planes_deformer_lvl1")) {
    io::JsonObjectReader d = r.object("planes_deformer_lvl1");
    c.deformerHeads = d.integer("heads", 1, 1024);
    c.deformerHeadDim = d.integer("head_dim", 1, kMaxChannels);
    d.finish();
  }
  if (!c.mpiOnly || r.has("depth_decoder_lvl1"))
    c.depthDecoder = readDecoder(r.object("depth_decoder_lvl1"));
  c.rgbaDecoder = readDecoder(r.object("rgba_decoder"));
  const json& samli = r.require("samli_blocks");
  if (!samli.is_array())
    fail(source, ": field \"samli_blocks\" is ", io::jsonExcerpt(samli),
         ", expected an array (one entry per MLI correction)");
  for (std::size_t i = 0; i < samli.size(); ++i)
    c.samliBlocks.push_back(readTBlock(
        io::JsonObjectReader(samli[i], source, "samli_blocks[" + std::to_string(i) + "]"), false,
        true));
  r.finish();
  c.validate(source);
  return c;
}

NetworkConfig loadNetworkConfig(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    fail(path, ": cannot open the network config");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad())
    fail(path, ": read error");
  return parseNetworkConfig(text.str(), path);
}

std::string toJson(const NetworkConfig& c) {
  json samli = json::array();
  for (const TBlockConfig& b : c.samliBlocks)
    samli.push_back({{"blocks", blocksJson(b.blocks)},
                     {"out_channels", b.outChannels},
                     {"attention_hidden", b.attentionHidden}});
  json root = {
      {"name", c.name},
      {"num_layers", c.numLayers},
      {"num_planes", c.numPlanes},
      {"min_depth", c.minDepth},
      {"max_depth", c.maxDepth},
      {"scale_feat_extractor", c.scaleFeatExtractor},
      {"scale_lvl0", c.scaleLvl0},
      {"scale_lvl1", c.scaleLvl1},
      {"scale_lvl2", c.scaleLvl2},
      {"mpi_only", c.mpiOnly},
      {"lvl0_tanh_planes", c.lvl0TanhPlanes},
      {"mli_error_with_image", c.mliErrorWithImage},
      {"features_extractor",
       {{"widths", c.featuresExtractor.widths},
        {"head_width", c.featuresExtractor.headWidth},
        {"descriptors", c.featuresExtractor.descriptors}}},
      {"sampi_block_lvl0",
       {{"state_channels", c.sampiLvl0.stateChannels},
        {"blocks", blocksJson(c.sampiLvl0.blocks)},
        {"out_channels", c.sampiLvl0.outChannels}}},
      {"alpha_decoder_lvl0", decoderJson(c.alphaDecoder)},
      {"sampi_block_lvl1",
       {{"blocks", blocksJson(c.sampiLvl1.blocks)}, {"out_channels", c.sampiLvl1.outChannels}}},
      {"planes_deformer_lvl1", {{"heads", c.deformerHeads}, {"head_dim", c.deformerHeadDim}}},
      {"depth_decoder_lvl1", decoderJson(c.depthDecoder)},
      {"rgba_decoder", decoderJson(c.rgbaDecoder)},
      {"samli_blocks", samli}};
  if (c.lvl0PhotoPrior) // written only when on: configs without it keep their exact text
    root["lvl0_photo_prior"] = true;
  return root.dump(2);
}

NetworkConfig officialConfig(int layers) {
  if (layers != 4 && layers != 8)
    fail("officialConfig: ", layers, " layers; the reference ships 4 and 8");
  NetworkConfig c;
  c.name = layers == 4 ? "official-4l" : "official-8l";
  c.numLayers = layers;
  c.numPlanes = 41;
  c.featuresExtractor = FeatureExtractorConfig{};
  c.sampiLvl0.blocks = {{32, 32}, {32, 32}, {32, 32}, {32, 16}, {16, 16}, {16, 16}};
  c.sampiLvl0.outChannels = 12;
  c.sampiLvl0.stateChannels = 12;
  c.alphaDecoder = {{12, 12}, Activation::Elu};
  c.sampiLvl1.blocks = {{32, 32}, {32, 16}};
  c.sampiLvl1.outChannels = 16;
  c.depthDecoder = {{16, 8}, Activation::Relu};
  c.rgbaDecoder = {{16, 8}, Activation::Relu};
  TBlockConfig lvl2;
  lvl2.blocks = {{32, 32}, {16, 16}};
  lvl2.outChannels = 16;
  lvl2.attentionHidden = 16;
  TBlockConfig lvl34;
  lvl34.blocks = {{16, 16}};
  lvl34.outChannels = 16;
  lvl34.attentionHidden = 16;
  c.samliBlocks = {lvl2, lvl34, lvl34};
  c.validate(c.name);
  return c;
}

bool operator==(const NetworkConfig& a, const NetworkConfig& b) {
  if (a.samliBlocks.size() != b.samliBlocks.size())
    return false;
  for (std::size_t i = 0; i < a.samliBlocks.size(); ++i)
    if (!sameTBlock(a.samliBlocks[i], b.samliBlocks[i]))
      return false;
  return a.name == b.name && a.numLayers == b.numLayers && a.numPlanes == b.numPlanes &&
         a.minDepth == b.minDepth && a.maxDepth == b.maxDepth &&
         a.scaleFeatExtractor == b.scaleFeatExtractor && a.scaleLvl0 == b.scaleLvl0 &&
         a.scaleLvl1 == b.scaleLvl1 && a.scaleLvl2 == b.scaleLvl2 && a.mpiOnly == b.mpiOnly &&
         a.lvl0TanhPlanes == b.lvl0TanhPlanes && a.mliErrorWithImage == b.mliErrorWithImage &&
         a.lvl0PhotoPrior == b.lvl0PhotoPrior &&
         a.featuresExtractor.inChannels == b.featuresExtractor.inChannels &&
         a.featuresExtractor.widths == b.featuresExtractor.widths &&
         a.featuresExtractor.headWidth == b.featuresExtractor.headWidth &&
         a.featuresExtractor.descriptors == b.featuresExtractor.descriptors &&
         sameTBlock(a.sampiLvl0, b.sampiLvl0) && sameTBlock(a.sampiLvl1, b.sampiLvl1) &&
         sameDecoder(a.alphaDecoder, b.alphaDecoder) &&
         sameDecoder(a.depthDecoder, b.depthDecoder) && sameDecoder(a.rgbaDecoder, b.rgbaDecoder) &&
         a.deformerHeads == b.deformerHeads && a.deformerHeadDim == b.deformerHeadDim;
}

} // namespace simpli::network

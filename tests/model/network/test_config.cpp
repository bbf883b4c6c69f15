// Network configs: the JSON files in model/configs, the reference architectures (parameter
// counts, state-dict keys and shapes), and errors for bad configs.
#include "support/golden.h"

#include "support/expect_error.h"

#include "simpli/model/network/network.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>

namespace simpli::network {
namespace {

std::string configPath(const std::string& name) {
  return std::string(SIMPLI_NETWORK_CONFIG_DIR) + "/" + name + ".json";
}

int64_t countUnder(const ParameterStore& store, const std::string& prefix) {
  int64_t n = 0;
  for (const std::string& name : store.names())
    if (name.compare(0, prefix.size(), prefix) == 0)
      n += store.get(name).numel();
  return n;
}

TEST(NetConfig, OfficialFilesEqualBuiltInConfigs) {
  EXPECT_TRUE(loadNetworkConfig(configPath("official-4l")) == officialConfig(4));
  EXPECT_TRUE(loadNetworkConfig(configPath("official-8l")) == officialConfig(8));
  EXPECT_FALSE(officialConfig(4) == officialConfig(8));
}

TEST(NetConfig, JsonRoundTrip) {
  for (const char* name : {"official-4l", "official-8l", "tiny", "tiny-mpi"}) {
    const NetworkConfig c = loadNetworkConfig(configPath(name));
    EXPECT_EQ(c.name, name);
    EXPECT_TRUE(parseNetworkConfig(toJson(c), "<round trip>") == c) << name;
  }
}

// Reference §5: totals and the per-module table.
TEST(NetConfig, OfficialParameterCounts) {
  const SimpliNetwork four(officialConfig(4));
  EXPECT_EQ(four.parameters().count(), 1879343);
  const SimpliNetwork eight(officialConfig(8));
  EXPECT_EQ(eight.parameters().count(), 1879362);

  const std::map<std::string, std::pair<int64_t, int64_t>> modules = {
      {"features_extractor.", {1518555, 1518555}}, {"sampi_block_lvl0.", {253472, 253472}},
      {"alpha_decoder_lvl0.", {325, 325}},         {"sampi_block_lvl1.", {40480, 40480}},
      {"planes_deformer_lvl1.", {1376, 1440}},     {"depth_decoder_lvl1.", {507, 462}},
      {"rgba_decoder_lvl1.", {444, 444}},          {"samli_block_lvl2.", {34924, 34924}},
      {"rgba_decoder_lvl2.", {444, 444}},          {"samli_block_lvl3.", {13964, 13964}},
      {"rgba_decoder_lvl3.", {444, 444}},          {"samli_block_lvl4.", {13964, 13964}},
      {"rgba_decoder_lvl4.", {444, 444}}};
  for (const auto& [prefix, counts] : modules) {
    EXPECT_EQ(countUnder(four.parameters(), prefix), counts.first) << prefix;
    EXPECT_EQ(countUnder(eight.parameters(), prefix), counts.second) << prefix;
  }
  // Single blocks quoted in §5.
  EXPECT_EQ(countUnder(four.parameters(), "features_extractor.convDa."), 885504);
  EXPECT_EQ(countUnder(four.parameters(), "features_extractor.conv1a."), 1920);
  const int64_t lvl0Blocks[] = {60128, 55488, 55488, 42144, 13920, 13920, 12384};
  for (int i = 0; i < 7; ++i)
    EXPECT_EQ(countUnder(four.parameters(),
                         "sampi_block_lvl0.post_aggregate_block.model." + std::to_string(i) + "."),
              lvl0Blocks[i]);
}

TEST(NetConfig, OfficialKeysAndShapesEqualGoldenWeights) {
  SIMPLI_REQUIRE_GOLDEN();
  const io::SafeTensorsReader& weights = test::goldenFile("weights");
  const SimpliNetwork net(officialConfig(4));
  const auto shapes = net.parameters().shapes();
  ASSERT_EQ(shapes.size(), weights.keys().size());
  for (const std::string& key : weights.keys()) {
    ASSERT_TRUE(shapes.count(key)) << "no parameter " << key;
    EXPECT_EQ(shapes.at(key), weights.info(key).shape) << key;
  }
  EXPECT_EQ(weights.metadata().at("n_parameters"), std::to_string(net.parameters().count()));
}

TEST(NetConfig, TinyConfigsAreSmall) {
  const NetworkConfig tiny = loadNetworkConfig(configPath("tiny"));
  EXPECT_EQ(tiny.numPlanes, 17);
  EXPECT_EQ(tiny.groupSize(), 5);
  EXPECT_EQ(tiny.groupStride(), 4);
  const SimpliNetwork net(tiny);
  // Under an eighth of the reference's 1,879,343.
  EXPECT_LT(net.parameters().count(), 1879343 / 8);
  EXPECT_EQ(net.depthDecoder->outChannels(), 5);
  EXPECT_EQ(net.samliBlocks.size(), 3u);
  EXPECT_EQ(net.rgbaDecoders.size(), 4u);

  // The DeepView-dagger baseline has no planes -> layers modules.
  const SimpliNetwork mpi(loadNetworkConfig(configPath("tiny-mpi")));
  EXPECT_FALSE(mpi.planesDeformer.has_value());
  EXPECT_FALSE(mpi.depthDecoder.has_value());
  for (const std::string& name : mpi.parameters().names()) {
    EXPECT_EQ(name.find("planes_deformer"), std::string::npos);
    EXPECT_EQ(name.find("depth_decoder"), std::string::npos);
  }
  EXPECT_EQ(mpi.config().surfaces(), 9);
}

TEST(NetConfig, DerivedSizes) {
  const NetworkConfig c4 = officialConfig(4), c8 = officialConfig(8);
  EXPECT_EQ(c4.featureChannels(), 12);
  EXPECT_EQ(c4.groupSize(), 11);
  EXPECT_EQ(c4.groupStride(), 10);
  EXPECT_EQ(c8.groupSize(), 6);
  EXPECT_EQ(c8.groupStride(), 5);
  EXPECT_EQ(c4.mliCorrections(), 3);
  EXPECT_EQ(c4.mliSourceChannels(), 6);
  const SimpliNetwork net(c4);
  EXPECT_EQ(net.sampiLvl0.inChannels, 36);
  EXPECT_EQ(net.sampiLvl1.inChannels, 37);
  EXPECT_EQ(net.samliBlocks[0].inChannels, 40);
  EXPECT_EQ(net.samliBlocks[2].inChannels, 40);
  EXPECT_EQ(net.sampiLvl0.postAggregate.outChannels(), 12);
  EXPECT_EQ(net.featuresExtractor.outChannels(), 12);
  EXPECT_THROW(officialConfig(6), Error);
}

// A config text with one field replaced (a tiny JSON patch: key -> raw JSON value).
std::string patched(const std::string& key, const std::string& value) {
  std::string text = toJson(officialConfig(4));
  const std::string needle = "\"" + key + "\": ";
  const std::size_t at = text.find(needle);
  EXPECT_NE(at, std::string::npos) << key;
  const std::size_t start = at + needle.size();
  std::size_t end = start;
  int depth = 0;
  for (; end < text.size(); ++end) {
    const char ch = text[end];
    if (ch == '[' || ch == '{')
      ++depth;
    else if (ch == ']' || ch == '}') {
      if (depth == 0)
        break;
      --depth;
    } else if (ch == ',' && depth == 0)
      break;
  }
  return text.substr(0, start) + value + text.substr(end);
}

TEST(NetConfig, BadConfigsNameTheField) {
  using test::expectError;
  expectError([] { parseNetworkConfig("{", "bad.json"); }, {"bad.json", "not valid JSON"});
  expectError([] { parseNetworkConfig("[]", "bad.json"); }, {"bad.json", "JSON object"});
  expectError([] { parseNetworkConfig(patched("num_planes", "\"41\""), "c.json"); },
              {"c.json", "num_planes", "integer"});
  expectError([] { parseNetworkConfig(patched("num_planes", "18"), "c.json"); },
              {"c.json", "num_planes = 18", "num_layers = 4"});
  expectError([] { parseNetworkConfig(patched("max_depth", "0.5"), "c.json"); },
              {"c.json", "depth range"});
  expectError([] { parseNetworkConfig(patched("scale_lvl1", "-1"), "c.json"); },
              {"c.json", "scale_lvl1", "-1"});
  expectError([] { parseNetworkConfig(patched("widths", "[64, 64, 128]"), "c.json"); },
              {"c.json", "features_extractor.widths"});
  expectError([] { parseNetworkConfig(patched("head_width", "0"), "c.json"); },
              {"c.json", "features_extractor.head_width", "0"});
  expectError([] { parseNetworkConfig(patched("activation", "\"gelu\""), "c.json"); },
              {"c.json", "alpha_decoder_lvl0.activation", "gelu"});
  expectError([] { parseNetworkConfig(patched("blocks", "[[32]]"), "c.json"); },
              {"c.json", "samli_blocks[0].blocks[0]"});
  expectError([] { parseNetworkConfig(patched("mpi_only", "1"), "c.json"); },
              {"c.json", "mpi_only", "true or false"});
  expectError([] { parseNetworkConfig(patched("lvl0_tanh_planes", "42"), "c.json"); },
              {"c.json", "lvl0_tanh_planes", "42"});
  expectError([] { parseNetworkConfig(patched("name", "\"x\", \"colour\": 1"), "c.json"); },
              {"c.json", "unknown", "colour"});
  expectError([] { parseNetworkConfig(patched("samli_blocks", "{}"), "c.json"); },
              {"c.json", "samli_blocks", "array"});
  expectError(
      [] {
        parseNetworkConfig(patched("samli_blocks", "[{\"blocks\": [], \"out_channels\": 8, "
                                                   "\"attention_hidden\": 16}]"),
                           "c.json");
      },
      {"c.json", "samli_blocks[0].out_channels", "8"});
  std::string missing = toJson(officialConfig(4));
  missing.erase(missing.find("\"scale_lvl0\""), std::string("\"scale_lvl0\": 0.25,").size());
  expectError([&] { parseNetworkConfig(missing, "c.json"); }, {"c.json", "missing", "scale_lvl0"});
  expectError([] { loadNetworkConfig("/nonexistent/net.json"); },
              {"/nonexistent/net.json", "cannot open"});
}

} // namespace
} // namespace simpli::network

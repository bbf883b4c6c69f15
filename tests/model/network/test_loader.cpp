// Network loading shared by the CLI and the filters: config resolution by name or file,
// config from weights metadata, weights round trip, and the errors a user meets.
#include "support/expect_error.h"

#include "simpli/error.h"
#include "simpli/model/network/loader.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

using namespace simpli;
using namespace simpli::network;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("simpli_loader_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

} // namespace

TEST(NetLoader, ResolvesBuiltInShippedAndFileConfigs) {
  EXPECT_EQ(resolveNetworkConfig("official-4l"), officialConfig(4));
  EXPECT_EQ(resolveNetworkConfig("official-8l"), officialConfig(8));
  const NetworkConfig tiny = resolveNetworkConfig("tiny");
  EXPECT_EQ(tiny, loadNetworkConfig(networkConfigDir() + "/tiny.json"));
  EXPECT_EQ(resolveNetworkConfig(networkConfigDir() + "/tiny.json"), tiny);
  test::expectError([] { resolveNetworkConfig("no-such-config"); },
                    {"no-such-config", "does not exist", "official-4l"});
}

TEST(NetLoader, WeightsRoundTripWithTheConfigInTheirMetadata) {
  const fs::path dir = scratch("roundtrip");
  const NetworkConfig tiny = resolveNetworkConfig("tiny");
  const std::string weights = (dir / "w.safetensors").string();
  {
    SimpliNetwork net(tiny, ocl::Dtype::F32, 7);
    net.parameters().save(weights, {{"config", toJson(tiny)}});
  }
  ASSERT_TRUE(configFromWeights(weights).has_value());
  EXPECT_EQ(*configFromWeights(weights), tiny);
  const LoadedNetwork loaded = loadNetwork("", weights, std::nullopt);
  ASSERT_TRUE(loaded.network);
  EXPECT_EQ(loaded.network->config(), tiny);
  EXPECT_NE(loaded.weightsDescription.find("w.safetensors"), std::string::npos);
  // The loaded parameters are the saved ones, not a fresh initialisation.
  const SimpliNetwork reference(tiny, ocl::Dtype::F32, 7), other(tiny, ocl::Dtype::F32, 8);
  const auto& names = reference.parameters().names();
  ASSERT_FALSE(names.empty());
  const auto a = loaded.network->parameters().get(names.front()).toVector();
  EXPECT_EQ(a, reference.parameters().get(names.front()).toVector());
  EXPECT_NE(a, other.parameters().get(names.front()).toVector());
  // A name in the metadata works as well as the JSON text.
  {
    SimpliNetwork net(tiny, ocl::Dtype::F32, 7);
    net.parameters().save(weights, {{"config", "tiny"}});
  }
  EXPECT_EQ(*configFromWeights(weights), tiny);
}

TEST(NetLoader, RandomInitialisationAndErrors) {
  const LoadedNetwork random = loadNetwork("tiny", "", 3);
  EXPECT_EQ(random.network->config(), resolveNetworkConfig("tiny"));
  EXPECT_NE(random.weightsDescription.find("random"), std::string::npos);
  const fs::path dir = scratch("errors");
  test::expectError([&] { loadNetwork("", (dir / "missing.safetensors").string(), std::nullopt); },
                    {"missing.safetensors", "does not exist"});
  const std::string bare = (dir / "bare.safetensors").string();
  {
    SimpliNetwork net(resolveNetworkConfig("tiny"), ocl::Dtype::F32, 1);
    net.parameters().save(bare);
  }
  test::expectError([&] { loadNetwork("", bare, std::nullopt); }, {"bare.safetensors", "config"});
  test::expectError([&] { loadNetwork("tiny", bare, 5); }, {"bare.safetensors", "exclude"});
  // Weights of another architecture: the missing parameter is named.
  test::expectError([&] { loadNetwork("official-4l", bare, std::nullopt); }, {"bare.safetensors"});
  ::setenv("SIMPLI_DEFAULT_WEIGHTS", (dir / "none.safetensors").string().c_str(), 1);
  test::expectError([] { loadNetwork("", "", std::nullopt); },
                    {"none.safetensors", "missing", "simpli train"});
  ::unsetenv("SIMPLI_DEFAULT_WEIGHTS");
}

// Mutation test of the network config reader (support/mutator.h): every mutant of the shipped
// configs is parsed to a config that validates and round-trips, or rejected with a
// simpli::Error.
#include "support/mutator.h"
#include "support/temp_dir.h"

#include "simpli/model/network/config.h"

#include <gtest/gtest.h>

using namespace simpli;

TEST(NetworkConfigMutants, ParsedOrNamedError) {
  const std::string dir = SIMPLI_NETWORK_CONFIG_DIR;
  const std::vector<std::string> corpus = {network::toJson(network::officialConfig(4)),
                                           test::readText(dir + "/tiny.json"),
                                           test::readText(dir + "/tiny-mpi.json")};
  const test::MutationCounts counts = test::runMutants(
      "network config", 50, 3000, test::MutantKind::Json, corpus, [](const std::string& m) {
        const network::NetworkConfig c = network::parseNetworkConfig(m, "mutant.json");
        c.validate("mutant.json");
        EXPECT_TRUE(network::parseNetworkConfig(network::toJson(c), "round trip") == c);
      });
  EXPECT_GT(counts.rejected, 1500);
  EXPECT_GT(counts.parsed, 100);
}

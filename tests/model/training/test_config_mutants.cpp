// Mutation test of the training config reader (support/mutator.h): every mutant of the shipped
// training configs is parsed to a config that validates and round-trips, or rejected with a
// simpli::Error.
#include "support/mutator.h"
#include "support/temp_dir.h"

#include "simpli/model/training/config.h"

#include <gtest/gtest.h>

using namespace simpli;

TEST(TrainingConfigMutants, ParsedOrNamedError) {
  const std::string dir = std::string(SIMPLI_NETWORK_CONFIG_DIR) + "/training";
  std::vector<std::string> corpus;
  for (const char* name : {"official-4l.json", "tiny.json", "tiny-mpi.json", "tiny-world.json"})
    corpus.push_back(test::readText(dir + "/" + name));
  corpus.push_back(training::toJson(training::parseTrainingConfig(corpus[1], "tiny", dir)));
  const test::MutationCounts counts = test::runMutants(
      "training config", 60, 3000, test::MutantKind::Json, corpus, [&](const std::string& m) {
        const training::TrainingConfig c = training::parseTrainingConfig(m, "mutant.json", dir);
        c.validate("mutant.json");
        const training::TrainingConfig back =
            training::parseTrainingConfig(training::toJson(c), "round trip", dir);
        EXPECT_EQ(training::firstIncompatibleField(c, back), "");
        EXPECT_EQ(back.steps, c.steps);
      });
  EXPECT_GT(counts.rejected, 1000);
  EXPECT_GT(counts.parsed, 100);
}

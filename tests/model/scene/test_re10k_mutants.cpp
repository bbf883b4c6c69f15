// Mutation test of the RealEstate10K / SWORD camera-file reader (support/mutator.h): every
// mutant is read to valid cameras or rejected with a simpli::Error.
#include "support/captured_warnings.h"
#include "support/mutator.h"
#include "support/scene_fixtures.h"

#include "simpli/model/scene/camera_checks.h"
#include "simpli/model/scene/readers.h"
#include "simpli/model/scene/scene.h"

#include <gtest/gtest.h>

#include <set>

using namespace simpli;

TEST(RealEstate10KMutants, ReadOrNamedError) {
  test::TempDir dir;
  const std::string root = dir.str("scene");
  test::writeRealEstateScene(root, test::makeRig(5));
  const std::string path = root + "/scene.txt";
  const std::string original = test::readText(path);
  test::CapturedWarnings warnings; // frames whose mutated id names no image are left out
  const test::MutationCounts counts = test::runMutants(
      "RealEstate10K", 20, 3000, test::MutantKind::Text, {original}, [&](const std::string& m) {
        test::writeText(path, m);
        const scene::SceneSource src = scene::readRealEstateSource(root);
        ASSERT_FALSE(src.cameras.empty());
        ASSERT_EQ(src.names.size(), src.cameras.size());
        ASSERT_EQ(src.imagePaths.size(), src.cameras.size());
        EXPECT_EQ(std::set<std::string>(src.names.begin(), src.names.end()).size(),
                  src.names.size());
        for (const scene::Camera& c : src.cameras)
          scene::validateCamera(c, "mutant camera", scene::kRotationTolerance);
      });
  EXPECT_GT(counts.rejected, 1000);
  EXPECT_GT(counts.parsed, 300);
}

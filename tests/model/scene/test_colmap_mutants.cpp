// Mutation test of the COLMAP text reader (support/mutator.h): every mutant of cameras.txt,
// images.txt or points3D.txt is read to valid cameras or rejected with a simpli::Error.
#include "support/mutator.h"
#include "support/scene_fixtures.h"

#include "simpli/model/scene/camera_checks.h"
#include "simpli/model/scene/readers.h"
#include "simpli/model/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace simpli;

namespace {

// The views of a source read from a mutant: one name, image and valid camera each.
void expectValid(const scene::SceneSource& src) {
  ASSERT_FALSE(src.cameras.empty());
  ASSERT_EQ(src.names.size(), src.cameras.size());
  ASSERT_EQ(src.imagePaths.size(), src.cameras.size());
  for (const scene::Camera& c : src.cameras)
    scene::validateCamera(c, "mutant camera", scene::kRotationTolerance); // throws if not
  if (src.near > 0) {
    EXPECT_TRUE(std::isfinite(src.far) && src.far >= src.near) << src.near << " " << src.far;
  }
}

} // namespace

TEST(ColmapMutants, ReadOrNamedError) {
  test::TempDir dir;
  const std::string root = dir.str("scene");
  test::writeColmapScene(root, test::makeRig(4), test::makePoints(30));
  const std::string model = root + "/sparse/0/";
  const char* files[] = {"cameras.txt", "images.txt", "points3D.txt"};
  int rejected = 0, parsed = 0;
  for (int f = 0; f < 3; ++f) {
    const std::string path = model + files[f];
    const std::string original = test::readText(path);
    const test::MutationCounts counts =
        test::runMutants(std::string("COLMAP ") + files[f], 10 + static_cast<uint64_t>(f), 1200,
                         test::MutantKind::Text, {original}, [&](const std::string& mutant) {
                           test::writeText(path, mutant);
                           expectValid(scene::readColmapSource(root));
                         });
    test::writeText(path, original);
    rejected += counts.rejected;
    parsed += counts.parsed;
  }
  EXPECT_GT(rejected, 1000);
  EXPECT_GT(parsed, 300);
}

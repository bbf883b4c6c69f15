// Folders of scene folders: sorted by name, hidden folders and files skipped, each subfolder with
// what the format detection says of it; a scene folder is recognised as such.
#include "support/expect_error.h"
#include "support/scene_fixtures.h"
#include "support/temp_dir.h"

#include "simpli/model/scene/scene_folders.h"

#include <gtest/gtest.h>

#include <filesystem>

namespace simpli::scene {
namespace {

TEST(SceneFolders, SortedSubfoldersWithTheirProblems) {
  test::TempDir dir;
  const auto rig = test::makeRig(3);
  test::writeLlffScene(dir.str("b_llff"), rig, 2.0, 50.0);
  test::writeColmapScene(dir.str("a_colmap"), rig, test::makePoints(20));
  std::filesystem::create_directories(dir / "c_empty");
  std::filesystem::create_directories(dir / ".hidden");
  test::writeText(dir / "notes.txt", "not a folder");
  const std::vector<SceneFolder> s = listSceneFolders(dir.str());
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].name, "a_colmap");
  EXPECT_EQ(s[0].path, dir.str("a_colmap"));
  EXPECT_EQ(s[0].problem, "");
  EXPECT_EQ(s[1].name, "b_llff");
  EXPECT_EQ(s[1].problem, "");
  EXPECT_EQ(s[2].name, "c_empty");
  EXPECT_NE(s[2].problem.find("c_empty"), std::string::npos) << s[2].problem;
  EXPECT_TRUE(isSceneFolder(dir.str("b_llff")));
  EXPECT_FALSE(isSceneFolder(dir.str()));
  EXPECT_FALSE(isSceneFolder(dir.str("c_empty")));
  EXPECT_TRUE(listSceneFolders(dir.str("c_empty")).empty());
}

TEST(SceneFolders, MissingOrFileIsNamed) {
  test::TempDir dir;
  test::expectError([&] { listSceneFolders(dir.str("none")); }, {"none", "does not exist"});
  test::writeText(dir / "file", "x");
  test::expectError([&] { listSceneFolders(dir.str("file")); }, {"file", "is not a folder"});
}

} // namespace
} // namespace simpli::scene

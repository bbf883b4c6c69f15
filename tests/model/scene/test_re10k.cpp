// RealEstate10K / SWORD camera files.
#include "support/captured_warnings.h"
#include "support/expect_error.h"
#include "support/scene_fixtures.h"

#include "simpli/model/scene/scene.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace simpli;
using simpli::test::expectError;
using simpli::test::TempDir;
namespace fs = std::filesystem;

TEST(RealEstate10K, ReadsNamedFileWithImagesBeside) {
  TempDir dir;
  const auto rig = test::makeRig(4);
  const std::string root = dir / "scene_abc";
  test::writeRealEstateScene(root, rig);
  const scene::Scene s = scene::readScene(root);
  EXPECT_EQ(s.format, scene::SceneFormat::RealEstate10K);
  EXPECT_EQ(s.posesFile, root + "/scene_abc.txt");
  ASSERT_EQ(s.size(), 4u);
  // No bounds in the format: defaults, scale 1 (data assumed scaled, as in the reference).
  EXPECT_DOUBLE_EQ(s.near, scene::kDefaultNear);
  EXPECT_DOUBLE_EQ(s.far, scene::kDefaultFar);
  EXPECT_DOUBLE_EQ(s.normalisation.scale, 1.0);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(s.views[i].name, std::to_string(1000 * (i + 1)));
    EXPECT_LT((s.views[i].camera.R - rig[i].R).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_LT((s.views[i].camera.t - rig[i].t).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_DOUBLE_EQ(s.views[i].camera.fy, 1.5);
    EXPECT_EQ(s.views[i].camera.width, 48);
  }
  // The camera file may be given directly.
  EXPECT_EQ(scene::readScene(root + "/scene_abc.txt").size(), 4u);
  // With an explicit near bound the scene is scaled like the others.
  scene::SceneReadOptions o;
  o.near = 0.5;
  EXPECT_DOUBLE_EQ(scene::readScene(root, o).normalisation.scale, 2.0);
}

TEST(RealEstate10K, CamerasTxtWithImagesFolder) {
  TempDir dir;
  const std::string root = dir / "x";
  test::writeRealEstateScene(root, test::makeRig(2), "cameras.txt", "images");
  const scene::Scene s = scene::readScene(root);
  EXPECT_EQ(s.format, scene::SceneFormat::RealEstate10K);
  EXPECT_EQ(s.size(), 2u);
  EXPECT_EQ(s.views[1].imagePath, root + "/images/2000.png");
}

// Frames without an image are left out with one warning that lists them (the reference stops
// silently at the first one); no image at all is an error listing the frames.
TEST(RealEstate10K, MissingImagesAreListed) {
  TempDir dir;
  const std::string root = dir / "s";
  test::writeRealEstateScene(root, test::makeRig(8));
  for (const char* id : {"3000", "5000", "6000"})
    fs::remove(root + "/" + id + ".png");
  {
    test::CapturedWarnings warnings;
    const scene::Scene s = scene::readScene(root);
    ASSERT_EQ(s.size(), 5u);
    EXPECT_EQ(s.views[2].name, "4000"); // frames after the first missing one are read
    EXPECT_EQ(s.views[4].name, "8000");
    EXPECT_EQ(warnings.count({"s.txt", "3 of its 8 frames have no image", "3000 (line 4)",
                              "5000 (line 6)", "6000 (line 7)"}),
              1)
        << warnings.text();
  }
  {
    test::CapturedWarnings warnings;
    test::writeRealEstateScene(root, test::makeRig(8));
    EXPECT_EQ(scene::readScene(root).size(), 8u);
    EXPECT_TRUE(warnings.messages().empty()) << warnings.text();
  }
  for (int k = 1; k <= 8; ++k)
    fs::remove(root + "/" + std::to_string(1000 * k) + ".png");
  expectError([&] { scene::readScene(root); },
              {"s.txt", "none of its 8 frames has an image", "1000 (line 2)", "and 3 more"});
}

// Line 1 is the video's URL in RealEstate10K files, but a file may start with a frame: line 1
// is then read as one (it was always dropped as a header).
TEST(RealEstate10K, FirstLineIsAFrameUnlessAHeader) {
  TempDir dir;
  const std::string root = dir / "s";
  const auto rig = test::makeRig(3);
  test::writeRealEstateScene(root, rig);
  const std::string text = test::readText(root + "/s.txt");
  const std::string frames = text.substr(text.find('\n') + 1);
  test::writeText(root + "/s.txt", frames);
  scene::Scene s = scene::readScene(root);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s.views[0].name, "1000");
  // A scene name as the header (SWORD), comments and blank lines.
  test::writeText(root + "/s.txt", "scene_0042\n# comment\n\n" + frames);
  EXPECT_EQ(scene::readScene(root).size(), 3u);
  // A malformed first frame line is an error, not a header.
  test::writeText(root + "/s.txt", "1000 1 1.5 0.5\n" + frames.substr(frames.find('\n') + 1));
  expectError([&] { scene::readScene(root); }, {"s.txt", "line 1", "19 fields", "got 4"});
}

// Frame ids name the images: the same id twice is an error naming both lines.
TEST(RealEstate10K, DuplicateFrameIds) {
  TempDir dir;
  const std::string root = dir / "s";
  test::writeRealEstateScene(root, test::makeRig(3));
  std::string text = test::readText(root + "/s.txt");
  const size_t at = text.find("\n3000 ");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 6, "\n1000 ");
  test::writeText(root + "/s.txt", text);
  expectError([&] { scene::readScene(root); },
              {"s.txt", "line 4", "frame id 1000", "twice", "also line 2"});
}

TEST(RealEstate10K, BadLines) {
  TempDir dir;
  const std::string root = dir / "s";
  const auto rig = test::makeRig(2);
  test::writeRealEstateScene(root, rig);
  const std::string good = test::readText(root + "/s.txt");
  test::writeText(root + "/s.txt", good + "3000 1 1.5 0.5 0.5 0 0 1 0 0\n");
  test::writePatternImage(root + "/3000.png", 48, 32, 3);
  expectError([&] { scene::readScene(root); }, {"s.txt", "line 4", "19 fields", "10"});
  test::writeText(root + "/s.txt", good + "3000 1 1.5 0.5 0.5 0 0 1 0 0 0 0 1 0 0 0 0 1.2 0\n");
  expectError([&] { scene::readScene(root); }, {"s.txt", "'3000'", "line 4", "not orthonormal"});
  test::writeText(root + "/s.txt", good + "3000 1 1.5 0.5 0.5 0 0 1 0 0 0 0 1 0 0 0 0 1 inf\n");
  expectError([&] { scene::readScene(root); }, {"s.txt", "line 4", "t3", "inf"});
  test::writeText(root + "/s.txt", good + "3000 -1 1.5 0.5 0.5 0 0 1 0 0 0 0 1 0 0 0 0 1 0\n");
  expectError([&] { scene::readScene(root); }, {"s.txt", "'3000'", "focal length", "-1"});
  test::writeText(root + "/s.txt", "header only\n");
  expectError([&] { scene::readScene(root); }, {"s.txt", "no frames"});
  // Different image sizes.
  test::writeText(root + "/s.txt", good);
  test::writePatternImage(root + "/2000.png", 32, 32, 1);
  expectError([&] { scene::readScene(root); }, {"differ in size", "2000.png", "32 x 32"});
}

TEST(SceneFormat, Detection) {
  TempDir dir;
  const auto rig = test::makeRig(2);
  test::writeLlffScene(dir / "l", rig, 1, 10);
  test::writeColmapScene(dir / "c", rig, {});
  test::writeRealEstateScene(dir / "r", rig);
  EXPECT_EQ(scene::detectSceneFormat(dir / "l"), scene::SceneFormat::LLFF);
  EXPECT_EQ(scene::detectSceneFormat(dir / "l/poses_bounds.npy"), scene::SceneFormat::LLFF);
  EXPECT_EQ(scene::detectSceneFormat(dir / "c"), scene::SceneFormat::Colmap);
  EXPECT_EQ(scene::detectSceneFormat(dir / "r"), scene::SceneFormat::RealEstate10K);
  EXPECT_EQ(scene::detectSceneFormat(dir / "r/"), scene::SceneFormat::RealEstate10K);
  EXPECT_EQ(scene::detectSceneFormat(dir / "r/r.txt"), scene::SceneFormat::RealEstate10K);
  fs::create_directories(dir / "empty");
  expectError([&] { scene::detectSceneFormat(dir / "empty"); },
              {"empty", "cannot detect", "poses_bounds.npy"});
  expectError([&] { scene::detectSceneFormat(dir / "none"); }, {"none", "does not exist"});
  expectError([&] { scene::detectSceneFormat(dir / "l/images/img_00.png"); }, {"img_00.png"});
  // Forcing a format that does not match the folder.
  scene::SceneReadOptions o;
  o.format = scene::SceneFormat::Colmap;
  expectError([&] { scene::readScene(dir / "l", o); }, {"no COLMAP text model"});
  EXPECT_EQ(scene::parseSceneFormat("LLFF"), scene::SceneFormat::LLFF);
  EXPECT_EQ(scene::parseSceneFormat("sword"), scene::SceneFormat::RealEstate10K);
  expectError([] { scene::parseSceneFormat("obj"); }, {"'obj'"});
  EXPECT_DOUBLE_EQ(scene::maxBaseline({}), 0.0);
  EXPECT_NEAR(scene::maxBaseline(rig), (rig[0].centre() - rig[1].centre()).norm(), 1e-15);
}

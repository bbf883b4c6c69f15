// LLFF scenes: conversion of poses_bounds.npy to OpenCV world->camera cameras, bounds,
// normalisation, images, and every bad input.
#include "support/captured_warnings.h"
#include "support/expect_error.h"
#include "support/scene_fixtures.h"

#include "simpli/model/io/npy.h"
#include "simpli/model/scene/readers.h"
#include "simpli/model/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

using namespace simpli;
using simpli::test::expectError;
using simpli::test::TempDir;
namespace fs = std::filesystem;

namespace {

class LlffScene : public ::testing::Test {
protected:
  void SetUp() override {
    rig = test::makeRig(3);
    root = dir / "llff";
    test::writeLlffScene(root, rig, 2.0, 50.0);
  }
  std::string npy() const { return root + "/poses_bounds.npy"; }
  // Rewrites poses_bounds.npy with one value changed.
  void setValue(size_t view, size_t index, double value) {
    io::NpyArray a = io::readNpy(npy());
    a.data[view * 17 + index] = value;
    io::writeNpy(npy(), a.data, a.shape);
  }
  TempDir dir;
  std::vector<scene::Camera> rig;
  std::string root;
};

} // namespace

TEST_F(LlffScene, ReadsCamerasBoundsAndImages) {
  const scene::Scene s = scene::readScene(root);
  EXPECT_EQ(s.format, scene::SceneFormat::LLFF);
  EXPECT_EQ(s.posesFile, npy());
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s.width(), 48);
  EXPECT_EQ(s.height(), 32);
  // Bounds: min near (2.0) and max far (50) over the views; near -> 1 by default.
  EXPECT_EQ(s.normalisation.rule, scene::NormalisationMode::NearBound);
  EXPECT_DOUBLE_EQ(s.normalisation.scale, 0.5);
  EXPECT_DOUBLE_EQ(s.near, 1.0);
  EXPECT_DOUBLE_EQ(s.far, 25.0);
  EXPECT_DOUBLE_EQ(s.sceneNear(), 2.0);
  EXPECT_DOUBLE_EQ(s.sceneFar(), 50.0);
  for (size_t i = 0; i < 3; ++i) {
    const scene::Camera& c = s.views[i].camera;
    EXPECT_LT((c.R - rig[i].R).cwiseAbs().maxCoeff(), 1e-12) << i;
    EXPECT_LT((c.t - 0.5 * rig[i].t).cwiseAbs().maxCoeff(), 1e-12) << i;
    EXPECT_LT((s.normalisation.toScene(c).centre() - rig[i].centre()).norm(), 1e-12);
    EXPECT_DOUBLE_EQ(c.fx, 1.0);
    EXPECT_DOUBLE_EQ(c.fy, 1.5);
    EXPECT_DOUBLE_EQ(c.cx, 0.5);
    EXPECT_DOUBLE_EQ(c.cy, 0.5);
    EXPECT_EQ(c.width, 48);
    EXPECT_EQ(c.height, 32);
    EXPECT_EQ(s.views[i].originalWidth, 48);
    EXPECT_EQ(s.views[i].name, "img_0" + std::to_string(i) + ".png");
    const io::Image direct = io::readImage(s.views[i].imagePath);
    EXPECT_EQ(s.views[i].image.data, direct.data);
  }
  EXPECT_NE(s.views[0].image.data, s.views[1].image.data);
  EXPECT_TRUE(s.points.empty());
  // The projection of a world point agrees between the rig and the normalised scene.
  const Eigen::Vector3d X(0.2, 0.1, 5.0);
  EXPECT_LT((s.views[1].camera.project(s.normalisation.toNormalised(X)) - rig[1].project(X)).norm(),
            1e-12);
}

TEST_F(LlffScene, ConventionMatchesLlffAxes) {
  // An LLFF camera looking down world -z with "down" = -y and "right" = +x is the OpenCV
  // camera rotated by pi about x (x right, y down, z forward = world -z).
  std::vector<double> row = {0, 1, 0, 1, 32, -1, 0, 0, 2, 48, 0, 0, 1, 3, 48, 1, 9};
  std::vector<double> data;
  for (int i = 0; i < 3; ++i)
    data.insert(data.end(), row.begin(), row.end());
  io::writeNpy(npy(), data, {3, 17});
  scene::SceneReadOptions o;
  o.normalisation.mode = scene::NormalisationMode::None;
  const scene::Camera c = scene::readScene(root, o).views[0].camera;
  Eigen::Matrix3d expected;
  expected << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  EXPECT_LT((c.R - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((c.centre() - Eigen::Vector3d(1, 2, 3)).norm(), 1e-15);
  EXPECT_DOUBLE_EQ(c.fx, 1.0);       // 48 / 48
  EXPECT_DOUBLE_EQ(c.fy, 48.0 / 32); // 48 / 32
  // A point 5 units in front of the camera (world z = 3 - 5) has depth 5.
  EXPECT_NEAR(c.depth({1, 2, -2}), 5.0, 1e-12);
}

TEST_F(LlffScene, DownsampledImagesKeepRelativeIntrinsics) {
  // Poses written for 96 x 64 (focal 96), images 48 x 32: relative intrinsics are the same.
  const auto big = test::makeRig(3, 96, 64);
  std::vector<double> data;
  for (const scene::Camera& c : big) {
    const auto r = test::llffRow(c, 1.0, 10.0);
    data.insert(data.end(), r.begin(), r.end());
  }
  io::writeNpy(npy(), data, {3, 17});
  const scene::Scene s = scene::readScene(root);
  EXPECT_DOUBLE_EQ(s.views[0].camera.fx, 1.0);
  EXPECT_DOUBLE_EQ(s.views[0].camera.fy, 1.5);
  EXPECT_EQ(s.views[0].camera.width, 48);
  // Images whose aspect ratio differs from the stored h, w are not a down-sampled copy.
  for (int i = 0; i < 3; ++i)
    test::writePatternImage(root + "/images/img_0" + std::to_string(i) + ".png", 48, 48, i);
  expectError([&] { scene::readScene(root); },
              {"poses_bounds.npy", "96 x 64", "img_00.png", "48 x 48"});
}

TEST_F(LlffScene, ResizesToMultipleOf16AndOptions) {
  // 50 x 34 images with matching poses: resized to 48 x 32, intrinsics unchanged.
  std::vector<scene::Camera> cams = test::makeRig(3, 50, 34);
  for (auto& c : cams)
    c.fy = c.fx * 50.0 / 34.0;
  test::writeLlffScene(root, cams, 2.0, 50.0);
  scene::SceneReadOptions o;
  const scene::Scene s = scene::readScene(root, o);
  EXPECT_EQ(s.width(), 48);
  EXPECT_EQ(s.height(), 32);
  EXPECT_EQ(s.views[0].originalWidth, 50);
  EXPECT_EQ(s.views[0].originalHeight, 34);
  EXPECT_EQ(s.views[0].image.width, 48);
  EXPECT_DOUBLE_EQ(s.views[0].camera.fy, 50.0 / 34.0);
  o.sizeMultiple = 1;
  EXPECT_EQ(scene::readScene(root, o).width(), 50);

  o.sizeMultiple = 16;
  o.loadImages = false;
  const scene::Scene geometryOnly = scene::readScene(root, o);
  EXPECT_TRUE(geometryOnly.views[0].image.empty());
  EXPECT_EQ(geometryOnly.views[2].camera.width, 48);

  // Explicit bounds override the file's; near -> 1.
  o.near = 4.0;
  o.far = 40.0;
  const scene::Scene explicitBounds = scene::readScene(root, o);
  EXPECT_DOUBLE_EQ(explicitBounds.normalisation.scale, 0.25);
  EXPECT_DOUBLE_EQ(explicitBounds.far, 10.0);
  EXPECT_EQ(explicitBounds.boundsSource, "explicit");
  o.near = 0;
  o.far = 1.5; // below the file's near bound 2
  expectError([&] { scene::readScene(root, o); }, {"far bound 1.5", "near bound 2"});
  o.far = 0;
  o.near = -1;
  expectError([&] { scene::readScene(root, o); }, {"near bound option -1"});
}

TEST_F(LlffScene, ImagesDirOption) {
  for (int i = 0; i < 3; ++i)
    test::writePatternImage(root + "/images_2/a" + std::to_string(i) + ".JPG", 24, 16, i);
  scene::SceneReadOptions o;
  o.imagesDir = "images_2";
  o.sizeMultiple = 8;
  const scene::Scene s = scene::readScene(root, o);
  EXPECT_EQ(s.width(), 24);
  EXPECT_EQ(s.views[2].name, "a2.JPG");
  EXPECT_DOUBLE_EQ(s.views[2].camera.fy, 1.5);
  // Also accepted: the poses_bounds.npy path itself.
  EXPECT_EQ(scene::readScene(npy()).size(), 3u);
}

TEST_F(LlffScene, BadFolders) {
  expectError([&] { scene::readScene(dir / "nowhere"); }, {"nowhere", "does not exist"});
  fs::remove_all(root + "/images");
  expectError([&] { scene::readScene(root); }, {root + "/images", "does not exist"});
  fs::create_directories(root + "/images");
  test::writeText(root + "/images/notes.txt", "not an image");
  expectError([&] { scene::readScene(root); }, {"no images", root + "/images"});
}

TEST_F(LlffScene, ImageCountMismatch) {
  fs::remove(root + "/images/img_02.png");
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "3 poses", "2 images"});
  test::writePatternImage(root + "/images/img_02.png", 48, 32, 2);
  test::writePatternImage(root + "/images/img_03.jpg", 48, 32, 3);
  expectError([&] { scene::readScene(root); }, {"3 poses", "4 images"});
}

TEST_F(LlffScene, ImagesOfDifferentSizes) {
  test::writePatternImage(root + "/images/img_01.png", 64, 32, 1);
  expectError([&] { scene::readScene(root); },
              {"differ in size", "img_00.png", "48 x 32", "img_01.png", "64 x 32"});
}

TEST_F(LlffScene, CorruptImage) {
  test::writeText(root + "/images/img_01.png", "\x89PNG\r\n\x1a\n but then nothing");
  expectError([&] { scene::readScene(root); }, {"img_01.png", "cannot decode"});
}

TEST_F(LlffScene, MalformedNpy) {
  const std::string bytes = test::readText(npy());
  test::writeText(npy(), bytes.substr(0, bytes.size() - 30));
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "truncated"});
  test::writeText(npy(), bytes.substr(0, 40));
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "header is truncated"});
  std::string header = bytes;
  header.replace(header.find("'descr'"), 7, "'DESCR'");
  test::writeText(npy(), header);
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "'DESCR'"});
  io::writeNpy(npy(), std::vector<double>(45, 1.0), {3, 15});
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "15 columns"});
  io::writeNpy(npy(), std::vector<double>(51, 1.0), {3, 17, 1});
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "3 dimensions"});
  io::writeNpy(npy(), {}, {0, 17});
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "no poses"});
}

TEST_F(LlffScene, NonFinitePoses) {
  setValue(2, 3, std::numeric_limits<double>::quiet_NaN());
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "view 2", "value 3", "nan"});
  test::writeLlffScene(root, rig, 2.0, 50.0);
  setValue(0, 16, std::numeric_limits<double>::infinity());
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "view 0", "value 16", "inf"});
}

TEST_F(LlffScene, RotationNotOrthonormal) {
  setValue(1, 0, io::readNpy(npy()).at(1, 0) * 1.1 + 0.05); // stretch the "down" column
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "view 1", "not orthonormal"});
  // A reflection (right column negated) is orthonormal but not a rotation.
  test::writeLlffScene(root, rig, 2.0, 50.0);
  const io::NpyArray a = io::readNpy(npy());
  for (int r = 0; r < 3; ++r)
    setValue(2, size_t(5 * r + 1), -a.at(2, size_t(5 * r + 1)));
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "view 2", "reflection"});
}

TEST_F(LlffScene, BadBounds) {
  setValue(1, 15, 0.0);
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "view 1", "near bound 0"});
  setValue(1, 15, 2.0);
  setValue(0, 16, 1.5);
  expectError([&] { scene::readScene(root); },
              {"poses_bounds.npy", "view 0", "far bound 1.5", "near bound 2"});
  setValue(0, 16, 50);
  setValue(0, 14, -3); // focal
  expectError([&] { scene::readScene(root); }, {"poses_bounds.npy", "view 0", "focal", "-3"});
}

// Degenerate geometry: what cannot be a camera is an error naming the file, view, field and
// value; what is valid but will give a poor result is a warning that says why.
TEST_F(LlffScene, DegenerateGeometryIsRejectedOrWarned) {
  for (double focal : {1e-300, 1e300, 0.01}) { // relative fx = focal / 48
    setValue(1, 14, focal);
    expectError([&] { scene::readScene(root); },
                {"poses_bounds.npy", "view 1", "focal length fx", "outside [0.001, 1000]"});
    test::writeLlffScene(root, rig, 2.0, 50.0);
  }
  setValue(2, 4, 0.4); // h rounds to 0 pixels
  expectError([&] { scene::readScene(root); },
              {"poses_bounds.npy", "view 2", "declared image size (h, w) = (0.4, 48)"});
  test::writeLlffScene(root, rig, 2.0, 50.0);
  {
    test::CapturedWarnings warnings;
    scene::readScene(root);
    EXPECT_TRUE(warnings.messages().empty()) << warnings.text();
  }
  {
    test::writeLlffScene(root, rig, 1e-4, 1e6);
    test::CapturedWarnings warnings;
    const scene::Scene s = scene::readScene(root);
    EXPECT_EQ(s.size(), 3u);
    EXPECT_EQ(warnings.count({"poses_bounds.npy", "near..far bounds 0.0001..1e+06",
                              "depth ratio of 1e+10", "result will be poor"}),
              1)
        << warnings.text();
  }
  {
    // A wide-angle focal length: fx = 4.8 / 48 = 0.1 is the edge; 2.4 / 48 = 0.05 is beyond.
    test::writeLlffScene(root, rig, 2.0, 50.0);
    for (size_t v = 0; v < 3; ++v)
      setValue(v, 14, 2.4);
    test::CapturedWarnings warnings;
    scene::readScene(root);
    EXPECT_EQ(warnings.count({"poses_bounds.npy", "view 'img_00.png' (and 2 more)", "fx = 0.05",
                              "result will be poor"}),
              1)
        << warnings.text();
    EXPECT_EQ(warnings.count({"fy = 0.075"}), 1) << warnings.text();
  }
  {
    // All views at one centre: no parallax.
    std::vector<scene::Camera> same = rig;
    for (scene::Camera& c : same)
      c.t = -c.R * rig[0].centre();
    test::writeLlffScene(root, same, 2.0, 50.0);
    test::CapturedWarnings warnings;
    scene::readScene(root);
    EXPECT_EQ(warnings.count(
                  {"poses_bounds.npy", "3 views' camera centres lie within", "without parallax"}),
              1)
        << warnings.text();
  }
}

// The NeRF layout: images/ at full size and images_N/ down-sampled by N.
class LlffImageFolders : public LlffScene {
protected:
  void SetUp() override {
    LlffScene::SetUp();
    for (const auto& [folder, scale] : {std::pair{"images_2", 2}, std::pair{"images_4", 4}}) {
      fs::create_directories(fs::path(root) / folder);
      for (size_t i = 0; i < rig.size(); ++i)
        test::writePatternImage(
            (fs::path(root) / folder / ("img_0" + std::to_string(i) + ".png")).string(),
            rig[i].width / scale, rig[i].height / scale, int(i));
    }
  }
};

TEST_F(LlffImageFolders, FactorPicksImagesN) {
  EXPECT_EQ(scene::chooseImageFolder(root, 2, 0), "images_2");
  EXPECT_EQ(scene::chooseImageFolder(root, 1, 0), "images");
  scene::SceneReadOptions o;
  o.imagesFactor = 2;
  o.sizeMultiple = 1;
  const scene::Scene s = scene::readScene(root, o);
  EXPECT_EQ(s.imagesDir, "images_2");
  EXPECT_EQ(s.width(), 24);
  EXPECT_EQ(s.height(), 16);
  // Relative intrinsics hold for the down-sampled copy.
  EXPECT_DOUBLE_EQ(s.views[0].camera.fx, rig[0].fx);
}

TEST_F(LlffImageFolders, PreferredWidthPicksTheClosestFolder) {
  // Widths 48 (images), 24 (images_2), 12 (images_4); log-scale distance, ties to the larger.
  EXPECT_EQ(scene::chooseImageFolder(root, 0, 48), "images");
  EXPECT_EQ(scene::chooseImageFolder(root, 0, 30), "images_2");
  EXPECT_EQ(scene::chooseImageFolder(root, 0, 10), "images_4");
  EXPECT_EQ(scene::chooseImageFolder(root, 0, 17), "images_2"); // 24/17 = 1.41 < 17/12 = 1.42
  EXPECT_EQ(scene::chooseImageFolder(root, 0, 1000), "images");
  EXPECT_EQ(scene::chooseImageFolder(root, 0, 0), "");
  scene::SceneReadOptions o;
  o.preferredWidth = 12;
  o.sizeMultiple = 1;
  EXPECT_EQ(scene::readScene(root, o).width(), 12);
}

TEST_F(LlffImageFolders, MissingFactorFolderNamesTheFoldersFound) {
  expectError([&] { scene::chooseImageFolder(root, 8, 0); },
              {"image factor 8", "images_8", "images, images_2, images_4"});
  expectError([&] { scene::chooseImageFolder(root, -1, 0); }, {"image factor -1"});
  scene::SceneReadOptions o;
  o.imagesFactor = 3;
  expectError([&] { scene::readScene(root, o); }, {"images_3", "does not exist"});
}

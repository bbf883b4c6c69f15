// Training data sources (training/data.h): the synthetic source follows the config's
// "synthetic" section — style, size, views, photo textures from a folder — and, when photo
// textures are asked for and no photographs exist, fails with a named error or (photos_required
// false) falls back to procedural textures and says so.
#include "support/expect_error.h"
#include "support/temp_dir.h"

#include "simpli/model/io/image.h"
#include "simpli/model/training/data.h"

#include <gtest/gtest.h>

namespace simpli::training {
namespace {

DataOptions smallSynthetic() {
  DataOptions o;
  o.synthetic.views = 3;
  o.synthetic.objects = 3;
  o.synthetic.antialias = 1;
  o.synthetic.width = 64;
  o.synthetic.height = 48;
  o.configSource = "test.json";
  return o;
}

// A 32 x 32 photo of green and magenta blocks.
void writeTestPhoto(const std::string& file) {
  io::Image image(32, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const bool green = ((x / 8) + (y / 8)) % 2 == 0;
      image.at(0, y, x) = green ? -0.8f : 0.9f;
      image.at(1, y, x) = green ? 0.9f : -0.8f;
      image.at(2, y, x) = green ? -0.8f : 0.7f;
    }
  io::writeImagePng(image, file);
}

} // namespace

TEST(TrainData, SyntheticFollowsTheConfigSection) {
  DataOptions o = smallSynthetic();
  o.synthetic.style = synthetic::SceneStyle::World;
  auto data = openTrainingData("synthetic:4", o);
  const scene::Scene& s = data->scene(0);
  EXPECT_EQ(s.size(), 3u);
  EXPECT_EQ(s.width(), 64);
  EXPECT_EQ(s.height(), 48);
  EXPECT_NE(data->describe().find("world style"), std::string::npos) << data->describe();
  EXPECT_NE(data->describe().find("procedural textures"), std::string::npos);
  // --size (DataOptions width / height) overrides the section's size.
  o.width = 80;
  o.height = 32;
  EXPECT_EQ(openTrainingData("synthetic:4", o)->scene(0).width(), 80);
}

// Largest distance of a camera centre from the mean centre, in the scene's normalised units
// (nearest depth ~1), as the world style's translation range bounds it.
double cameraSpread(const scene::Scene& s) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const scene::SceneView& v : s.views)
    mean += v.camera.centre() / double(s.size());
  double spread = 0;
  for (const scene::SceneView& v : s.views)
    spread = std::max(spread, (v.camera.centre() - mean).norm());
  return spread;
}

TEST(TrainData, WorldTranslationRangeSetsTheBaseline) {
  DataOptions o = smallSynthetic();
  o.synthetic.style = synthetic::SceneStyle::World;
  o.synthetic.translationMin = o.synthetic.translationMax = 0.01;
  auto narrow = openTrainingData("synthetic:4", o);
  o.synthetic.translationMin = o.synthetic.translationMax = 0.4;
  auto wide = openTrainingData("synthetic:4", o);
  // The scene is normalised by its near bound (nearest visible depth, 0.9 .. 1.25 x the near
  // depth the range refers to), so the spread is the drawn fraction within that factor.
  const double a = cameraSpread(narrow->scene(0)), b = cameraSpread(wide->scene(0));
  EXPECT_GT(a, 0.01 * 0.7);
  EXPECT_LT(a, 0.01 * 1.3);
  EXPECT_GT(b, 0.4 * 0.7);
  EXPECT_LT(b, 0.4 * 1.3);
}

TEST(TrainData, PhotoTexturesFromAFolder) {
  test::TempDir photos;
  writeTestPhoto(photos.str("blocks.png"));
  DataOptions o = smallSynthetic();
  auto procedural = openTrainingData("synthetic:2", o);
  const io::Image a = procedural->scene(5).views[0].image;
  o.synthetic.textures = synthetic::TextureSet::Photo;
  o.synthetic.photoDir = photos.str();
  o.synthetic.photoProbability = 1.0;
  auto data = openTrainingData("synthetic:2", o);
  EXPECT_NE(data->describe().find("photo textures on 100 %"), std::string::npos)
      << data->describe();
  EXPECT_NE(data->describe().find("1 photos"), std::string::npos) << data->describe();
  const io::Image b = data->scene(5).views[0].image;
  ASSERT_EQ(a.data.size(), b.data.size());
  EXPECT_NE(a.data, b.data);
  // The same scene index gives the same images (the photos are read once and shared).
  EXPECT_EQ(openTrainingData("synthetic:2", o)->scene(5).views[0].image.data, b.data);
}

TEST(TrainData, NoPhotosIsANamedErrorOrAProceduralFallback) {
  test::TempDir empty;
  DataOptions o = smallSynthetic();
  o.synthetic.textures = synthetic::TextureSet::Photo;
  o.synthetic.photoDir = empty.str();
  test::expectError([&] { openTrainingData("synthetic", o); },
                    {"test.json", "field \"synthetic.textures\" is \"photo\"",
                     "no photographs were found in '" + empty.str() + "'",
                     "\"synthetic.photos_required\": false"});
  o.synthetic.photosRequired = false;
  auto data = openTrainingData("synthetic", o);
  EXPECT_NE(data->describe().find("NO PHOTOGRAPHS FOUND in '" + empty.str() + "'"),
            std::string::npos)
      << data->describe();
  // The fallback is the procedural source itself.
  DataOptions plain = smallSynthetic();
  EXPECT_EQ(data->scene(3).views[1].image.data,
            openTrainingData("synthetic", plain)->scene(3).views[1].image.data);
  // A photo folder that does not exist is named.
  o.synthetic.photoDir = empty.str("missing");
  test::expectError([&] { openTrainingData("synthetic", o); }, {"photo folder", "missing"});
}

} // namespace simpli::training

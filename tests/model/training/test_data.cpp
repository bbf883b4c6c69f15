// Training data sources (training/data.h): the synthetic source follows the config's
// "synthetic" section — style, size, views, photo textures from a folder — and, when photo
// textures are asked for and no photographs exist, fails with a named error or (photos_required
// false) falls back to procedural textures and says so; several sources mix by weight.
#include "support/expect_error.h"
#include "support/temp_dir.h"

#include "simpli/model/io/image.h"
#include "simpli/model/training/data.h"
#include "simpli/model/training/sampler.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>

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

TEST(TrainData, ParsesWeightedSources) {
  const DataSource plain = parseDataSource("synthetic:1");
  EXPECT_EQ(plain.spec, "synthetic:1");
  EXPECT_EQ(plain.weight, 1.0);
  const DataSource weighted = parseDataSource("scenes/llff@0.25");
  EXPECT_EQ(weighted.spec, "scenes/llff");
  EXPECT_EQ(weighted.weight, 0.25);
  EXPECT_EQ(parseDataSource("synthetic@3e1").weight, 30.0);
  // A path that exists is taken whole, '@' and all.
  test::TempDir dir;
  const std::string odd = dir.str("scenes@2");
  std::filesystem::create_directories(odd);
  EXPECT_EQ(parseDataSource(odd).spec, odd);
  EXPECT_EQ(parseDataSource(odd).weight, 1.0);
  for (const std::string bad : {"synthetic@", "synthetic@-1", "synthetic@abc", "@2", "synthetic@1x",
                                "synthetic@0", "synthetic@0.0"})
    test::expectError([&] { parseDataSource(bad); }, {"training data '" + bad + "'"});
  const DataOptions options = smallSynthetic();
  test::expectError([&] { openTrainingData(std::vector<DataSource>{}, options); },
                    {"no source given"});
  test::expectError(
      [&] {
        openTrainingData({{"synthetic:1", 1.0}, {"synthetic:2", -1.0}}, smallSynthetic());
      },
      {"'synthetic:2'", "weight -1"});
}

// scene_00 alone (weight 1) and the folder of all six scenes (weight 3): scene_00 is drawn with
// probability 1/4 + 3/4 x 1/6 = 0.375, each other scene 3/4 x 1/6 = 0.125 (over 4 000 mixture
// indices, binomial standard deviations 0.008 and 0.005); an index always gives the same scene.
TEST(TrainData, MixtureDrawsSourcesByWeight) {
  const std::string six = std::string(SIMPLI_DATASETS_SMALL_DIR) + "/synthetic";
  const std::string one = six + "/scene_00";
  DataOptions o;
  o.width = 32;
  o.height = 32;
  auto data = openTrainingData({{one, 1.0}, {six, 3.0}}, o);
  EXPECT_EQ(data->sceneCount(), 0u);
  const std::string about = data->describe();
  EXPECT_NE(about.find("25.0 % scene " + one), std::string::npos) << about;
  EXPECT_NE(about.find("75.0 % 6 scenes under " + six), std::string::npos) << about;
  std::map<std::string, int> counts;
  const int n = 4000;
  for (uint64_t i = 0; i < uint64_t(n); ++i) {
    const uint64_t index = i * 7919; // the sampler draws any 31-bit index
    const scene::Scene& s = data->scene(index);
    EXPECT_EQ(data->depths(index), nullptr); // folders know no depth
    ++counts[std::filesystem::path(s.root).filename().string()];
  }
  ASSERT_EQ(counts.size(), 6u);
  EXPECT_NEAR(counts["scene_00"] / double(n), 0.375, 0.03);
  for (const char* name : {"scene_01", "scene_02", "scene_03", "scene_04", "scene_05"})
    EXPECT_NEAR(counts[name] / double(n), 0.125, 0.025) << name;
  const std::string first = data->scene(12345).root;
  data->scene(777);
  EXPECT_EQ(data->scene(12345).root, first);
}

// A synthetic source in a mixture renders the scene the same source alone renders for that
// index, with its depths.
TEST(TrainData, MixtureKeepsTheSyntheticScenesAndDepths) {
  DataOptions o = smallSynthetic();
  const std::string folder = std::string(SIMPLI_DATASETS_SMALL_DIR) + "/synthetic/scene_01";
  auto mixed = openTrainingData({{"synthetic:4", 1.0}, {folder, 1.0}}, o);
  auto alone = openTrainingData("synthetic:4", o);
  int synthetic = 0, folders = 0;
  for (uint64_t index = 0; index < 12; ++index) {
    const scene::Scene& s = mixed->scene(index);
    if (s.root == folder) {
      ++folders;
      EXPECT_EQ(mixed->depths(index), nullptr);
      continue;
    }
    ++synthetic;
    const std::vector<float> pixels = s.views[1].image.data;
    const std::vector<std::vector<float>> depths = *mixed->depths(index);
    EXPECT_EQ(alone->scene(index).views[1].image.data, pixels) << index;
    EXPECT_EQ(*alone->depths(index), depths) << index;
  }
  EXPECT_GT(synthetic, 0);
  EXPECT_GT(folders, 0);
}

// A training draw renders colour only for its frames (sceneForFrames), and the sample is the
// one a draw from the fully rendered scene gives: same frames, pixels, cameras and depths.
TEST(TrainData, DrawRendersOnlyItsFramesAndGivesTheFullDraw) {
  DataOptions o = smallSynthetic();
  o.synthetic.views = 6;
  o.synthetic.style = synthetic::SceneStyle::World;
  SamplingConfig c;
  c.minViews = 2;
  c.maxViews = 3;
  c.novelViews = 1;
  c.window = 6;
  c.zoomScales = {1.0, 1.5};
  auto lazy = openTrainingData("synthetic:4", o), full = openTrainingData("synthetic:4", o);
  Sampler a(c, 21), b(c, 21);
  for (int k = 0; k < 4; ++k) {
    const TrainingSample s = a.draw(*lazy);
    // b draws the index as draw() does, then its sample from the fully rendered scene (the
    // path before sceneForFrames).
    const uint64_t index = uint64_t(b.random().uniformInt(0, (int64_t(1) << 31) - 1));
    ASSERT_EQ(index, s.sceneIndex);
    const scene::Scene& scene = lazy->sceneForFrames(s.sceneIndex, {}); // the cached scene
    size_t rendered = 0;
    for (const scene::SceneView& v : scene.views)
      rendered += v.image.empty() ? 0 : 1;
    EXPECT_EQ(rendered, s.sourceFrames.size() + s.targetFrames.size()) << k;
    const scene::Scene& all = full->scene(index);
    for (const scene::SceneView& v : all.views)
      ASSERT_FALSE(v.image.empty());
    const TrainingSample t = b.drawFromScene(all, index, full->depths(index));
    EXPECT_EQ(s.sourceFrames, t.sourceFrames);
    EXPECT_EQ(s.targetFrames, t.targetFrames);
    ASSERT_EQ(s.sources.size(), t.sources.size());
    for (size_t v = 0; v < s.sources.size(); ++v)
      EXPECT_EQ(s.sources[v].data, t.sources[v].data) << k << " source " << v;
    EXPECT_EQ(s.targets[0].data, t.targets[0].data) << k;
    EXPECT_EQ(s.targetCameras[0].t, t.targetCameras[0].t) << k;
    EXPECT_EQ(s.targetDepths, t.targetDepths) << k;
    EXPECT_EQ(s.sourceDepths, t.sourceDepths) << k;
  }
}

// Draws from a mixture go through its parts' frameCount / sceneForFrames: synthetic samples
// render colour for their frames only and equal the lone source's draws; folder samples read
// their scene whole.
TEST(TrainData, MixtureDrawsRenderOnlyTheirFrames) {
  DataOptions o = smallSynthetic();
  o.synthetic.views = 6;
  const std::string folder = std::string(SIMPLI_DATASETS_SMALL_DIR) + "/synthetic/scene_01";
  auto mixed = openTrainingData({{"synthetic:4", 1.0}, {folder, 1.0}}, o);
  SamplingConfig c;
  c.minViews = 2;
  c.maxViews = 2;
  c.novelViews = 1;
  Sampler sampler(c, 5);
  int synthetic = 0, folders = 0;
  for (int k = 0; k < 10; ++k) {
    const TrainingSample s = sampler.draw(*mixed);
    ASSERT_EQ(s.sources.size(), 2u);
    ASSERT_EQ(s.targets.size(), 1u);
    const scene::Scene& scene = mixed->sceneForFrames(s.sceneIndex, {});
    size_t rendered = 0;
    for (const scene::SceneView& v : scene.views)
      rendered += v.image.empty() ? 0 : 1;
    if (s.sceneRoot == folder) {
      ++folders;
      EXPECT_EQ(rendered, scene.size());
      EXPECT_TRUE(s.targetDepths.empty());
    } else {
      ++synthetic;
      EXPECT_EQ(rendered, 3u) << k;
      EXPECT_EQ(s.targetDepths.size(), 1u);
    }
  }
  EXPECT_GT(synthetic, 0);
  EXPECT_GT(folders, 0);
}

} // namespace simpli::training

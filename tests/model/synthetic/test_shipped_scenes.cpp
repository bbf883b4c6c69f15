// The synthetic scenes shipped in datasets_small/synthetic: readable, small, and exactly what
// `simpli make-scene` regenerates from the parameters in their scene.json.
#include "simpli/model/io/files.h"
#include "simpli/model/scene/scene.h"
#include "simpli/model/synthetic/scene_writer.h"

#include "synthetic_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>
#include <fstream>

using namespace simpli::synthetic;
namespace fs = std::filesystem;

namespace {

const fs::path kRoot = fs::path(SIMPLI_DATASETS_SMALL_DIR) / "synthetic";
constexpr int kSceneCount = 6;

std::string sceneName(int i) {
  return "scene_0" + std::to_string(i);
}

SyntheticSceneParams paramsFromJson(const fs::path& file) {
  std::ifstream in(file);
  const nlohmann::json j = nlohmann::json::parse(in);
  const nlohmann::json& p = j.at("params");
  SyntheticSceneParams s;
  s.seed = p.at("seed").get<uint64_t>();
  s.views = p.at("views");
  s.width = p.at("width");
  s.height = p.at("height");
  s.objects = p.at("objects");
  s.fovDegrees = p.at("fov_degrees");
  s.nearDepth = p.at("near_depth");
  s.backgroundDepthMin = p.at("background_depth_min");
  s.backgroundDepthMax = p.at("background_depth_max");
  s.maxBackgroundSlantDegrees = p.at("max_background_slant_degrees");
  s.translation = p.at("translation");
  s.rotationDegrees = p.at("rotation_degrees");
  s.antialias = p.at("antialias");
  return s;
}

// Same bytes, or (PNG encoders may differ between library versions) the same decoded pixels.
void expectSameFile(const fs::path& shipped, const fs::path& regenerated, bool isPng) {
  const auto a = simpli::io::readFileBytes(shipped.string(), "shipped file");
  const auto b = simpli::io::readFileBytes(regenerated.string(), "regenerated file");
  if (a == b)
    return;
  ASSERT_TRUE(isPng) << shipped << " differs from its regenerated copy";
  const cv::Mat ma = cv::imread(shipped.string(), cv::IMREAD_UNCHANGED);
  const cv::Mat mb = cv::imread(regenerated.string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(ma.type(), mb.type()) << shipped;
  ASSERT_EQ(ma.size(), mb.size()) << shipped;
  EXPECT_EQ(cv::norm(ma, mb, cv::NORM_INF), 0.0) << shipped << ": decoded pixels differ";
}

} // namespace

TEST(ShippedScenes, ReadableAndSmall) {
  uintmax_t bytes = 0;
  for (const auto& e : fs::recursive_directory_iterator(kRoot))
    if (e.is_regular_file())
      bytes += e.file_size();
  EXPECT_LT(bytes, 15u * 1000 * 1000) << "datasets_small/synthetic is " << bytes << " bytes";
  for (int i = 0; i < kSceneCount; ++i) {
    const fs::path dir = kRoot / sceneName(i);
    simpli::scene::SceneReadOptions options;
    options.loadImages = false;
    const simpli::scene::Scene s = simpli::scene::readScene(dir.string(), options);
    EXPECT_EQ(s.format, simpli::scene::SceneFormat::LLFF);
    EXPECT_EQ(s.size(), 12u);
    EXPECT_EQ(s.width(), 192);
    EXPECT_EQ(s.height(), 128);
    const SyntheticSceneParams p = paramsFromJson(dir / "scene.json");
    EXPECT_EQ(p.seed, uint64_t(i));
    int depthFiles = 0;
    for (const auto& e : fs::directory_iterator(dir / "depth"))
      depthFiles += e.path().extension() == ".png";
    EXPECT_EQ(depthFiles, 12);
  }
}

TEST(ShippedScenes, SceneZeroRegeneratesExactly) {
  const fs::path shipped = kRoot / sceneName(0);
  const SyntheticSceneParams p = paramsFromJson(shipped / "scene.json");
  const SyntheticScene scene = generateSyntheticScene(p);
  simpli::test::TempDir tmp;
  writeSyntheticScene(tmp.str("scene_00"), scene, renderViews(scene));
  const fs::path fresh = tmp.path() / "scene_00";
  expectSameFile(shipped / "poses_bounds.npy", fresh / "poses_bounds.npy", false);
  expectSameFile(shipped / "scene.json", fresh / "scene.json", false);
  for (const char* sub : {"images", "depth"})
    for (const auto& e : fs::directory_iterator(shipped / sub))
      expectSameFile(e.path(), fresh / sub / e.path().filename(), true);
  // Nothing extra on either side.
  for (const char* sub : {"images", "depth"}) {
    const auto count = [](const fs::path& d) {
      return std::distance(fs::directory_iterator(d), fs::directory_iterator());
    };
    EXPECT_EQ(count(shipped / sub), count(fresh / sub)) << sub;
  }
}

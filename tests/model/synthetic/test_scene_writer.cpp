// Writing synthetic scenes (synthetic/scene_writer.h) and the on-the-fly source
// (synthetic/procedural_source.h): both must give what readScene reads back.
#include "simpli/model/scene/llff_writer.h"
#include "simpli/model/scene/scene.h"
#include "simpli/model/synthetic/procedural_source.h"
#include "simpli/model/synthetic/scene_writer.h"

#include "support/expect_error.h"
#include "synthetic_test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

using namespace simpli::synthetic;
using simpli::test::expectError;
using simpli::test::TempDir;
namespace fs = std::filesystem;

namespace {

SyntheticSceneParams tinyParams(uint64_t seed = 3) {
  SyntheticSceneParams p;
  p.seed = seed;
  p.width = 48;
  p.height = 32;
  p.views = 3;
  p.objects = 5;
  p.antialias = 2;
  return p;
}

// Folder names in `dir` (to spot leftovers of a failed write).
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

void expectSameScene(const simpli::scene::Scene& read, const SyntheticSample& sample) {
  ASSERT_EQ(read.size(), sample.scene.size());
  EXPECT_NEAR(read.near, sample.scene.near, 1e-12);
  EXPECT_NEAR(read.far, sample.scene.far, 1e-12);
  EXPECT_NEAR(read.normalisation.scale, sample.scene.normalisation.scale, 1e-12);
  for (size_t i = 0; i < read.size(); ++i) {
    const auto& a = read.views[i];
    const auto& b = sample.scene.views[i];
    EXPECT_EQ(a.name, b.name);
    ASSERT_EQ(a.image.data.size(), b.image.data.size());
    for (size_t k = 0; k < a.image.data.size(); ++k)
      ASSERT_NEAR(a.image.data[k], b.image.data[k], 1e-6) << "view " << i << " value " << k;
    EXPECT_EQ(a.camera.R, b.camera.R);
    EXPECT_LT((a.camera.t - b.camera.t).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_NEAR(a.camera.fx, b.camera.fx, 1e-15);
    EXPECT_NEAR(a.camera.fy, b.camera.fy, 1e-15);
    EXPECT_EQ(a.camera.width, b.camera.width);
  }
}

} // namespace

TEST(SyntheticSceneWriter, WritesLlffDepthAndDescription) {
  TempDir tmp;
  const SyntheticScene scene = generateSyntheticScene(tinyParams());
  const std::vector<RenderedView> views = renderViews(scene);
  const WrittenScene w = writeSyntheticScene(tmp.str("scene"), scene, views);
  EXPECT_EQ(w.depthScale, 0.001);
  ASSERT_EQ(w.bounds.size(), 3u);
  EXPECT_EQ(entries(tmp.path()), std::vector<std::string>{"scene"}); // no temporary left
  EXPECT_EQ(entries(tmp.path() / "scene"),
            (std::vector<std::string>{"depth", "images", "poses_bounds.npy", "scene.json"}));
  EXPECT_EQ(entries(tmp.path() / "scene" / "images"),
            (std::vector<std::string>{"000.png", "001.png", "002.png"}));

  std::ifstream in(tmp.path() / "scene" / "scene.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["generator"], kSceneGenerator);
  EXPECT_EQ(j["seed"], 3u);
  EXPECT_EQ(j["params"]["views"], 3);
  EXPECT_EQ(j["params"]["width"], 48);
  EXPECT_EQ(j["depth"]["scale"], 0.001);
  EXPECT_EQ(j["objects"].size(), 5u);
  EXPECT_EQ(j["background"]["role"], "background");
  EXPECT_EQ(j["cameras"].size(), 3u);
  EXPECT_EQ(j["command"], "simpli make-scene --out DIR --seed 3 --views 3 --size 48x32 "
                          "--objects 5 --antialias 2");

  // Depth maps: the exact depths to within half a count.
  for (size_t i = 0; i < 3; ++i) {
    const std::vector<float> d = simpli::scene::readDepthPng(
        (tmp.path() / "scene" / "depth" / (simpli::scene::llffViewName(i, 3) + ".png")).string(),
        w.depthScale);
    ASSERT_EQ(d.size(), views[i].depth.size());
    for (size_t k = 0; k < d.size(); ++k)
      ASSERT_NEAR(d[k], views[i].depth[k], 0.5 * w.depthScale + 1e-5);
  }
}

TEST(SyntheticSceneWriter, ReadSceneGivesWhatTheProceduralSourceGives) {
  TempDir tmp;
  const SyntheticScene scene = generateSyntheticScene(tinyParams(8));
  const std::vector<RenderedView> views = renderViews(scene);
  writeSyntheticScene(tmp.str("s"), scene, views);
  const simpli::scene::Scene read = simpli::scene::readScene(tmp.str("s"));
  EXPECT_EQ(read.format, simpli::scene::SceneFormat::LLFF);
  expectSameScene(read, makeSample(scene, views));

  // And the source, given the same seed through its index mapping, renders the same scene.
  ProceduralSceneSource source(tinyParams(), 99);
  SyntheticSceneParams p = tinyParams(source.seedOf(4));
  const SyntheticScene viaSeed = generateSyntheticScene(p);
  const std::vector<RenderedView> viaSeedViews = renderViews(viaSeed);
  writeSyntheticScene(tmp.str("t"), viaSeed, viaSeedViews);
  expectSameScene(simpli::scene::readScene(tmp.str("t")), source.sample(4));
}

TEST(SyntheticSceneWriter, ExistingFoldersAreProtected) {
  TempDir tmp;
  const SyntheticScene a = generateSyntheticScene(tinyParams(1));
  const SyntheticScene b = generateSyntheticScene(tinyParams(2));
  const std::vector<RenderedView> va = renderViews(a), vb = renderViews(b);
  writeSyntheticScene(tmp.str("s"), a, va);
  expectError([&] { writeSyntheticScene(tmp.str("s"), b, vb); }, {"already exists", "--force"});
  SceneWriteOptions force;
  force.overwrite = true;
  writeSyntheticScene(tmp.str("s"), b, vb, force);
  std::ifstream in(tmp.path() / "s" / "scene.json");
  EXPECT_EQ(nlohmann::json::parse(in)["seed"], 2u);
  EXPECT_EQ(entries(tmp.path()), std::vector<std::string>{"s"});

  // A folder that is not a generated scene is never replaced.
  fs::create_directories(tmp.path() / "mine");
  std::ofstream(tmp.path() / "mine" / "notes.txt") << "keep me";
  expectError([&] { writeSyntheticScene(tmp.str("mine"), a, va, force); },
              {"mine", "not a scene written by simpli make-scene"});
  EXPECT_TRUE(fs::exists(tmp.path() / "mine" / "notes.txt"));

  expectError([&] { writeSyntheticScene(tmp.str("no/such/parent"), a, va); },
              {"parent folder", "does not exist"});
  expectError([&] { writeSyntheticScene("/proc/simpli_scene", a, va); },
              {"cannot create output folder '/proc/simpli_scene'"});
  const std::vector<RenderedView> two(va.begin(), va.begin() + 2);
  expectError([&] { writeSyntheticScene(tmp.str("x"), a, two); }, {"2 rendered views for 3"});
}

TEST(SyntheticSceneWriter, FailureLeavesNothingBehind) {
  TempDir tmp;
  const SyntheticScene a = generateSyntheticScene(tinyParams(1));
  SceneWriteOptions tooFine;
  tooFine.depthScale = 1e-6; // depths of several units do not fit 16 bits
  expectError([&] { writeSyntheticScene(tmp.str("s"), a, renderViews(a), tooFine); },
              {"cannot be stored as a 16-bit count"});
  EXPECT_TRUE(entries(tmp.path()).empty());
}

TEST(SyntheticSceneWriter, DepthScaleGrowsForDeepScenes) {
  RenderedView v;
  v.width = 2;
  v.height = 1;
  v.depth = {1.0f, 65.0f};
  EXPECT_EQ(chooseDepthScale({v}), 0.001);
  v.depth = {1.0f, 300.0f};
  EXPECT_DOUBLE_EQ(chooseDepthScale({v}), 0.01);
}

TEST(ProceduralSource, SamplesAreReproducibleAndIndependent) {
  const ProceduralSceneSource source(tinyParams(), 7);
  const SyntheticSample s3 = source.sample(3);
  const SyntheticSample s2 = source.sample(2);
  const SyntheticSample s3again = source.sample(3);
  EXPECT_EQ(s3.seed, source.seedOf(3));
  EXPECT_EQ(s3.index, 3u);
  ASSERT_EQ(s3.scene.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(s3.scene.views[i].image.data, s3again.scene.views[i].image.data);
    EXPECT_EQ(s3.depths[i], s3again.depths[i]);
  }
  EXPECT_NE(s3.scene.views[0].image.data, s2.scene.views[0].image.data);
  EXPECT_NE(ProceduralSceneSource(tinyParams(), 8).seedOf(3), s3.seed);

  // Normalised like readScene: near bound -> 1, depths in the same units, images on the
  // 8-bit grid in [-1, 1].
  EXPECT_NEAR(s3.scene.near, 1.0, 1e-12);
  float smallest = 1e30f;
  for (const auto& d : s3.depths)
    for (float z : d) {
      ASSERT_GT(z, 0.0f);
      smallest = std::min(smallest, z);
    }
  EXPECT_NEAR(smallest, 1.0 / 0.9, 1e-5); // near = 0.9 x the smallest depth
  for (float v : s3.scene.views[1].image.data) {
    ASSERT_GE(v, -1.0f);
    ASSERT_LE(v, 1.0f);
    const double q = (double(v) + 1.0) * 127.5;
    ASSERT_NEAR(q, std::round(q), 1e-4);
  }
  expectError(
      [] {
        SyntheticSceneParams p;
        p.views = 0;
        ProceduralSceneSource s(p);
      },
      {"'views' is 0"});
}

// Training renders colour only for the views a sample uses and the depth of the others: the
// rendered views, cameras, bounds and depths are those of the full sample, to the bit.
TEST(ProceduralSource, ColourForSomeViewsIsTheFullSampleThere) {
  SyntheticSceneParams p = tinyParams();
  p.views = 5;
  const ProceduralSceneSource source(p, 11);
  const SyntheticSample full = source.sample(4);
  const SyntheticSample part = source.sample(source.geometry(4), 4, {3, 1, 3});
  EXPECT_EQ(part.index, 4u);
  EXPECT_EQ(part.seed, full.seed);
  ASSERT_EQ(part.scene.size(), full.scene.size());
  EXPECT_EQ(part.scene.near, full.scene.near);
  EXPECT_EQ(part.scene.far, full.scene.far);
  EXPECT_EQ(part.depths, full.depths);
  for (size_t i = 0; i < full.scene.size(); ++i) {
    const bool colour = i == 1 || i == 3;
    EXPECT_EQ(part.scene.views[i].image.empty(), !colour) << i;
    if (colour) {
      EXPECT_EQ(part.scene.views[i].image.data, full.scene.views[i].image.data) << i;
    }
    EXPECT_EQ(part.scene.views[i].camera.t, full.scene.views[i].camera.t) << i;
    EXPECT_EQ(part.scene.views[i].camera.R, full.scene.views[i].camera.R) << i;
  }
  const SyntheticScene g = source.geometry(4);
  expectError([&] { source.sample(g, 4, {5}); }, {"synthetic sample 4", "view 5", "5 views"});
  expectError([&] { source.sample(g, 4, {-1}); }, {"view -1"});
}

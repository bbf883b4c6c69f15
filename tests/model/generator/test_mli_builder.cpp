// MLIBuilder: the network cache (kept while its source is unchanged, reloaded when it changes),
// the forward-reuse policy (the same network, sources, cameras and settings give the previous
// MLI without a pass; anything else runs one) and cancellation. The tiny config with random
// weights on the bundled synthetic scene.
#include "support/expect_error.h"

#include "simpli/error.h"
#include "simpli/model/generator/mli_builder.h"
#include "simpli/model/scene/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

using namespace simpli;

namespace {

const scene::Scene& bundled() {
  static const scene::Scene scene =
      scene::readScene(std::string(SIMPLI_DATA_DIR) + "/synthetic/scene_00");
  return scene;
}

generator::NetworkSource tiny(uint64_t seed) {
  generator::NetworkSource source;
  source.config = "tiny";
  source.randomSeed = seed;
  return source;
}

generator::MLIBuildOptions quick(std::vector<int> views) {
  generator::MLIBuildOptions options;
  options.views = std::move(views);
  options.corrections = 0;
  return options;
}

bool hasStage(const generator::MLIBuild& build, const std::string& name) {
  return std::any_of(build.stageMs.begin(), build.stageMs.end(),
                     [&](const auto& stage) { return stage.first == name; });
}

} // namespace

TEST(MLIBuilder, KeepsTheNetworkWhileItsSourceIsUnchanged) {
  generator::MLIBuilder builder;
  EXPECT_FALSE(builder.hasNetwork());
  const network::SimpliNetwork* first = builder.network(tiny(1)).network.get();
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(builder.network(tiny(1)).network.get(), first);
  EXPECT_EQ(builder.network(tiny(1)).weightsDescription, "random (seed 1)");
  builder.network(tiny(2));
  EXPECT_EQ(builder.network(tiny(2)).weightsDescription, "random (seed 2)");
  builder.release();
  EXPECT_FALSE(builder.hasNetwork());
}

TEST(MLIBuilder, ReusesTheLastPassOnlyForTheSameInputs) {
  generator::MLIBuilder builder;
  builder.network(tiny(3));
  const generator::MLIBuild a = builder.build(bundled(), quick({0, 4}));
  EXPECT_FALSE(a.reused);
  EXPECT_TRUE(hasStage(a, "to_mli"));
  EXPECT_EQ(a.views, (std::vector<int>{0, 4}));
  EXPECT_EQ(a.mli.numLayers(), 4);
  EXPECT_FALSE(a.output.has_value());

  const generator::MLIBuild b = builder.build(bundled(), quick({0, 4}));
  EXPECT_TRUE(b.reused);
  ASSERT_EQ(b.stageMs.size(), 1u);
  EXPECT_EQ(b.stageMs[0].first, "forward_reused");
  ASSERT_EQ(b.mli.layers.size(), a.mli.layers.size());
  for (std::size_t k = 0; k < a.mli.layers.size(); ++k) {
    EXPECT_EQ(b.mli.layers[k].rgba, a.mli.layers[k].rgba) << "layer " << k;
    EXPECT_EQ(b.mli.layers[k].depth, a.mli.layers[k].depth) << "layer " << k;
  }

  EXPECT_FALSE(builder.build(bundled(), quick({0, 5})).reused) << "other views";
  generator::MLIBuildOptions ranged = quick({0, 5});
  ranged.depthRange = generator::DepthRangeSource::Scene;
  EXPECT_FALSE(builder.build(bundled(), ranged).reused) << "other depth range";
  generator::MLIBuildOptions kept = quick({0, 5});
  kept.keepOutput = true;
  const generator::MLIBuild c = builder.build(bundled(), kept);
  EXPECT_FALSE(c.reused) << "keepOutput needs a pass";
  ASSERT_TRUE(c.output.has_value());
  EXPECT_EQ(c.output->rgba.size(0), 4);

  builder.network(tiny(4)); // another network: no reuse
  EXPECT_FALSE(builder.build(bundled(), quick({0, 5})).reused);
}

TEST(MLIBuilder, CancelledPassKeepsNothing) {
  generator::MLIBuilder builder;
  builder.network(tiny(5));
  builder.build(bundled(), quick({1, 2}));
  generator::MLIBuildOptions cancel = quick({1, 2});
  cancel.corrections = 1; // another pass, cancelled after its first stage
  cancel.progress = [](const std::string&, int, int) { return false; };
  EXPECT_THROW(builder.build(bundled(), cancel), generator::GeneratorCancelled);
  EXPECT_FALSE(builder.build(bundled(), quick({1, 2})).reused);
}

TEST(MLIBuilder, ErrorsNameTheProblem) {
  generator::MLIBuilder builder;
  test::expectError([&] { builder.build(bundled(), quick({0})); }, {"no network"});
  builder.network(tiny(6));
  test::expectError(
      [&] {
        builder.build(bundled(), quick({0, 99}));
      },
      {"source view 99", "out of range"});
  generator::NetworkSource missing;
  missing.weights = "/no/such/weights.safetensors";
  test::expectError([&] { builder.network(missing); }, {"no/such/weights.safetensors"});
  EXPECT_FALSE(builder.hasNetwork());
}

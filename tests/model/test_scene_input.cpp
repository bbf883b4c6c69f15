// Scene -> generator input: image layout, cameras, reference camera, view selection, depth
// range, and the errors for bad view lists. Uses the bundled synthetic scene.
#include "test_helpers.h"

#include <simpli/error.h>
#include <simpli/model/generator/scene_input.h>
#include <simpli/model/reference_camera.h>
#include <simpli/model/scene_readers.h>

#include <gtest/gtest.h>

using namespace simpli;

namespace {

const Scene& bundled() {
  static const Scene scene = readScene(std::string(SIMPLI_DATA_DIR) + "/synthetic/scene_00");
  return scene;
}

} // namespace

TEST(SceneInput, ChosenViewsInOrderWithTheirReferenceCamera) {
  const Scene& scene = bundled();
  ASSERT_GE(scene.size(), 5u);
  SceneInputOptions options;
  options.views = {4, 0, 2};
  const GeneratorInput in = sceneInput(scene, options);
  const int H = scene.height(), W = scene.width();
  ASSERT_EQ(in.images.shape(), (ocl::Shape{3, 3, H, W}));
  const std::vector<float> pixels = in.images.toVectorF32();
  const std::size_t plane = 3 * static_cast<std::size_t>(H) * W;
  for (std::size_t k = 0; k < options.views.size(); ++k) {
    const SceneView& view = scene.views[static_cast<std::size_t>(options.views[k])];
    EXPECT_TRUE(std::equal(view.image.data.begin(), view.image.data.end(),
                           pixels.begin() + static_cast<std::ptrdiff_t>(k * plane)))
        << "view " << options.views[k];
    EXPECT_TRUE(in.sources[k].R.isApprox(view.camera.R));
    EXPECT_TRUE(in.sources[k].t.isApprox(view.camera.t));
  }
  const Camera ref = referenceCamera(in.sources);
  EXPECT_TRUE(in.reference.R.isApprox(ref.R));
  EXPECT_TRUE(in.reference.t.isApprox(ref.t));
  EXPECT_EQ(in.reference.width, W);
  EXPECT_EQ(in.reference.height, H);
  // Config range by default (both 0), the scene's on request.
  EXPECT_EQ(in.minDepth, 0.0);
  EXPECT_EQ(in.maxDepth, 0.0);
  options.depthRange = DepthRangeSource::Scene;
  const GeneratorInput ranged = sceneInput(scene, options);
  EXPECT_DOUBLE_EQ(ranged.minDepth, scene.near);
  EXPECT_DOUBLE_EQ(ranged.maxDepth, scene.far);
  EXPECT_EQ(sceneInput(scene).images.size(0), static_cast<int64_t>(scene.size()));
}

TEST(SceneInput, BadViewListsNameTheSceneAndTheView) {
  const Scene& scene = bundled();
  SceneInputOptions options;
  options.views = {0, static_cast<int>(scene.size())};
  test::expectError([&] { sceneInput(scene, options); },
                    {"scene_00", "source view " + std::to_string(scene.size()), "out of range"});
  options.views = {1, 1};
  test::expectError([&] { sceneInput(scene, options); }, {"scene_00", "view 1", "twice"});
  options.views = {-1};
  test::expectError([&] { sceneInput(scene, options); }, {"view -1"});
  Scene empty;
  empty.root = "/nowhere/empty";
  test::expectError([&] { sceneInput(empty); }, {"/nowhere/empty", "no views"});
}

// Scene -> generator input: image layout, cameras, reference camera, view selection, depth
// range, and the errors for bad view lists. Uses the bundled synthetic scene.
#include "support/expect_error.h"

#include "simpli/error.h"
#include "simpli/model/generator/scene_input.h"
#include "simpli/model/io/image.h"
#include "simpli/model/scene/readers.h"
#include "simpli/model/scene/reference_camera.h"

#include <gtest/gtest.h>

using namespace simpli;

namespace {

const scene::Scene& bundled() {
  static const scene::Scene scene =
      scene::readScene(std::string(SIMPLI_DATA_DIR) + "/synthetic/scene_00");
  return scene;
}

} // namespace

TEST(SceneInput, ChosenViewsInOrderWithTheirReferenceCamera) {
  const scene::Scene& scene = bundled();
  ASSERT_GE(scene.size(), 5u);
  generator::SceneInputOptions options;
  options.views = {4, 0, 2};
  const generator::GeneratorInput in = generator::sceneInput(scene, options);
  const int H = scene.height(), W = scene.width();
  ASSERT_EQ(in.images.shape(), (ocl::Shape{3, 3, H, W}));
  const std::vector<float> pixels = in.images.toVectorF32();
  const std::size_t plane = 3 * static_cast<std::size_t>(H) * W;
  for (std::size_t k = 0; k < options.views.size(); ++k) {
    const scene::SceneView& view = scene.views[static_cast<std::size_t>(options.views[k])];
    EXPECT_TRUE(std::equal(view.image.data.begin(), view.image.data.end(),
                           pixels.begin() + static_cast<std::ptrdiff_t>(k * plane)))
        << "view " << options.views[k];
    EXPECT_TRUE(in.sources[k].R.isApprox(view.camera.R));
    EXPECT_TRUE(in.sources[k].t.isApprox(view.camera.t));
  }
  const scene::Camera ref = scene::referenceCamera(in.sources);
  EXPECT_TRUE(in.reference.R.isApprox(ref.R));
  EXPECT_TRUE(in.reference.t.isApprox(ref.t));
  EXPECT_EQ(in.reference.width, W);
  EXPECT_EQ(in.reference.height, H);
  // Config range by default (both 0), the scene's on request.
  EXPECT_EQ(in.minDepth, 0.0);
  EXPECT_EQ(in.maxDepth, 0.0);
  options.depthRange = generator::DepthRangeSource::Scene;
  const generator::GeneratorInput ranged = generator::sceneInput(scene, options);
  EXPECT_DOUBLE_EQ(ranged.minDepth, scene.near);
  EXPECT_DOUBLE_EQ(ranged.maxDepth, scene.far);
  EXPECT_EQ(generator::sceneInput(scene).images.size(0), static_cast<int64_t>(scene.size()));
}

TEST(SceneInput, BadViewListsNameTheSceneAndTheView) {
  const scene::Scene& scene = bundled();
  generator::SceneInputOptions options;
  options.views = {0, static_cast<int>(scene.size())};
  test::expectError([&] { generator::sceneInput(scene, options); },
                    {"scene_00", "source view " + std::to_string(scene.size()), "out of range"});
  options.views = {1, 1};
  test::expectError([&] { generator::sceneInput(scene, options); },
                    {"scene_00", "view 1", "twice"});
  options.views = {-1};
  test::expectError([&] { generator::sceneInput(scene, options); }, {"view -1"});
  scene::Scene empty;
  empty.root = "/nowhere/empty";
  test::expectError([&] { generator::sceneInput(empty); }, {"/nowhere/empty", "no views"});
}

// InputScale: the images are io::resizeImage's at scaledSize(size, scale), the cameras keep their
// pose and relative intrinsics with the new size, and so does the reference camera.
TEST(SceneInput, InputScaleResizesTheImagesAndTheCameras) {
  const scene::Scene& scene = bundled();
  generator::SceneInputOptions options;
  options.views = {1, 3};
  const generator::GeneratorInput full = generator::sceneInput(scene, options);
  options.inputScale = 0.5;
  const generator::GeneratorInput half = generator::sceneInput(scene, options);
  const int h = generator::scaledSize(scene.height(), 0.5);
  const int w = generator::scaledSize(scene.width(), 0.5);
  EXPECT_EQ(w, scene.width() / 2); // 192x128: already multiples of 32
  ASSERT_EQ(half.images.shape(), (ocl::Shape{2, 3, h, w}));
  const std::vector<float> pixels = half.images.toVectorF32();
  for (std::size_t k = 0; k < 2; ++k) {
    const io::Image small =
        io::resizeImage(scene.views[static_cast<std::size_t>(options.views[k])].image, w, h);
    EXPECT_TRUE(std::equal(small.data.begin(), small.data.end(),
                           pixels.begin() + static_cast<std::ptrdiff_t>(k * small.data.size())))
        << k;
    EXPECT_EQ(half.sources[k].width, w);
    EXPECT_EQ(half.sources[k].height, h);
    EXPECT_EQ(half.sources[k].relativeK(), full.sources[k].relativeK());
    EXPECT_EQ(half.sources[k].R, full.sources[k].R);
    EXPECT_EQ(half.sources[k].t, full.sources[k].t);
  }
  EXPECT_EQ(half.reference.width, w);
  EXPECT_EQ(half.reference.height, h);
  EXPECT_TRUE(half.reference.R.isApprox(full.reference.R));
  EXPECT_EQ(half.reference.relativeK(), full.reference.relativeK());
  // 1 leaves them as they are; a non-multiple of 16 rounds to the nearest one.
  EXPECT_EQ(generator::scaledSize(378, 0.5), 192);
  for (double bad : {0.0, -1.0, 2.5})
    test::expectError(
        [&] {
          options.inputScale = bad;
          generator::sceneInput(scene, options);
        },
        {"input scale", "(0, 2]"});
}

// scaledInput, which sceneInput and the evaluation's sampleInput share, names what does not fit.
TEST(SceneInput, ScaledInputNamesMismatchedImagesAndCameras) {
  const scene::Scene& scene = bundled();
  const io::Image other(scene.width() / 2, scene.height());
  const std::vector<const io::Image*> mixed = {&scene.views[0].image, &other};
  const std::vector<scene::Camera> two = {scene.views[0].camera, scene.views[1].camera};
  test::expectError([&] { generator::scaledInput(mixed, two, two[0], 1.0, ocl::Dtype::F32); },
                    {"images of different sizes", std::to_string(scene.width() / 2)});
  const std::vector<const io::Image*> one = {&scene.views[0].image};
  test::expectError([&] { generator::scaledInput(one, two, two[0], 0.5, ocl::Dtype::F32); },
                    {"1 images for 2 cameras"});
  test::expectError([&] { generator::scaledInput({}, {}, two[0], 1.0, ocl::Dtype::F32); },
                    {"0 images for 0 cameras"});
}

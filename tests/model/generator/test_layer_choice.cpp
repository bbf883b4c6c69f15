// generator::chooseLayers (`--layers auto`): the fewest layers within the PSNR margin on the
// given views, by backward elimination.
#include "support/expect_error.h"

#include "simpli/model/generator/layer_choice.h"
#include "simpli/model/raster/render_mli.h"
#include "simpli/ocl/autograd.h"

#include <gtest/gtest.h>

namespace simpli {
namespace {

// Three constant layers over the whole reference view: an opaque back layer, a faint one
// (alpha `faint`) and a strong one (alpha 0.8), each its own colour.
mli::MLI threeLayers(float faint) {
  scene::Camera ref;
  ref.fx = 1.0;
  ref.fy = 1.5;
  ref.width = 48;
  ref.height = 32;
  mli::MLI m = mli::MLI::allocate(ref, 3);
  const float depth[3] = {10.0f, 5.0f, 2.0f}, alpha[3] = {1.0f, faint, 0.8f};
  const float colour[3][3] = {{0.2f, 0.4f, 0.6f}, {0.9f, 0.9f, 0.1f}, {0.1f, 0.8f, 0.3f}};
  for (int k = 0; k < 3; ++k)
    for (std::size_t p = 0; p < m.texels(); ++p) {
      m.layers[k].depth[p] = depth[k];
      for (int c = 0; c < 3; ++c)
        m.layers[k].rgba[4 * p + c] = colour[k][c];
      m.layers[k].rgba[4 * p + 3] = alpha[k];
    }
  return m;
}

// The "photo" of a view: the MLI's own render, as an io::Image in [-1, 1].
io::Image photo(const mli::MLI& m, const scene::Camera& c) {
  ocl::NoGradGuard noGrad;
  const std::vector<float> v = raster::renderMLI(m, c).colour.toVectorF32();
  io::Image image(c.width, c.height);
  // Plus a +-0.02 checkerboard, zero-mean, so that the full MLI's PSNR is finite (~34 dB) and
  // any change of the render makes it worse.
  const std::size_t n = static_cast<std::size_t>(c.width) * c.height;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::size_t p = i % n, x = p % c.width, y = p / c.width;
    image.data[i] = 2.0f * (v[i] + ((x + y) % 2 ? 0.02f : -0.02f)) - 1.0f;
  }
  return image;
}

TEST(LayerChoice, DropsWhatCostsLessThanTheMarginAndKeepsTheRest) {
  const mli::MLI m = threeLayers(0.002f);
  const std::vector<scene::Camera> cameras{m.camera};
  const std::vector<io::Image> images{photo(m, m.camera)};
  const generator::LayerChoice choice = generator::chooseLayers(m, cameras, images);
  // The faint layer (0.2 % of a colour difference) goes; the back layer and the strong one
  // (which makes up 80 % of the colour) stay.
  EXPECT_EQ(choice.kept, (std::vector<int>{0, 2}));
  EXPECT_EQ(choice.mli.numLayers(), 2);
  EXPECT_GE(choice.chosenPsnr, choice.fullPsnr - 0.2);
  EXPECT_GT(choice.renders, 1);
}

TEST(LayerChoice, KeepsEveryLayerThatMattersAndAMarginOfZeroKeepsAll) {
  const mli::MLI m = threeLayers(0.5f);
  const std::vector<scene::Camera> cameras{m.camera};
  const std::vector<io::Image> images{photo(m, m.camera)};
  EXPECT_EQ(generator::chooseLayers(m, cameras, images).kept, (std::vector<int>{0, 1, 2}));
  generator::LayerChoiceOptions strict;
  strict.maxLossDb = 0;
  const mli::MLI faint = threeLayers(0.002f);
  const std::vector<io::Image> faintImages{photo(faint, faint.camera)};
  EXPECT_EQ(generator::chooseLayers(faint, cameras, faintImages, strict).kept.size(), 3u);
}

TEST(LayerChoice, BadInputIsANamedError) {
  const mli::MLI m = threeLayers(0.5f);
  test::expectError([&] { generator::chooseLayers(m, {m.camera}, {}); },
                    {"meanQualityOfMLI", "1 cameras and 0 images"});
  generator::LayerChoiceOptions bad;
  bad.maxLossDb = -1;
  test::expectError([&] { generator::chooseLayers(m, {m.camera}, {photo(m, m.camera)}, bad); },
                    {"PSNR margin -1 dB"});
}

} // namespace
} // namespace simpli

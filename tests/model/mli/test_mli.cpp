// The MLI type: allocation, validation messages, empty-layer report.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "mli_test_util.h"
#include "simpli/error.h"
#include "simpli/model/mli/mli.h"

namespace simpli::test {
namespace {

TEST(MLIData, AllocateSizesEveryLayerFromTheCamera) {
  const mli::MLI mli = mli::MLI::allocate(generalCamera(7, 5), 3);
  EXPECT_EQ(mli.numLayers(), 3);
  EXPECT_EQ(mli.width(), 7);
  EXPECT_EQ(mli.height(), 5);
  for (const mli::MLILayer& layer : mli.layers) {
    EXPECT_EQ(layer.depth.size(), 35u);
    EXPECT_EQ(layer.rgba.size(), 140u);
  }
  EXPECT_NO_THROW(mli::validateMLI(mli));
}

TEST(MLIData, ValidMLIPasses) {
  EXPECT_NO_THROW(mli::validateMLI(randomMLI(2, 4, 6, 1)));
}

TEST(MLIData, RejectsNoLayers) {
  mli::MLI mli = randomMLI(1, 4, 4, 2);
  mli.layers.clear();
  expectError([&] { mli::validateMLI(mli, "ctx"); }, {"ctx", "no layers"});
}

TEST(MLIData, RejectsTooSmallForTheCornerGrid) {
  const mli::MLI mli = mli::MLI::allocate(generalCamera(1, 4), 1);
  expectError([&] { mli::validateMLI(mli, "ctx"); }, {"ctx", "4 x 1", "at least 2 x 2"});
}

TEST(MLIData, RejectsWrongVectorSizes) {
  mli::MLI mli = randomMLI(2, 4, 5, 3);
  mli.layers[1].depth.pop_back();
  expectError([&] { mli::validateMLI(mli, "ctx"); }, {"ctx: layer 1", "depth has 19 values", "20"});
  mli = randomMLI(2, 4, 5, 3);
  mli.layers[0].rgba.push_back(0.5f);
  expectError([&] { mli::validateMLI(mli, "ctx"); }, {"layer 0", "rgba has 81 values", "80"});
}

TEST(MLIData, RejectsBadDepthValues) {
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), 0.0f, -2.0f,
                    std::numeric_limits<float>::infinity()}) {
    mli::MLI mli = randomMLI(2, 4, 5, 4);
    mli.layers[1].depth[2 * 5 + 3] = bad;
    expectError([&] { mli::validateMLI(mli, "ctx"); },
                {"ctx: layer 1", "depth at (row 2, col 3)", "finite and > 0"});
  }
}

TEST(MLIData, RejectsBadRgbaValues) {
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), 1.5f, -0.25f}) {
    mli::MLI mli = randomMLI(2, 4, 5, 5);
    mli.layers[0].rgba[4 * (1 * 5 + 4) + 3] = bad; // alpha of (1, 4)
    expectError([&] { mli::validateMLI(mli, "ctx"); },
                {"layer 0", "rgba A at (row 1, col 4)", "[0, 1]"});
  }
  mli::MLI mli = randomMLI(1, 4, 5, 5);
  mli.layers[0].rgba[1] = 2.0f;
  expectError([&] { mli::validateMLI(mli); }, {"rgba G at (row 0, col 0) = 2"});
}

TEST(MLIData, RejectsBadCameras) {
  mli::MLI mli = randomMLI(1, 4, 4, 6);
  mli.camera.fx = 0.0;
  expectError([&] { mli::validateMLI(mli); }, {"focal", "> 0"});
  mli = randomMLI(1, 4, 4, 6);
  mli.camera.cy = std::nan("");
  expectError([&] { mli::validateMLI(mli); }, {"cy", "not finite"});
  mli = randomMLI(1, 4, 4, 6);
  mli.camera.R *= 1.01;
  expectError([&] { mli::validateMLI(mli); }, {"not a rotation"});
  mli = randomMLI(1, 4, 4, 6);
  mli.camera.R.row(0) *= -1.0;
  expectError([&] { mli::validateMLI(mli); }, {"determinant", "reflection"});
  mli = randomMLI(1, 4, 4, 6);
  mli.camera.t.y() = std::numeric_limits<double>::infinity();
  expectError([&] { mli::validateMLI(mli); }, {"translation", "not finite"});
}

TEST(MLIData, EmptyLayersAreThoseWithoutVisibleAlpha) {
  mli::MLI mli = randomMLI(3, 4, 4, 7);
  for (std::size_t e = 3; e < mli.layers[1].rgba.size(); e += 4)
    mli.layers[1].rgba[e] = 0.001f;
  EXPECT_FLOAT_EQ(mli::maxAlpha(mli.layers[1]), 0.001f);
  EXPECT_EQ(mli::emptyLayers(mli), std::vector<int>{1});
  EXPECT_TRUE(mli::emptyLayers(mli, 0.0005f).empty());
  mli.layers[2].rgba[4 * 7 + 3] = 0.9f; // one visible texel keeps a layer
  for (std::size_t e = 3; e < mli.layers[2].rgba.size(); e += 4)
    if (e != 4 * 7 + 3)
      mli.layers[2].rgba[e] = 0.0f;
  EXPECT_EQ(mli::emptyLayers(mli), std::vector<int>{1});
}

} // namespace
} // namespace simpli::test

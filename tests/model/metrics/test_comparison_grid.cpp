// Error maps and side-by-side rows: exact pixel values on hand-made images, bad input.
#include "support/expect_error.h"

#include "simpli/model/metrics/comparison_grid.h"

#include <gtest/gtest.h>

using namespace simpli;
using simpli::test::expectError;

namespace {
io::Image filled(int w, int h, float r, float g, float b) {
  io::Image im(w, h);
  const float v[3] = {r, g, b};
  for (int c = 0; c < 3; ++c)
    std::fill(im.plane(c), im.plane(c) + w * h, v[c]);
  return im;
}
} // namespace

TEST(ErrorMap, MapsMeanAbsoluteErrorOntoTheHotRamp) {
  // io::Image values are in [-1, 1]; errors are measured on the [0, 1] scale.
  const io::Image truth = filled(3, 2, 0.2f, -0.4f, 0.6f);
  io::Image render = truth;
  render.at(0, 0, 1) += 0.3f; // [0, 1] error 0.15 in one channel: mean 0.05 -> e = 0.2
  for (int c = 0; c < 3; ++c)
    render.at(c, 1, 2) = -1.0f; // mean [0, 1] error 0.5 -> e = 1 (white, clamped)
  const io::Image map = metrics::errorMap(render, truth, 4.0);
  ASSERT_EQ(map.width, 3);
  ASSERT_EQ(map.height, 2);
  EXPECT_NEAR(map.at(0, 0, 1), 2 * 0.6f - 1, 1e-5); // red 0.6 of the ramp
  EXPECT_EQ(map.at(1, 0, 1), -1.0f);
  EXPECT_EQ(map.at(2, 0, 1), -1.0f);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(map.at(c, 1, 2), 1.0f);
    EXPECT_EQ(map.at(c, 0, 0), -1.0f); // no error: black
  }
}

TEST(ErrorMap, RejectsDifferentSizesAndBadGain) {
  expectError([] { metrics::errorMap(io::Image(3, 2), io::Image(2, 3)); }, {"differ in size"});
  expectError([] { metrics::errorMap(io::Image(2, 2), io::Image(2, 2), 0.0); }, {"gain 0"});
}

TEST(SideBySide, PlacesImagesWithWhiteGaps) {
  const io::Image a = filled(2, 2, 0.1f, 0.2f, 0.3f), b = filled(2, 2, 0.7f, 0.8f, 0.9f);
  const io::Image row = metrics::sideBySide({&a, &b}, 1);
  ASSERT_EQ(row.width, 5);
  ASSERT_EQ(row.height, 2);
  for (int y = 0; y < 2; ++y) {
    EXPECT_EQ(row.at(0, y, 1), 0.1f);
    EXPECT_EQ(row.at(1, y, 2), 1.0f); // the gap
    EXPECT_EQ(row.at(2, y, 3), 0.9f);
  }
}

TEST(SideBySide, RejectsMismatchedSizes) {
  const io::Image a(2, 2), b(3, 2);
  expectError([&] { metrics::sideBySide({&a, &b}); }, {"image 1 is 3x2"});
  expectError([] { metrics::sideBySide({}); }, {"no images"});
}

#include "support/mli_compare.h"

#include <gtest/gtest.h>

#include <cstring>

namespace simpli::test {

void expectSameMLI(const mli::MLI& a, const mli::MLI& b) {
  ASSERT_EQ(a.numLayers(), b.numLayers());
  EXPECT_EQ(a.camera.R, b.camera.R);
  EXPECT_EQ(a.camera.t, b.camera.t);
  EXPECT_EQ(a.camera.fx, b.camera.fx);
  EXPECT_EQ(a.camera.fy, b.camera.fy);
  EXPECT_EQ(a.camera.cx, b.camera.cx);
  EXPECT_EQ(a.camera.cy, b.camera.cy);
  EXPECT_EQ(a.width(), b.width());
  EXPECT_EQ(a.height(), b.height());
  for (std::size_t k = 0; k < a.layers.size(); ++k) {
    const mli::MLILayer &x = a.layers[k], &y = b.layers[k];
    ASSERT_EQ(x.depth.size(), y.depth.size()) << "layer " << k;
    ASSERT_EQ(x.rgba.size(), y.rgba.size()) << "layer " << k;
    EXPECT_EQ(std::memcmp(x.depth.data(), y.depth.data(), x.depth.size() * sizeof(float)), 0)
        << "layer " << k << " depth";
    EXPECT_EQ(std::memcmp(x.rgba.data(), y.rgba.data(), x.rgba.size() * sizeof(float)), 0)
        << "layer " << k << " rgba";
  }
}

} // namespace simpli::test

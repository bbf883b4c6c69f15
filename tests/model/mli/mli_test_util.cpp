#include "mli_test_util.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "simpli/error.h"

namespace simpli::test {

scene::Camera generalCamera(int W, int H) {
  scene::Camera c;
  c.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, -1.0, 0.4).normalized()).toRotationMatrix();
  c.t = Eigen::Vector3d(0.7, -1.3, 2.1);
  c.fx = 0.92;
  c.fy = 1.23;
  c.cx = 0.47;
  c.cy = 0.4167; // off-centre like the reference's new8_mli scene
  c.width = W;
  c.height = H;
  return c;
}

mli::MLI randomMLI(int L, int H, int W, unsigned seed, float dmin, float dmax) {
  mli::MLI mli = mli::MLI::allocate(generalCamera(W, H), L);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> depth(dmin, dmax), unit(0.0f, 1.0f);
  for (mli::MLILayer& layer : mli.layers) {
    for (float& d : layer.depth)
      d = depth(rng);
    for (float& v : layer.rgba)
      v = unit(rng);
  }
  return mli;
}

mli::MLI smoothMLI(int L, int H, int W) {
  mli::MLI mli = mli::MLI::allocate(generalCamera(W, H), L);
  for (int k = 0; k < L; ++k) {
    mli::MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
    const double base = 10.0 / (k + 1); // back layers farther, as in an MLI
    for (int i = 0; i < H; ++i)
      for (int j = 0; j < W; ++j) {
        const std::size_t p = static_cast<std::size_t>(i) * W + j;
        const double x = static_cast<double>(j) / W, y = static_cast<double>(i) / H;
        layer.depth[p] = static_cast<float>(base * (1.0 + 0.3 * std::sin(3 * x + 2 * y + k)));
        float* rgba = &layer.rgba[4 * p];
        rgba[0] = static_cast<float>(0.5 + 0.4 * std::sin(2 * x + k));
        rgba[1] = static_cast<float>(0.5 + 0.4 * std::cos(3 * y));
        rgba[2] = static_cast<float>(0.5 + 0.4 * std::sin(2 * x + 3 * y));
        rgba[3] = static_cast<float>(0.5 + 0.45 * std::cos(2 * x - y + k));
      }
  }
  return mli;
}

} // namespace simpli::test

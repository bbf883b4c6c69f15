#include "raster_test_util.h"

#include <cmath>

namespace simpli::test {

LayerScene randomScene(int L, int H, int W, int A, double bump, unsigned seed, double alphaLo,
                       double alphaHi) {
  LayerScene s;
  s.L = L;
  s.H = H;
  s.W = W;
  s.A = A;
  const std::size_t texels = std::size_t(H) * W;
  const std::vector<double> unit = randomValues(L * texels, -1.0, 1.0, seed);
  s.depth.resize(L * texels);
  for (int k = 0; k < L; ++k) {
    const double base = 8.0 / (1.0 + 0.6 * k); // layer 0 farthest
    for (std::size_t p = 0; p < texels; ++p)
      s.depth[k * texels + p] = base * (1.0 + bump * unit[k * texels + p]);
  }
  s.attrs = randomValues(std::size_t(L) * A * texels, 0.0, 1.0, seed + 1);
  const std::vector<double> alpha = randomValues(L * texels, alphaLo, alphaHi, seed + 2);
  for (int k = 0; k < L; ++k)
    for (std::size_t p = 0; p < texels; ++p)
      s.attrs[(std::size_t(k) * A + A - 1) * texels + p] = alpha[k * texels + p];
  s.reference = testReferenceCamera(W, H);
  return s;
}

LayerScene flatScene(const std::vector<double>& depths, int H, int W, int A, unsigned seed) {
  LayerScene s = randomScene(static_cast<int>(depths.size()), H, W, A, 0.0, seed);
  const std::size_t texels = std::size_t(H) * W;
  for (std::size_t k = 0; k < depths.size(); ++k)
    for (std::size_t p = 0; p < texels; ++p)
      s.depth[k * texels + p] = depths[k];
  return s;
}

scene::Camera testReferenceCamera(int W, int H) {
  return makeCamera(0.9, 1.2, 0.47, 0.53, W, H, smallRotation(7.0, 11),
                    Eigen::Vector3d(0.3, -0.2, 0.5));
}

bool allFinite(const std::vector<double>& values) {
  for (double v : values)
    if (!std::isfinite(v))
      return false;
  return true;
}

} // namespace simpli::test

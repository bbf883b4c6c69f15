// The reprojection error of an adaptive mesh against its layer (mli/adaptive_mesh.h),
// computed from the mesh alone (grid positions, depths, triangles), not from the builder.
#include "simpli/model/mli/adaptive_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "simpli/error.h"

namespace simpli::mli {

AdaptiveMeshError measureAdaptiveMesh(const MLI& mli, int k, const AdaptiveLayerMesh& mesh,
                                      const AdaptiveMeshOptions& options) {
  validateMLI(mli, "measureAdaptiveMesh");
  validateAdaptiveMeshOptions(options);
  if (k < 0 || k >= mli.numLayers())
    fail("measureAdaptiveMesh: layer index ", k, " is out of range [0, ", mli.numLayers(), ")");
  const std::size_t n = mesh.numPoints();
  if (mesh.grid.size() != 2 * n || mesh.points.size() != 3 * n || mesh.triangles.size() % 3)
    fail("measureAdaptiveMesh: inconsistent mesh (", n, " depths, ", mesh.grid.size() / 2,
         " grid positions, ", mesh.points.size() / 3, " points, ", mesh.triangles.size(),
         " triangle indices)");
  const int W = mli.width(), H = mli.height();
  const MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
  const double scale = pixelsPerInverseDepth(mli, options);
  std::vector<double> worst(mli.texels(), -1.0); // -1: not covered
  std::vector<double> swim(mli.texels(), 0.0);

  for (std::size_t t = 0; t < mesh.numTriangles(); ++t) {
    double gx[3], gy[3], disparity[3];
    for (int c = 0; c < 3; ++c) {
      const std::int32_t v = mesh.triangles[3 * t + c];
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        fail("measureAdaptiveMesh: triangle ", t, " refers to vertex ", v, " of ", n);
      gx[c] = mesh.grid[2 * static_cast<std::size_t>(v)];
      gy[c] = mesh.grid[2 * static_cast<std::size_t>(v) + 1];
      disparity[c] = 1.0 / static_cast<double>(mesh.depth[static_cast<std::size_t>(v)]);
    }
    const double area = (gx[1] - gx[0]) * (gy[2] - gy[0]) - (gx[2] - gx[0]) * (gy[1] - gy[0]);
    if (area == 0)
      continue;
    const int x0 = std::max(0, static_cast<int>(std::ceil(std::min({gx[0], gx[1], gx[2]}))));
    const int x1 = std::min(W - 1, static_cast<int>(std::floor(std::max({gx[0], gx[1], gx[2]}))));
    const int y0 = std::max(0, static_cast<int>(std::ceil(std::min({gy[0], gy[1], gy[2]}))));
    const int y1 = std::min(H - 1, static_cast<int>(std::floor(std::max({gy[0], gy[1], gy[2]}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        // Barycentrics; grid positions are multiples of 1/2, so these are exact.
        double b[3];
        for (int c = 0; c < 3; ++c) {
          const int a1 = (c + 1) % 3, a2 = (c + 2) % 3;
          b[c] = ((gx[a2] - gx[a1]) * (y - gy[a1]) - (gy[a2] - gy[a1]) * (x - gx[a1])) / area;
        }
        if (b[0] < 0 || b[1] < 0 || b[2] < 0)
          continue;
        const std::size_t p = static_cast<std::size_t>(y) * W + x;
        const double surface = b[0] * disparity[0] + b[1] * disparity[1] + b[2] * disparity[2];
        const double e = scale * std::abs(1.0 / static_cast<double>(layer.depth[p]) - surface);
        worst[p] = std::max(worst[p], e);
        // The texture coordinate a renderer interpolates at this surface point.
        double sx = 0, sy = 0;
        for (int c = 0; c < 3; ++c) {
          const double l = b[c] * disparity[c] / surface;
          sx += l * gx[c];
          sy += l * gy[c];
        }
        swim[p] = std::max(swim[p], std::hypot(sx - x, sy - y));
      }
  }

  AdaptiveMeshError out;
  for (std::size_t p = 0; p < mli.texels(); ++p) {
    if (!(layer.rgba[4 * p + 3] >= options.alphaThreshold))
      continue;
    ++out.visibleTexels;
    if (worst[p] < 0)
      ++out.uncoveredVisibleTexels;
    else
      out.maxPixels = std::max(out.maxPixels, worst[p]);
    out.maxTextureSwim = std::max(out.maxTextureSwim, swim[p]);
  }
  return out;
}

} // namespace simpli::mli

// Cross-check with the MPI renderer (geometry/mpi_render.h): flat MLI layers with constant
// colour and alpha are the MPI's planes, so both renderers must agree wherever the pixel ray
// meets every plane well inside the reference frustum (away from the MPI's half-pixel fade band
// and from the mesh boundary, the only places where the two representations differ).
#include "raster_test_util.h"

#include "simpli/model/geometry/mpi_render.h"
#include "simpli/model/raster/rasterizer.h"

#include <gtest/gtest.h>

#include <cmath>

namespace simpli::test {
namespace {

using ocl::Dtype;
using ocl::Tensor;

TEST(RasterMpi, FlatConstantLayersMatchTheMpiRender) {
  const std::vector<double> planes{9.0, 5.0, 3.0}; // index 0 = back, as in the MPI
  const double rgba[3][4] = {{0.9, 0.2, 0.1, 0.6}, {0.1, 0.7, 0.3, 0.4}, {0.2, 0.3, 0.8, 0.7}};
  const int P = 3, h = 8, w = 10;
  const int H = 6, W = 7; // any mesh resolution: constant layers
  const int Ht = 30, Wt = 40;
  scene::Camera ref = testReferenceCamera(w, h);
  const scene::Camera target =
      makeCamera(1.0, 1.25, 0.5, 0.48, Wt, Ht, smallRotation(4.0, 21) * ref.R,
                 ref.t + Eigen::Vector3d(0.3, -0.2, 0.4));

  std::vector<double> mpi(std::size_t(P) * 4 * h * w), depth(std::size_t(P) * H * W),
      attrs(std::size_t(P) * 4 * H * W);
  for (int p = 0; p < P; ++p)
    for (int c = 0; c < 4; ++c) {
      for (int i = 0; i < h * w; ++i)
        mpi[(std::size_t(p) * 4 + c) * h * w + i] = rgba[p][c];
      for (int i = 0; i < H * W; ++i)
        attrs[(std::size_t(p) * 4 + c) * H * W + i] = rgba[p][c];
    }
  for (int p = 0; p < P; ++p)
    for (int i = 0; i < H * W; ++i)
      depth[std::size_t(p) * H * W + i] = planes[p];

  const geometry::MpiRendering m = geometry::renderMpi(
      Tensor::fromHost(mpi, {P, 4, h, w}, Dtype::F32), planes, ref, {target}, Ht, Wt);
  const raster::RenderedLayers r =
      raster::renderLayers(Tensor::fromHost(depth, {P, H, W}, Dtype::F32),
                           Tensor::fromHost(attrs, {P, 4, H, W}, Dtype::F32), ref, target);
  const std::vector<double> mc = m.color.toVector(), mo = m.opacity.toVector();
  const std::vector<double> rc = r.colour.toVector(), ro = r.opacity.toVector();
  ASSERT_EQ(mc.size(), rc.size());

  // Ray of each target pixel, in reference-camera coordinates.
  const Eigen::Matrix3d toRef = ref.R * target.R.transpose();
  const Eigen::Vector3d centre = ref.worldToCamera(target.centre());
  const std::size_t plane = std::size_t(Ht) * Wt;
  int compared = 0;
  for (int row = 0; row < Ht; ++row)
    for (int col = 0; col < Wt; ++col) {
      const double ut = (col + 0.5) / Wt, vt = (row + 0.5) / Ht;
      const Eigen::Vector3d dir =
          toRef * Eigen::Vector3d((ut - target.cx) / target.fx, (vt - target.cy) / target.fy, 1);
      bool inside = true;
      for (double d : planes) {
        const double lambda = (d - centre.z()) / dir.z();
        const Eigen::Vector3d X = centre + lambda * dir;
        const double u = ref.fx * X.x() / X.z() + ref.cx, v = ref.fy * X.y() / X.z() + ref.cy;
        inside = inside && lambda > 0 && u > 1.5 / w && u < 1 - 1.5 / w && v > 1.5 / h &&
                 v < 1 - 1.5 / h;
      }
      if (!inside)
        continue;
      ++compared;
      const std::size_t pix = std::size_t(row) * Wt + col;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(rc[c * plane + pix], mc[c * plane + pix], 1e-5) << row << "," << col;
      ASSERT_NEAR(ro[pix], mo[pix], 1e-5) << row << "," << col;
    }
  EXPECT_GT(compared, static_cast<int>(plane / 4));
}

} // namespace
} // namespace simpli::test

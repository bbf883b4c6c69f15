// Corner-grid meshes of MLI layers (spec §6.6; see mli/mesh.h).
#include "simpli/model/mli/mesh.h"

#include <limits>

#include "simpli/error.h"

namespace simpli::mli {

namespace {

// Appends layer k's vertices to `mesh` and its triangles with indices offset by `base`.
void appendLayer(const MLI& mli, int k, std::int64_t base, const MLIMeshOptions& options,
                 MLIMesh& mesh) {
  const int H = mli.height(), W = mli.width();
  const MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
  const scene::Camera& cam = mli.camera;
  const Eigen::Matrix3d Rt = cam.R.transpose();

  for (int i = 0; i < H; ++i) {
    const double v = static_cast<double>(i) / (H - 1);
    for (int j = 0; j < W; ++j) {
      const double u = static_cast<double>(j) / (W - 1);
      const std::size_t p = static_cast<std::size_t>(i) * W + j;
      const double d = layer.depth[p];
      // Same arithmetic as mliVertex, inlined to keep R^T out of the per-texel loop.
      const Eigen::Vector3d xc(d * ((u - cam.cx) / cam.fx), d * ((v - cam.cy) / cam.fy), d);
      const Eigen::Vector3d xw = Rt * (xc - cam.t);
      mesh.points.insert(mesh.points.end(), {static_cast<float>(xw.x()), static_cast<float>(xw.y()),
                                             static_cast<float>(xw.z())});
      mesh.uv.insert(mesh.uv.end(), {static_cast<float>(u), static_cast<float>(v)});
    }
  }
  mesh.depth.insert(mesh.depth.end(), layer.depth.begin(), layer.depth.end());
  mesh.rgba.insert(mesh.rgba.end(), layer.rgba.begin(), layer.rgba.end());

  const float cut = options.dropAlphaBelow;
  auto transparent = [&](std::size_t p) { return layer.rgba[4 * p + 3] < cut; };
  auto push = [&](std::size_t a, std::size_t b, std::size_t c) {
    if (transparent(a) && transparent(b) && transparent(c))
      return;
    mesh.triangles.insert(mesh.triangles.end(),
                          {static_cast<std::int32_t>(base + a), static_cast<std::int32_t>(base + b),
                           static_cast<std::int32_t>(base + c)});
  };
  for (int i = 0; i + 1 < H; ++i)
    for (int j = 0; j + 1 < W; ++j) {
      const std::size_t b = static_cast<std::size_t>(i) * W + j;
      push(b, b + W, b + W + 1);
      push(b, b + W + 1, b + 1);
    }
}

void reserve(MLIMesh& mesh, std::size_t vertices, std::size_t triangles) {
  mesh.points.reserve(3 * vertices);
  mesh.rgba.reserve(4 * vertices);
  mesh.depth.reserve(vertices);
  mesh.uv.reserve(2 * vertices);
  mesh.triangles.reserve(3 * triangles);
}

void checkIndexRange(const MLI& mli, std::size_t vertices) {
  // Indices are int32 (what the OpenCL rasteriser and VTK's 32-bit cell arrays take).
  if (vertices > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    fail("MLI mesh: ", mli.numLayers(), " layers of ", mli.height(), " x ", mli.width(), " = ",
         vertices, " vertices exceed the int32 index range");
}

} // namespace

Eigen::Vector3d mliVertex(const scene::Camera& camera, int i, int j, double d) {
  const double u = static_cast<double>(j) / (camera.width - 1);
  const double v = static_cast<double>(i) / (camera.height - 1);
  const Eigen::Vector3d xc(d * ((u - camera.cx) / camera.fx), d * ((v - camera.cy) / camera.fy), d);
  return camera.R.transpose() * (xc - camera.t);
}

MLIMesh buildMLIMesh(const MLI& mli, const MLIMeshOptions& options) {
  validateMLI(mli, "buildMLIMesh");
  const std::size_t n = mli.texels();
  const std::size_t L = mli.layers.size();
  checkIndexRange(mli, n * L);
  MLIMesh mesh;
  reserve(mesh, n * L, L * 2 * static_cast<std::size_t>(mli.height() - 1) * (mli.width() - 1));
  for (int k = 0; k < mli.numLayers(); ++k)
    appendLayer(mli, k, static_cast<std::int64_t>(k) * static_cast<std::int64_t>(n), options, mesh);
  return mesh;
}

MLIMesh buildLayerMesh(const MLI& mli, int k, const MLIMeshOptions& options) {
  validateMLI(mli, "buildLayerMesh");
  if (k < 0 || k >= mli.numLayers())
    fail("buildLayerMesh: layer index ", k, " is out of range [0, ", mli.numLayers(), ")");
  checkIndexRange(mli, mli.texels());
  MLIMesh mesh;
  reserve(mesh, mli.texels(), 2 * static_cast<std::size_t>(mli.height() - 1) * (mli.width() - 1));
  appendLayer(mli, k, 0, options, mesh);
  return mesh;
}

} // namespace simpli::mli

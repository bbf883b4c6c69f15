// OpenCL rendering of the adaptive display form (raster/render_adaptive.h): host-side
// projection and tile binning, one shading pass (model/kernels/raster_adaptive.cl).
#include "simpli/model/raster/render_adaptive.h"

#include "model_kernels.h"
#include "raster/camera.h"
#include "simpli/error.h"
#include "simpli/model/raster/render_mli.h"

#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_shape.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace simpli::raster {

namespace {

constexpr const char* kOp = "renderAdaptiveMLI";
constexpr int kTriStride = 15;       // TRI_STRIDE in raster_adaptive.cl
constexpr double kGuard = 4194304.0; // 2^22 pixels, as the rasterizer's fixed-point range

void checkMesh(const mli::MLI& mli, int k, const mli::AdaptiveLayerMesh& m) {
  const std::size_t n = m.numPoints();
  if (m.grid.size() != 2 * n || m.points.size() != 3 * n || m.triangles.size() % 3)
    fail(kOp, ": layer ", k, ": inconsistent mesh (", n, " depths, ", m.grid.size() / 2,
         " grid positions, ", m.points.size() / 3, " points, ", m.triangles.size(),
         " triangle indices)");
  for (std::size_t v = 0; v < n; ++v)
    if (!(m.grid[2 * v] >= 0 && m.grid[2 * v] <= mli.width() - 1 && m.grid[2 * v + 1] >= 0 &&
          m.grid[2 * v + 1] <= mli.height() - 1))
      fail(kOp, ": layer ", k, ": vertex ", v, " at grid position (", m.grid[2 * v], ", ",
           m.grid[2 * v + 1], ") is outside the ", mli.width(), " x ", mli.height(), " grid");
  for (std::int32_t v : m.triangles)
    if (v < 0 || static_cast<std::size_t>(v) >= n)
      fail(kOp, ": layer ", k, ": a triangle refers to vertex ", v, " of ", n);
}

// Triangles in the target camera, in layer order, and their screen tiles.
struct Binned {
  std::vector<double> tris;          ///< T x kTriStride
  std::vector<cl_int> layer;         ///< T
  std::vector<cl_int> tileStart;     ///< tiles + 1 prefix sums
  std::vector<cl_int> tileTriangles; ///< triangle indices per tile, layer order
  int tilesX = 0, tilesY = 0;
};

// Projects layer meshes into `target` and keeps the triangles in front of nearZ with a pixel
// centre in their box.
void projectTriangles(const AdaptiveMLI& a, const scene::Camera& target, double nearZ, Binned& out,
                      std::vector<std::array<int, 4>>& boxes) {
  const Eigen::Matrix3d K = target.pixelK();
  for (std::size_t k = 0; k < a.meshes.size(); ++k) {
    const mli::AdaptiveLayerMesh& m = a.meshes[k];
    std::vector<Eigen::Vector3d> projected(m.numPoints());
    for (std::size_t v = 0; v < m.numPoints(); ++v) {
      const Eigen::Vector3d xw(m.points[3 * v], m.points[3 * v + 1], m.points[3 * v + 2]);
      const Eigen::Vector3d xc = target.worldToCamera(xw);
      projected[v] = {K(0, 0) * xc.x() / xc.z() + K(0, 2), K(1, 1) * xc.y() / xc.z() + K(1, 2),
                      xc.z()};
    }
    for (std::size_t t = 0; t < m.numTriangles(); ++t) {
      const std::int32_t* v = &m.triangles[3 * t];
      double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
      bool keep = true;
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector3d& p = projected[static_cast<std::size_t>(v[c])];
        keep = keep && p.z() > nearZ && std::abs(p.x()) < kGuard && std::abs(p.y()) < kGuard;
        x0 = std::min(x0, p.x());
        x1 = std::max(x1, p.x());
        y0 = std::min(y0, p.y());
        y1 = std::max(y1, p.y());
      }
      if (!keep)
        continue;
      // Pixel centres c + 0.5 inside [x0, x1].
      const int c0 = std::max(0, static_cast<int>(std::ceil(x0 - 0.5)));
      const int c1 = std::min(target.width - 1, static_cast<int>(std::floor(x1 - 0.5)));
      const int r0 = std::max(0, static_cast<int>(std::ceil(y0 - 0.5)));
      const int r1 = std::min(target.height - 1, static_cast<int>(std::floor(y1 - 0.5)));
      if (c0 > c1 || r0 > r1)
        continue;
      for (int c = 0; c < 3; ++c) {
        const std::size_t i = static_cast<std::size_t>(v[c]);
        const Eigen::Vector3d& p = projected[i];
        out.tris.insert(out.tris.end(), {p.x(), p.y(), p.z(), m.grid[2 * i], m.grid[2 * i + 1]});
      }
      out.layer.push_back(static_cast<cl_int>(k));
      boxes.push_back({c0, c1, r0, r1});
    }
  }
}

Binned binTriangles(const AdaptiveMLI& a, const scene::Camera& target, double nearZ, int tile) {
  Binned b;
  std::vector<std::array<int, 4>> boxes;
  projectTriangles(a, target, nearZ, b, boxes);
  b.tilesX = (target.width + tile - 1) / tile;
  b.tilesY = (target.height + tile - 1) / tile;
  const std::size_t tiles = static_cast<std::size_t>(b.tilesX) * b.tilesY;
  std::vector<std::size_t> count(tiles + 1, 0);
  auto forTiles = [&](const std::array<int, 4>& box, auto&& f) {
    for (int ty = box[2] / tile; ty <= box[3] / tile; ++ty)
      for (int tx = box[0] / tile; tx <= box[1] / tile; ++tx)
        f(static_cast<std::size_t>(ty) * b.tilesX + tx);
  };
  for (const auto& box : boxes)
    forTiles(box, [&](std::size_t t) { ++count[t + 1]; });
  for (std::size_t t = 0; t < tiles; ++t)
    count[t + 1] += count[t];
  if (count[tiles] > static_cast<std::size_t>(std::numeric_limits<cl_int>::max()))
    fail(kOp, ": ", count[tiles], " (triangle, tile) pairs exceed the int32 range");
  b.tileStart.assign(count.begin(), count.end());
  b.tileTriangles.resize(std::max<std::size_t>(1, count[tiles]));
  std::vector<std::size_t> next(count.begin(), count.end() - 1);
  for (std::size_t i = 0; i < boxes.size(); ++i)
    forTiles(boxes[i], [&](std::size_t t) { b.tileTriangles[next[t]++] = static_cast<cl_int>(i); });
  return b;
}

std::shared_ptr<ocl::Buffer> upload(const std::vector<cl_int>& values) {
  std::vector<cl_int> padded = values;
  if (padded.empty())
    padded.push_back(0); // OpenCL buffers cannot be empty
  std::shared_ptr<ocl::Buffer> buffer = intBuffer(padded.size());
  ocl::checkCl(clEnqueueWriteBuffer(ocl::Device::current().queue(), buffer->mem(), CL_TRUE, 0,
                                    padded.size() * sizeof(cl_int), padded.data(), 0, nullptr,
                                    nullptr),
               "renderAdaptiveMLI: write");
  return buffer;
}

} // namespace

std::size_t AdaptiveMLI::numTriangles() const {
  std::size_t n = 0;
  for (const mli::AdaptiveLayerMesh& m : meshes)
    n += m.numTriangles();
  return n;
}

AdaptiveMLI buildAdaptiveMLI(const mli::MLI& mli, const mli::AdaptiveMeshOptions& options) {
  mli::validateMLI(mli, "buildAdaptiveMLI");
  AdaptiveMLI out;
  out.mli = mli;
  for (int k = 0; k < mli.numLayers(); ++k)
    out.meshes.push_back(mli::buildAdaptiveLayerMesh(mli, k, options));
  return out;
}

AdaptiveRenderer::AdaptiveRenderer(AdaptiveMLI adaptive, ocl::Dtype dtype)
    : adaptive_(std::move(adaptive)), dtype_(dtype) {
  mli::validateMLI(adaptive_.mli, kOp);
  if (adaptive_.meshes.size() != adaptive_.mli.layers.size())
    fail(kOp, ": ", adaptive_.meshes.size(), " meshes for ", adaptive_.mli.numLayers(), " layers");
  for (std::size_t k = 0; k < adaptive_.meshes.size(); ++k)
    checkMesh(adaptive_.mli, static_cast<int>(k), adaptive_.meshes[k]);
  rgba_ = mliTensors(adaptive_.mli, dtype_).rgba;
}

AdaptiveRender AdaptiveRenderer::render(const scene::Camera& target,
                                        const AdaptiveRenderSettings& settings) const {
  checkCamera(target, kOp, "target", true);
  if (!(settings.nearZ > 0) || !std::isfinite(settings.nearZ))
    fail(kOp, ": nearZ = ", settings.nearZ, ", expected a finite value > 0");
  if (settings.tileSize < 4 || settings.tileSize > 64)
    fail(kOp, ": tileSize = ", settings.tileSize, ", expected 4 .. 64");
  ocl::checkedInt(int64_t(4) * target.width * target.height, kOp);
  ensureModelKernels();

  const Binned b = binTriangles(adaptive_, target, settings.nearZ, settings.tileSize);
  const int64_t T = static_cast<int64_t>(b.layer.size());
  std::vector<double> tris = b.tris;
  if (tris.empty())
    tris.assign(kTriStride, 0.0); // never read: every tile list is empty
  const ocl::Tensor triTensor =
      ocl::Tensor::fromHost(tris, {std::max<int64_t>(T, 1), kTriStride}, dtype_);
  const auto layerBuffer = upload(b.layer), startBuffer = upload(b.tileStart);
  const auto listBuffer = upload(b.tileTriangles);

  ocl::Tensor packed = ocl::Tensor::empty({4, target.height, target.width}, dtype_);
  ocl::Launch("raster_adaptive", "raster_adaptive_shade", dtype_)
      .arg(adaptive_.mli.height())
      .arg(adaptive_.mli.width())
      .arg(target.height)
      .arg(target.width)
      .arg(settings.tileSize)
      .arg(b.tilesX)
      .arg(triTensor)
      .arg(layerBuffer->mem())
      .arg(startBuffer->mem())
      .arg(listBuffer->mem())
      .arg(rgba_)
      .arg(packed)
      .run2(target.width, target.height, 16, 4);
  return {ocl::slice(packed, 0, 0, 3), ocl::slice(packed, 0, 3, 4)};
}

AdaptiveRender renderAdaptiveMLI(const AdaptiveMLI& adaptive, const scene::Camera& target,
                                 const AdaptiveRenderSettings& settings, ocl::Dtype dtype) {
  return AdaptiveRenderer(adaptive, dtype).render(target, settings);
}

} // namespace simpli::raster

// rasterizeLayers: vertex projection, triangle binning into screen tiles, per-pixel k-buffer
// (kernels in model/kernels/raster.cl).
#include "model_kernels.h"
#include "raster/camera.h"
#include "simpli/error.h"
#include "simpli/model/raster/rasterizer.h"

#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/launch.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace simpli::raster {
namespace {

constexpr const char* kOp = "rasterizeLayers";

void fillInts(cl_mem mem, int value, std::size_t count) {
  const cl_int v = value;
  ocl::checkCl(clEnqueueFillBuffer(ocl::Device::current().queue(), mem, &v, sizeof(v), 0,
                                   count * sizeof(cl_int), 0, nullptr, nullptr),
               "rasterizeLayers: fill");
}

std::vector<cl_int> readInts(cl_mem mem, std::size_t count) {
  std::vector<cl_int> out(count);
  ocl::checkCl(clEnqueueReadBuffer(ocl::Device::current().queue(), mem, CL_TRUE, 0,
                                   count * sizeof(cl_int), out.data(), 0, nullptr, nullptr),
               "rasterizeLayers: read");
  return out;
}

void writeInts(cl_mem mem, const std::vector<cl_int>& values) {
  ocl::checkCl(clEnqueueWriteBuffer(ocl::Device::current().queue(), mem, CL_TRUE, 0,
                                    values.size() * sizeof(cl_int), values.data(), 0, nullptr,
                                    nullptr),
               "rasterizeLayers: write");
}

// Tile lists vary in length from frame to frame; rounding their allocation up to a power of two
// lets the buffer pool reuse them instead of keeping one buffer per length.
std::size_t listCapacity(int64_t entries) {
  std::size_t cap = 4096;
  while (static_cast<int64_t>(cap) < entries)
    cap *= 2;
  return cap;
}

// Exclusive prefix sum of `counts` into `offsets` (clamped to the int range; only used when the
// total fits); returns the total.
int64_t exclusiveScan(const std::vector<cl_int>& counts, std::vector<cl_int>& offsets) {
  offsets.resize(counts.size());
  int64_t total = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    offsets[i] = static_cast<cl_int>(std::min<int64_t>(total, std::numeric_limits<cl_int>::max()));
    total += counts[i];
  }
  return total;
}

struct Grid {
  int L, H, W, Ht, Wt, K, tile, tilesX, tilesY;
  int tiles() const { return tilesX * tilesY; }
};

} // namespace

std::array<int64_t, 3> layerTriangleVertices(int64_t id, int H, int W) {
  if (H < 2 || W < 2)
    fail("layerTriangleVertices: grid ", H, "x", W, " must be at least 2x2");
  if (id < 0)
    fail("layerTriangleVertices: triangle id ", id, " is negative");
  const int64_t quads = int64_t(H - 1) * (W - 1);
  const int64_t layer = id / (2 * quads);
  const int64_t rest = id - layer * 2 * quads;
  const int64_t q = rest / 2;
  const int64_t qi = q / (W - 1), qj = q % (W - 1);
  const int64_t b = layer * H * W + qi * W + qj;
  if (rest % 2 == 0)
    return {b, b + W, b + W + 1};
  return {b, b + W + 1, b + 1};
}

std::vector<int32_t> RasterFragments::triangleIds() const {
  if (!triangles)
    fail("RasterFragments::triangleIds: no fragments (default-constructed)");
  const std::size_t n = std::size_t(maxFragments) * targetHeight * targetWidth;
  const std::vector<cl_int> ids = readInts(triangles->mem(), n);
  return {ids.begin(), ids.end()};
}

ocl::Tensor RasterFragments::layerIndex() const {
  if (!triangles)
    fail("RasterFragments::layerIndex: no fragments (default-constructed)");
  ensureModelKernels();
  ocl::Tensor out = ocl::Tensor::empty({maxFragments, targetHeight, targetWidth}, dtype);
  const int n = static_cast<int>(out.numel());
  ocl::Launch("raster", "raster_fragment_layer", dtype, raster::programOptions(maxFragments))
      .arg(n)
      .arg(2 * (height - 1) * (width - 1))
      .arg(triangles->mem())
      .arg(out)
      .run(n);
  return out;
}

RasterFragments rasterizeLayers(const ocl::Tensor& depth, const scene::Camera& reference,
                                const scene::Camera& target, const RasterSettings& settings) {
  raster::checkDepth(depth, kOp);
  raster::checkCamera(reference, kOp, "reference", false);
  raster::checkCamera(target, kOp, "target", true);
  raster::checkSettings(settings, kOp);
  ensureModelKernels();

  Grid g{};
  g.L = static_cast<int>(depth.size(0));
  g.H = static_cast<int>(depth.size(1));
  g.W = static_cast<int>(depth.size(2));
  g.Ht = target.height;
  g.Wt = target.width;
  g.K = settings.maxFragments;
  g.tile = settings.tileSize;
  g.tilesX = (g.Wt + g.tile - 1) / g.tile;
  g.tilesY = (g.Ht + g.tile - 1) / g.tile;
  ocl::checkedInt(int64_t(g.K) * g.Ht * g.Wt, kOp);
  // Pixel centres are snapped to 1/256 pixel in 64-bit integers; the image must lie well
  // inside the +-2^21 pixel guard band.
  if (g.Ht > (1 << 20) || g.Wt > (1 << 20))
    fail(kOp, ": target size ", g.Wt, "x", g.Ht, " exceeds 2^20 pixels per side");

  RasterFragments f;
  f.layers = g.L;
  f.height = g.H;
  f.width = g.W;
  f.targetHeight = g.Ht;
  f.targetWidth = g.Wt;
  f.maxFragments = g.K;
  f.interpolation = settings.interpolation;
  f.reference = reference;
  f.target = target;
  f.nearZ = settings.nearZ;
  f.farZ = settings.farZ;
  f.dtype = depth.dtype();

  const std::string options = raster::programOptions(g.K);
  const ocl::Dtype dt = depth.dtype();
  const ocl::Tensor params =
      raster::parameterTensor(reference, target, settings.nearZ, settings.farZ, dt);
  const ocl::Tensor verts = raster::projectVertices(depth, params, g.K);
  const int perspective = settings.interpolation == RasterInterpolation::PerspectiveCorrect;

  const std::size_t tiles = static_cast<std::size_t>(g.tiles());
  const std::size_t pixels = std::size_t(g.Ht) * g.Wt;
  auto tileCounts = raster::intBuffer(tiles);
  auto tileOffsets = raster::intBuffer(tiles);
  auto tileCursor = raster::intBuffer(tiles);
  auto pixelCounts = raster::intBuffer(pixels);
  auto pixelOffsets = raster::intBuffer(pixels);
  auto pixelCursor = raster::intBuffer(pixels);
  f.triangles = raster::intBuffer(std::size_t(g.K) * pixels);
  f.depth = ocl::Tensor::empty({g.K, g.Ht, g.Wt}, dt);
  // Snapped corners of the large triangles (6 per triangle), written by the count pass.
  const int64_t numTriangles = f.numTriangles();
  const ocl::Tensor corners = ocl::Tensor::empty({numTriangles * 6}, dt);

  // List offsets are 32-bit in the kernels. One triangle adds at most SMALL_RECT (64, raster.cl)
  // pixel candidates or one entry per tile, so halving a range always ends within the budget.
  const int64_t budget = std::max<int64_t>(
      std::min<int64_t>(settings.maxBinEntries, std::numeric_limits<cl_int>::max() / 2),
      static_cast<int64_t>(tiles) + 64);
  // Triangle ranges still to bin; a range whose lists exceed the budget is halved.
  std::vector<std::pair<int64_t, int64_t>> todo{{0, numTriangles}};
  bool first = true;
  while (!todo.empty()) {
    const auto [t0, nt] = todo.back();
    todo.pop_back();
    fillInts(tileCounts->mem(), 0, tiles);
    fillInts(pixelCounts->mem(), 0, pixels);
    ocl::Launch("raster", "raster_bin_count", dt, options)
        .arg(static_cast<int>(t0))
        .arg(static_cast<int>(nt))
        .arg(g.H)
        .arg(g.W)
        .arg(g.Ht)
        .arg(g.Wt)
        .arg(g.tile)
        .arg(g.tilesX)
        .arg(verts)
        .arg(params)
        .arg(pixelCounts->mem())
        .arg(tileCounts->mem())
        .arg(corners)
        .run(nt);
    std::vector<cl_int> pixelStart, tileStart;
    const int64_t fragTotal = exclusiveScan(readInts(pixelCounts->mem(), pixels), pixelStart);
    const int64_t tileTotal = exclusiveScan(readInts(tileCounts->mem(), tiles), tileStart);
    if (fragTotal + tileTotal > budget && nt > 1) {
      const int64_t half = nt / 2;
      todo.push_back({t0 + half, nt - half});
      todo.push_back({t0, half});
      continue;
    }
    if (fragTotal + tileTotal == 0 && !first)
      continue;
    writeInts(pixelOffsets->mem(), pixelStart);
    writeInts(tileOffsets->mem(), tileStart);
    fillInts(pixelCursor->mem(), 0, pixels);
    fillInts(tileCursor->mem(), 0, tiles);
    const ocl::Tensor fragZ = ocl::Tensor::empty({int64_t(listCapacity(fragTotal))}, dt);
    auto fragId = raster::intBuffer(listCapacity(fragTotal));
    auto tileList = raster::intBuffer(listCapacity(tileTotal));
    if (fragTotal + tileTotal > 0)
      ocl::Launch("raster", "raster_bin_fill", dt, options)
          .arg(static_cast<int>(t0))
          .arg(static_cast<int>(nt))
          .arg(g.H)
          .arg(g.W)
          .arg(g.Ht)
          .arg(g.Wt)
          .arg(g.tile)
          .arg(g.tilesX)
          .arg(perspective)
          .arg(verts)
          .arg(params)
          .arg(pixelOffsets->mem())
          .arg(pixelCursor->mem())
          .arg(fragZ)
          .arg(fragId->mem())
          .arg(tileOffsets->mem())
          .arg(tileCursor->mem())
          .arg(tileList->mem())
          .run(nt);
    const std::size_t local = g.tile >= 8 ? 8 : 4;
    ocl::Launch("raster", "raster_fragments", dt, options)
        .arg(g.H)
        .arg(g.W)
        .arg(g.Ht)
        .arg(g.Wt)
        .arg(g.tile)
        .arg(g.tilesX)
        .arg(first ? 1 : 0)
        .arg(perspective)
        .arg(verts)
        .arg(params)
        .arg(pixelOffsets->mem())
        .arg(pixelCounts->mem())
        .arg(fragZ)
        .arg(fragId->mem())
        .arg(tileOffsets->mem())
        .arg(tileCounts->mem())
        .arg(tileList->mem())
        .arg(corners)
        .arg(f.depth)
        .arg(f.triangles->mem())
        .run2(g.Wt, g.Ht, local, local);
    first = false;
  }
  return f;
}

} // namespace simpli::raster

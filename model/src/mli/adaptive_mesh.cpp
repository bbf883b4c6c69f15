// Adaptive meshes of MLI layers: the quadtree, its leaves' triangulation and the vertex
// registry (see mli/adaptive_mesh.h for the error measure and the rules).
#include "simpli/model/mli/adaptive_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "mli/adaptive_mesh_internal.h"
#include "simpli/error.h"
#include "simpli/model/scene/trajectory.h"

namespace simpli::mli {

namespace adaptive {

SummedArea::SummedArea(int w, int h, const std::vector<std::uint8_t>& flags) : w_(w), h_(h) {
  s_.assign(static_cast<std::size_t>(w + 1) * (h + 1), 0);
  for (int y = 0; y < h; ++y) {
    std::int64_t row = 0;
    for (int x = 0; x < w; ++x) {
      row += flags[static_cast<std::size_t>(y) * w + x];
      at(x + 1, y + 1) = at(x + 1, y) + row;
    }
  }
}

std::int64_t SummedArea::sum(int x0, int y0, int x1, int y1) const {
  return get(x1, y1) - get(x0, y1) - get(x1, y0) + get(x0, y0);
}

LayerGrid::LayerGrid(const MLI& mli, int k, const AdaptiveMeshOptions& options)
    : W(mli.width()), H(mli.height()) {
  const MLILayer& layer = mli.layers[static_cast<std::size_t>(k)];
  const std::size_t n = mli.texels();
  pixelsPerDisparity = pixelsPerInverseDepth(mli, options);
  // Infinite when B f_px = 0 cannot happen (validated camera, B > 0); tolerance 0 stays 0.
  disparityTolerance = options.tolerancePixels / pixelsPerDisparity;
  textureTolerance = options.tolerancePixels;
  disparity.resize(n);
  visible.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    disparity[p] = 1.0 / static_cast<double>(layer.depth[p]);
    visible[p] = layer.rgba[4 * p + 3] >= options.alphaThreshold ? 1 : 0;
  }
  markDiscontinuities(options.discontinuityPixels);
  std::vector<std::uint8_t> quadVisible(static_cast<std::size_t>(W - 1) * (H - 1));
  std::vector<std::uint8_t> quadCut(quadVisible.size());
  for (int y = 0; y + 1 < H; ++y)
    for (int x = 0; x + 1 < W; ++x) {
      const std::size_t q = static_cast<std::size_t>(y) * (W - 1) + x;
      quadVisible[q] = visible[index(x, y)] | visible[index(x + 1, y)] | visible[index(x, y + 1)] |
                       visible[index(x + 1, y + 1)];
      quadCut[q] =
          cutH[hIndex(x, y)] | cutH[hIndex(x, y + 1)] | cutV[index(x, y)] | cutV[index(x + 1, y)];
    }
  visibleQuads = SummedArea(W - 1, H - 1, quadVisible);
  cutQuads = SummedArea(W - 1, H - 1, quadCut);
}

void LayerGrid::markDiscontinuities(double discontinuityPixels) {
  cutH.assign(static_cast<std::size_t>(W - 1) * H, 0);
  cutV.assign(static_cast<std::size_t>(W) * H, 0); // the last row stays 0
  if (std::isinf(discontinuityPixels))
    return;
  const double maxJump = discontinuityPixels / pixelsPerDisparity;
  auto cut = [&](std::size_t a, std::size_t b) -> std::uint8_t {
    return (visible[a] || visible[b]) && std::abs(disparity[a] - disparity[b]) > maxJump;
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      if (x + 1 < W)
        cutH[hIndex(x, y)] = cut(index(x, y), index(x + 1, y));
      if (y + 1 < H)
        cutV[index(x, y)] = cut(index(x, y), index(x, y + 1));
    }
}

double LayerGrid::twoTriangleDisparity(const Cell& c, double x, double y) const {
  const double s = (x - c.x0) / (c.x1 - c.x0), t = (y - c.y0) / (c.y1 - c.y0);
  const double tl = disparity[index(c.x0, c.y0)], tr = disparity[index(c.x1, c.y0)];
  const double bl = disparity[index(c.x0, c.y1)], br = disparity[index(c.x1, c.y1)];
  if (c.flip) // diagonal bottom-left to top-right: (TL, BL, TR) above it, (BL, BR, TR) below
    return s + t <= 1 ? tl + s * (tr - tl) + t * (bl - tl)
                      : br + (1 - s) * (bl - br) + (1 - t) * (tr - br);
  // Diagonal top-left to bottom-right: (TL, BL, BR) below it, (TL, BR, TR) above it.
  return t >= s ? tl + t * (bl - tl) + s * (br - bl) : tl + s * (tr - tl) + t * (br - tr);
}

bool LayerGrid::twoTrianglesFit(const Cell& c) const {
  const double tl = 1.0 / disparity[index(c.x0, c.y0)], tr = 1.0 / disparity[index(c.x1, c.y0)];
  const double bl = 1.0 / disparity[index(c.x0, c.y1)], br = 1.0 / disparity[index(c.x1, c.y1)];
  const double diagonal = std::hypot(c.x1 - c.x0, c.y1 - c.y0);
  // The two triangles share the diagonal's ends and each has one of the other corners.
  const double a = c.flip ? bl : tl, b = c.flip ? tr : br;
  for (const double third :
       c.flip ? std::array<double, 2>{tl, br} : std::array<double, 2>{bl, tr}) {
    const double zMin = std::min({a, b, third}), zMax = std::max({a, b, third});
    if (textureSwimBound(diagonal, zMin, zMax) > textureTolerance)
      return false;
  }
  for (int y = c.y0; y <= c.y1; ++y)
    for (int x = c.x0; x <= c.x1; ++x) {
      const std::size_t p = index(x, y);
      if (visible[p] && std::abs(disparity[p] - twoTriangleDisparity(c, x, y)) > disparityTolerance)
        return false;
    }
  return true;
}

} // namespace adaptive

namespace {

using adaptive::Cell;
using adaptive::edgeFunction;
using adaptive::LayerGrid;
using adaptive::PolygonPoint;
using adaptive::Triangle;

std::vector<Cell> children(const Cell& c) {
  const int w = c.x1 - c.x0, h = c.y1 - c.y0;
  const int xm = w >= 2 ? c.x0 + w / 2 : c.x1, ym = h >= 2 ? c.y0 + h / 2 : c.y1;
  std::vector<Cell> out;
  for (const auto& [x0, x1] : {std::pair{c.x0, xm}, std::pair{xm, c.x1}})
    for (const auto& [y0, y1] : {std::pair{c.y0, ym}, std::pair{ym, c.y1}})
      if (x1 > x0 && y1 > y0)
        out.push_back({x0, y0, x1, y1, false});
  return out;
}

// Appends the leaves of cell `c` (top-down refinement, see the header's rules).
void refine(const LayerGrid& g, const Cell& c, int maxTransparentQuads, std::vector<Cell>& leaves) {
  const int w = c.x1 - c.x0, h = c.y1 - c.y0;
  const std::int64_t visible = g.visibleQuads.sum(c.x0, c.y0, c.x1, c.y1);
  if (visible == 0)
    return; // nothing to see: no triangles
  const bool cut = g.cutQuads.sum(c.x0, c.y0, c.x1, c.y1) > 0;
  if (w == 1 && h == 1) {
    leaves.push_back({c.x0, c.y0, c.x1, c.y1, cut});
    return;
  }
  const std::int64_t transparent = static_cast<std::int64_t>(w) * h - visible;
  if (!cut && transparent <= maxTransparentQuads)
    for (const bool flip : {false, true}) {
      const Cell leaf{c.x0, c.y0, c.x1, c.y1, false, flip};
      if (g.twoTrianglesFit(leaf)) {
        leaves.push_back(leaf);
        return;
      }
    }
  for (const Cell& child : children(c))
    refine(g, child, maxTransparentQuads, leaves);
}

// The positions (doubled grid) that lie on some leaf's boundary: cell corners and the
// midpoints of a cut quad's continuous edges.
std::vector<std::uint8_t> boundaryMarks(const LayerGrid& g, const std::vector<Cell>& leaves) {
  const int W2 = 2 * g.W - 1;
  std::vector<std::uint8_t> mark(static_cast<std::size_t>(W2) * (2 * g.H - 1), 0);
  auto set = [&](int X, int Y) { mark[static_cast<std::size_t>(Y) * W2 + X] = 1; };
  for (const Cell& c : leaves) {
    set(2 * c.x0, 2 * c.y0);
    set(2 * c.x1, 2 * c.y0);
    set(2 * c.x0, 2 * c.y1);
    set(2 * c.x1, 2 * c.y1);
    if (!c.cut)
      continue;
    if (!g.cutV[g.index(c.x0, c.y0)])
      set(2 * c.x0, 2 * c.y0 + 1);
    if (!g.cutV[g.index(c.x1, c.y0)])
      set(2 * c.x1, 2 * c.y0 + 1);
    if (!g.cutH[g.hIndex(c.x0, c.y0)])
      set(2 * c.x0 + 1, 2 * c.y0);
    if (!g.cutH[g.hIndex(c.x0, c.y1)])
      set(2 * c.x0 + 1, 2 * c.y1);
  }
  return mark;
}

// 1/d at doubled-grid position (X, Y) on a leaf's boundary: a texel's own value, or (for the
// midpoint of a texel edge) the mean of its two ends, which lies on the straight 3-D edge.
double boundaryDisparity(const LayerGrid& g, int X, int Y) {
  const int x0 = X / 2, y0 = Y / 2, x1 = (X + 1) / 2, y1 = (Y + 1) / 2;
  return 0.5 * (g.disparity[g.index(x0, y0)] + g.disparity[g.index(x1, y1)]);
}

// The boundary polygon of leaf `c`, wound top-left -> bottom-left -> bottom-right -> top-right
// (the per-texel triangles' winding): its corners and every marked position on its edges.
std::vector<PolygonPoint> boundaryPolygon(const LayerGrid& g, const Cell& c,
                                          const std::vector<std::uint8_t>& mark) {
  const int W2 = 2 * g.W - 1;
  const int X0 = 2 * c.x0, X1 = 2 * c.x1, Y0 = 2 * c.y0, Y1 = 2 * c.y1;
  std::vector<PolygonPoint> polygon;
  auto visit = [&](int X, int Y) {
    if (mark[static_cast<std::size_t>(Y) * W2 + X])
      polygon.push_back({X, Y, boundaryDisparity(g, X, Y)});
  };
  for (int Y = Y0; Y < Y1; ++Y)
    visit(X0, Y);
  for (int X = X0; X < X1; ++X)
    visit(X, Y1);
  for (int Y = Y1; Y > Y0; --Y)
    visit(X1, Y);
  for (int X = X1; X > X0; --X)
    visit(X, Y0);
  return polygon;
}

// The centre of a fan over leaf `c`: the grid point at the split position when the leaf is at
// least 2 x 2 quads, else the half-grid point in its middle. Its 1/d is the texel's when that
// texel is visible, else the leaf's two-triangle surface there (a transparent texel's depth is
// free and may be far off).
PolygonPoint fanCentre(const LayerGrid& g, const Cell& c) {
  const int w = c.x1 - c.x0, h = c.y1 - c.y0;
  const int X = w >= 2 ? 2 * (c.x0 + w / 2) : c.x0 + c.x1;
  const int Y = h >= 2 ? 2 * (c.y0 + h / 2) : c.y0 + c.y1;
  if (X % 2 == 0 && Y % 2 == 0 && g.visible[g.index(X / 2, Y / 2)])
    return {X, Y, g.disparity[g.index(X / 2, Y / 2)]};
  return {X, Y, g.twoTriangleDisparity(c, 0.5 * X, 0.5 * Y)};
}

// A leaf's triangulations, best first: two triangles when its polygon is its four corners;
// else a fan from a corner whose two edges carry no other vertex (n - 2 triangles), then a
// fan from its centre (n triangles).
std::vector<std::vector<Triangle>> leafTriangulations(const LayerGrid& g, const Cell& c,
                                                      const std::vector<PolygonPoint>& polygon) {
  const std::size_t n = polygon.size();
  if (n == 4) {
    const PolygonPoint &tl = polygon[0], &bl = polygon[1], &br = polygon[2], &tr = polygon[3];
    if (c.flip)
      return {{Triangle{tl, bl, tr}, Triangle{bl, br, tr}}};
    return {{Triangle{tl, bl, br}, Triangle{tl, br, tr}}};
  }
  auto isCorner = [&](const PolygonPoint& p) {
    return (p.X == 2 * c.x0 || p.X == 2 * c.x1) && (p.Y == 2 * c.y0 || p.Y == 2 * c.y1);
  };
  std::vector<std::vector<Triangle>> out;
  for (std::size_t k = 0; k < n && out.empty(); ++k) {
    if (!isCorner(polygon[k]) || !isCorner(polygon[(k + 1) % n]) ||
        !isCorner(polygon[(k + n - 1) % n]))
      continue;
    std::vector<Triangle> fan;
    for (std::size_t i = 1; i + 1 < n; ++i)
      fan.push_back({polygon[k], polygon[(k + i) % n], polygon[(k + i + 1) % n]});
    out.push_back(std::move(fan));
  }
  const PolygonPoint centre = fanCentre(g, c);
  std::vector<Triangle> fan;
  for (std::size_t k = 0; k < n; ++k)
    fan.push_back({centre, polygon[k], polygon[(k + 1) % n]});
  out.push_back(std::move(fan));
  return out;
}

// Largest |1/d - surface| over the visible texels inside triangle t (closed).
double triangleError(const LayerGrid& g, const Triangle& t) {
  const std::int64_t area = edgeFunction(t[0], t[1], t[2].X, t[2].Y);
  if (area == 0)
    return 0.0;
  const int x0 = (std::min({t[0].X, t[1].X, t[2].X}) + 1) / 2;
  const int x1 = std::max({t[0].X, t[1].X, t[2].X}) / 2;
  const int y0 = (std::min({t[0].Y, t[1].Y, t[2].Y}) + 1) / 2;
  const int y1 = std::max({t[0].Y, t[1].Y, t[2].Y}) / 2;
  double worst = 0.0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const std::size_t p = g.index(x, y);
      if (!g.visible[p])
        continue;
      const std::int64_t b0 = edgeFunction(t[1], t[2], 2 * x, 2 * y);
      const std::int64_t b1 = edgeFunction(t[2], t[0], 2 * x, 2 * y);
      const std::int64_t b2 = edgeFunction(t[0], t[1], 2 * x, 2 * y);
      const bool inside =
          area > 0 ? (b0 >= 0 && b1 >= 0 && b2 >= 0) : (b0 <= 0 && b1 <= 0 && b2 <= 0);
      if (!inside)
        continue;
      const double surface =
          (static_cast<double>(b0) * t[0].disparity + static_cast<double>(b1) * t[1].disparity +
           static_cast<double>(b2) * t[2].disparity) /
          static_cast<double>(area);
      worst = std::max(worst, std::abs(g.disparity[p] - surface));
    }
  return worst;
}

// textureSwimBound of triangle t.
double triangleSwim(const Triangle& t) {
  const int dx = std::max({t[0].X, t[1].X, t[2].X}) - std::min({t[0].X, t[1].X, t[2].X});
  const int dy = std::max({t[0].Y, t[1].Y, t[2].Y}) - std::min({t[0].Y, t[1].Y, t[2].Y});
  const double dMin = std::min({t[0].disparity, t[1].disparity, t[2].disparity});
  const double dMax = std::max({t[0].disparity, t[1].disparity, t[2].disparity});
  return adaptive::textureSwimBound(0.5 * std::hypot(dx, dy), 1.0 / dMax, 1.0 / dMin);
}

} // namespace

void validateAdaptiveMeshOptions(const AdaptiveMeshOptions& o) {
  if (!(o.tolerancePixels >= 0) || !std::isfinite(o.tolerancePixels))
    fail("adaptive mesh: tolerancePixels = ", o.tolerancePixels, ", expected a finite value >= 0");
  if (!(o.cameraOffset >= 0) || !std::isfinite(o.cameraOffset))
    fail("adaptive mesh: cameraOffset = ", o.cameraOffset,
         ", expected a finite value >= 0 (0 = default)");
  if (!(o.discontinuityPixels > 0))
    fail("adaptive mesh: discontinuityPixels = ", o.discontinuityPixels,
         ", expected a value > 0 (infinity: never cut)");
  if (!(o.alphaThreshold >= 0 && o.alphaThreshold <= 1))
    fail("adaptive mesh: alphaThreshold = ", o.alphaThreshold, ", expected a value in [0, 1]");
  if (o.maxTransparentQuads < 0)
    fail("adaptive mesh: maxTransparentQuads = ", o.maxTransparentQuads, ", expected >= 0");
}

double defaultCameraOffset(const MLI& mli) {
  double near = std::numeric_limits<double>::infinity(), far = 0.0;
  for (const MLILayer& layer : mli.layers)
    for (float d : layer.depth) {
      near = std::min(near, static_cast<double>(d));
      far = std::max(far, static_cast<double>(d));
    }
  return 0.05 * scene::trajectoryFocusDepth(near, far);
}

double pixelsPerInverseDepth(const MLI& mli, const AdaptiveMeshOptions& options) {
  const double offset = options.cameraOffset > 0 ? options.cameraOffset : defaultCameraOffset(mli);
  const scene::Camera& c = mli.camera;
  return offset * std::max(c.fx * c.width, c.fy * c.height);
}

AdaptiveLayerMesh buildAdaptiveLayerMesh(const MLI& mli, int k,
                                         const AdaptiveMeshOptions& options) {
  validateMLI(mli, "buildAdaptiveLayerMesh");
  validateAdaptiveMeshOptions(options);
  if (k < 0 || k >= mli.numLayers())
    fail("buildAdaptiveLayerMesh: layer index ", k, " is out of range [0, ", mli.numLayers(), ")");
  const LayerGrid g(mli, k, options);

  std::vector<Cell> leaves;
  refine(g, {0, 0, g.W - 1, g.H - 1, false}, options.maxTransparentQuads, leaves);
  // Fans (leaves whose neighbours put vertices on their edges) are checked against the
  // tolerance; those that miss it are split, which may turn neighbours into fans: repeat.
  AdaptiveLayerMesh mesh;
  std::vector<std::vector<Triangle>> triangles;
  for (bool settled = false; !settled;) {
    ++mesh.passes;
    settled = true;
    const std::vector<std::uint8_t> mark = boundaryMarks(g, leaves);
    std::vector<Cell> next;
    triangles.clear();
    for (const Cell& c : leaves) {
      if (c.cut) {
        next.push_back(c);
        triangles.emplace_back();
        continue;
      }
      // Two triangles were checked by refine (and 1 x 1 quads are exact): take the first
      // triangulation that fits.
      const bool single = c.x1 - c.x0 == 1 && c.y1 - c.y0 == 1;
      bool placed = false;
      for (std::vector<Triangle>& t : leafTriangulations(g, c, boundaryPolygon(g, c, mark))) {
        bool fits = true;
        if (t.size() > 2 && !single)
          for (const Triangle& tri : t)
            fits = fits && triangleError(g, tri) <= g.disparityTolerance &&
                   triangleSwim(tri) <= g.textureTolerance;
        if (fits) {
          next.push_back(c);
          triangles.push_back(std::move(t));
          placed = true;
          break;
        }
      }
      if (placed)
        continue;
      settled = false;
      for (const Cell& child : children(c))
        refine(g, child, options.maxTransparentQuads, next);
    }
    leaves = std::move(next);
  }

  adaptive::emitLeaves(g, mli, leaves, triangles, mesh);
  return mesh;
}

} // namespace simpli::mli

// Adaptive meshes: the vertices and triangles of the quadtree's leaves (cut quads as quarters,
// the others as their triangulation without the triangles over transparent quads only), see
// mli/adaptive_mesh.h.
#include "mli/adaptive_mesh_internal.h"

#include <algorithm>
#include <limits>
#include <unordered_map>

#include "simpli/error.h"

namespace simpli::mli::adaptive {

namespace {

// Vertices of the mesh being built. Positions are on the doubled grid (X, Y) = (2x, 2y), so
// half-grid points of cut quads and of thin fan centres are integers too. Shared positions
// (cell corners, midpoints of continuous edges) have one vertex; the two sides of a cut edge
// and the centres of a cut quad's sides have their own.
class VertexRegistry {
public:
  VertexRegistry(const MLI& mli, AdaptiveLayerMesh& mesh)
      : mli_(mli), mesh_(mesh), W2_(2 * mli.width() - 1),
        shared_(static_cast<std::size_t>(W2_) * (2 * mli.height() - 1), -1) {}

  std::int32_t shared(int X, int Y, double disparity) {
    std::int32_t& id = shared_[static_cast<std::size_t>(Y) * W2_ + X];
    if (id < 0)
      id = add(X, Y, disparity);
    return id;
  }
  // The vertex of cut-edge midpoint (X, Y) on the side of the corner `side` (a texel index).
  std::int32_t side(int X, int Y, std::size_t side, double disparity) {
    const std::int64_t key =
        (static_cast<std::int64_t>(Y) * W2_ + X) * static_cast<std::int64_t>(mli_.texels()) +
        static_cast<std::int64_t>(side);
    auto [it, inserted] = sides_.try_emplace(key, -1);
    if (inserted)
      it->second = add(X, Y, disparity);
    return it->second;
  }
  std::int32_t unique(int X, int Y, double disparity) { return add(X, Y, disparity); }

private:
  std::int32_t add(int X, int Y, double disparity) {
    const scene::Camera& cam = mli_.camera;
    const double x = 0.5 * X, y = 0.5 * Y, d = 1.0 / disparity;
    const double u = x / (cam.width - 1), v = y / (cam.height - 1);
    const Eigen::Vector3d xw = cam.backproject({u, v}, d);
    mesh_.points.insert(mesh_.points.end(), {static_cast<float>(xw.x()), static_cast<float>(xw.y()),
                                             static_cast<float>(xw.z())});
    mesh_.grid.insert(mesh_.grid.end(), {static_cast<float>(x), static_cast<float>(y)});
    mesh_.depth.push_back(static_cast<float>(d));
    if (mesh_.depth.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
      fail("adaptive mesh: more than 2^31 vertices");
    return static_cast<std::int32_t>(mesh_.depth.size() - 1);
  }

  const MLI& mli_;
  AdaptiveLayerMesh& mesh_;
  int W2_;
  std::vector<std::int32_t> shared_;
  std::unordered_map<std::int64_t, std::int32_t> sides_;
};

// True when some visible texel quad overlaps the interior of triangle t (separating axes on
// the doubled grid: the quad's box against the triangle's bounding box and its three edges).
bool coversVisibleQuad(const LayerGrid& g, const Triangle& t) {
  const int qx0 = std::min({t[0].X, t[1].X, t[2].X}) / 2;
  const int qx1 = (std::max({t[0].X, t[1].X, t[2].X}) + 1) / 2; // exclusive quad bounds
  const int qy0 = std::min({t[0].Y, t[1].Y, t[2].Y}) / 2;
  const int qy1 = (std::max({t[0].Y, t[1].Y, t[2].Y}) + 1) / 2;
  if (g.visibleQuads.sum(qx0, qy0, qx1, qy1) == 0)
    return false;
  const std::int64_t area = edgeFunction(t[0], t[1], t[2].X, t[2].Y);
  if (area == 0)
    return false;
  const int sign = area > 0 ? 1 : -1;
  for (int qy = qy0; qy < qy1; ++qy)
    for (int qx = qx0; qx < qx1; ++qx) {
      if (g.visibleQuads.sum(qx, qy, qx + 1, qy + 1) == 0)
        continue;
      bool separated = false;
      for (int e = 0; e < 3 && !separated; ++e) {
        const PolygonPoint &a = t[e], &b = t[(e + 1) % 3];
        std::int64_t best = std::numeric_limits<std::int64_t>::min();
        for (int cy = 0; cy <= 1; ++cy)
          for (int cx = 0; cx <= 1; ++cx)
            best = std::max(best, sign * edgeFunction(a, b, 2 * (qx + cx), 2 * (qy + cy)));
        separated = best <= 0; // the whole quad is on the outer side of (or on) this edge
      }
      if (!separated)
        return true;
    }
  return false;
}

// Emits the eight quarter triangles of cut quad `c` (see the header).
void emitCutQuad(const LayerGrid& g, const Cell& c, VertexRegistry& vertices,
                 AdaptiveLayerMesh& mesh) {
  // Corners in winding order TL, BL, BR, TR; edge e joins corner e and corner e + 1.
  const int cx[4] = {c.x0, c.x0, c.x1, c.x1}, cy[4] = {c.y0, c.y1, c.y1, c.y0};
  const bool edgeCut[4] = {g.cutV[g.index(c.x0, c.y0)] != 0, g.cutH[g.hIndex(c.x0, c.y1)] != 0,
                           g.cutV[g.index(c.x1, c.y0)] != 0, g.cutH[g.hIndex(c.x0, c.y0)] != 0};
  std::size_t texel[4];
  double disparity[4];
  std::int32_t corner[4];
  for (int k = 0; k < 4; ++k) {
    texel[k] = g.index(cx[k], cy[k]);
    disparity[k] = g.disparity[texel[k]];
    corner[k] = vertices.shared(2 * cx[k], 2 * cy[k], disparity[k]);
  }
  // Sides: corners joined along the cycle by continuous edges.
  int sideOf[4] = {0, 1, 2, 3};
  for (bool changed = true; changed;) {
    changed = false;
    for (int e = 0; e < 4; ++e) {
      const int a = e, b = (e + 1) % 4;
      if (!edgeCut[e] && sideOf[a] != sideOf[b]) {
        sideOf[a] = sideOf[b] = std::min(sideOf[a], sideOf[b]);
        changed = true;
      }
    }
  }
  std::int32_t centre[4] = {-1, -1, -1, -1};
  for (int s = 0; s < 4; ++s) {
    double sum = 0;
    int n = 0;
    for (int k = 0; k < 4; ++k)
      if (sideOf[k] == s) {
        sum += disparity[k];
        ++n;
      }
    if (n > 0)
      centre[s] = vertices.unique(c.x0 + c.x1, c.y0 + c.y1, sum / n);
  }
  // Midpoint of edge e as seen from corner k (one of its ends).
  auto midpoint = [&](int e, int k) {
    const int a = e, b = (e + 1) % 4;
    const int X = cx[a] + cx[b], Y = cy[a] + cy[b];
    if (!edgeCut[e])
      return vertices.shared(X, Y, 0.5 * (disparity[a] + disparity[b]));
    return vertices.side(X, Y, texel[k], disparity[k]);
  };
  for (int k = 0; k < 4; ++k) {
    const std::int32_t after = midpoint(k, k), before = midpoint((k + 3) % 4, k);
    const std::int32_t mid = centre[sideOf[k]];
    mesh.triangles.insert(mesh.triangles.end(), {corner[k], after, mid, corner[k], mid, before});
  }
}

void emitLeaf(const LayerGrid& g, const Cell& c, const std::vector<Triangle>& triangles,
              VertexRegistry& vertices, AdaptiveLayerMesh& mesh) {
  const bool allVisible = g.visibleQuads.sum(c.x0, c.y0, c.x1, c.y1) ==
                          static_cast<std::int64_t>(c.x1 - c.x0) * (c.y1 - c.y0);
  auto id = [&](const PolygonPoint& p) {
    // Fan centres are inside the leaf, never on another leaf: shared() is still right (each
    // position is used by one leaf only), and keeps one code path.
    return vertices.shared(p.X, p.Y, p.disparity);
  };
  for (const Triangle& t : triangles)
    if (allVisible || coversVisibleQuad(g, t))
      mesh.triangles.insert(mesh.triangles.end(), {id(t[0]), id(t[1]), id(t[2])});
}

} // namespace

void emitLeaves(const LayerGrid& g, const MLI& mli, const std::vector<Cell>& leaves,
                const std::vector<std::vector<Triangle>>& triangles, AdaptiveLayerMesh& mesh) {
  VertexRegistry vertices(mli, mesh);
  for (std::size_t l = 0; l < leaves.size(); ++l) {
    if (leaves[l].cut) {
      emitCutQuad(g, leaves[l], vertices, mesh);
      ++mesh.cutQuads;
    } else {
      emitLeaf(g, leaves[l], triangles[l], vertices, mesh);
    }
  }
  mesh.leaves = leaves.size();
}

} // namespace simpli::mli::adaptive

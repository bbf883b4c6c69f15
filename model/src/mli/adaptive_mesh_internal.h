#pragma once
// The adaptive mesh builder's view of one layer (mli/adaptive_mesh.h): 1/d, visibility and
// discontinuous texel edges on the corner grid, with summed-area tables for cell queries.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "simpli/model/mli/adaptive_mesh.h"

namespace simpli::mli::adaptive {

/// Upper bound of the texture swim of a triangle (texels) whose grid bounding box has diagonal
/// `diagonal` (texels) and whose vertices' depths span [zMin, zMax]: texture coordinates
/// interpolated linearly over the 3-D triangle (what OpenGL does) versus the reference
/// projection of the surface point. With 3-D barycentrics l, the projection is
/// sum l_i z_i p_i / z, z = sum l_i z_i, so the swim is sum l_i (z_i - z)(p_i - c) / z for any
/// point c; with c the box centre (|p_i - c| <= diagonal / 2) and the mean absolute deviation
/// sum l_i |z_i - z| <= (zMax - zMin) / 2, it is at most diagonal (zMax - zMin) / (4 zMin).
inline double textureSwimBound(double diagonal, double zMin, double zMax) {
  return diagonal * (zMax - zMin) / (4.0 * zMin);
}

/// Sums of 0/1 flags over rectangles of a w x h grid in O(1).
class SummedArea {
public:
  SummedArea() = default;
  SummedArea(int w, int h, const std::vector<std::uint8_t>& flags);
  /// Sum over [x0, x1) x [y0, y1).
  std::int64_t sum(int x0, int y0, int x1, int y1) const;

private:
  std::int64_t& at(int x, int y) { return s_[static_cast<std::size_t>(y) * (w_ + 1) + x]; }
  std::int64_t get(int x, int y) const { return s_[static_cast<std::size_t>(y) * (w_ + 1) + x]; }
  int w_ = 0, h_ = 0;
  std::vector<std::int64_t> s_;
};

/// A quadtree cell: the texel quads [x0, x1) x [y0, y1), i.e. grid points x0..x1, y0..y1.
struct Cell {
  int x0, y0, x1, y1;
  bool cut;          ///< a single quad with a discontinuous edge (emitted as quarters)
  bool flip = false; ///< two triangles on the diagonal bottom-left to top-right
};

struct LayerGrid {
  LayerGrid(const MLI& mli, int k, const AdaptiveMeshOptions& options);

  int W, H;
  double pixelsPerDisparity;         ///< B f_px
  double disparityTolerance;         ///< tolerancePixels / (B f_px)
  double textureTolerance;           ///< tolerancePixels, for the texture swim (texels)
  std::vector<double> disparity;     ///< 1/d per texel
  std::vector<std::uint8_t> visible; ///< alpha >= threshold per texel
  /// Discontinuous edges: cutH[hIndex(x, y)] joins (x, y) and (x + 1, y); cutV[index(x, y)]
  /// joins (x, y) and (x, y + 1).
  std::vector<std::uint8_t> cutH, cutV;
  SummedArea visibleQuads; ///< quads with a visible corner, (W-1) x (H-1)
  SummedArea cutQuads;     ///< quads with a discontinuous edge

  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * W + x; }
  std::size_t hIndex(int x, int y) const { return static_cast<std::size_t>(y) * (W - 1) + x; }

  /// 1/d of the cell's two triangles (corners only, on the diagonal c.flip says) at grid
  /// position (x, y) inside the cell.
  double twoTriangleDisparity(const Cell& c, double x, double y) const;
  /// Whether the two triangles are within the tolerance at every visible texel of the cell and
  /// their texture swim bound is within it too.
  bool twoTrianglesFit(const Cell& c) const;

private:
  void markDiscontinuities(double discontinuityPixels);
};

/// A point of a leaf's boundary polygon or fan: position on the doubled grid (X, Y) = (2x, 2y),
/// so that half-grid points are integers too, and 1/d.
struct PolygonPoint {
  int X, Y;
  double disparity;
};

using Triangle = std::array<PolygonPoint, 3>;

/// Twice the signed area of (a, b, p) on the doubled grid (positive inside a triangle wound as
/// the mesh's triangles: y points down, so this winding is clockwise on screen).
inline std::int64_t edgeFunction(const PolygonPoint& a, const PolygonPoint& b, std::int64_t X,
                                 std::int64_t Y) {
  return (static_cast<std::int64_t>(b.Y) - a.Y) * (X - a.X) -
         (static_cast<std::int64_t>(b.X) - a.X) * (Y - a.Y);
}

/// Appends the vertices and triangles of `leaves` to `mesh` (adaptive_mesh_emit.cpp): cut
/// quads as their quarters, the others as `triangles[l]` without those that cover no visible
/// quad; counts leaves and cut quads.
void emitLeaves(const LayerGrid& g, const MLI& mli, const std::vector<Cell>& leaves,
                const std::vector<std::vector<Triangle>>& triangles, AdaptiveLayerMesh& mesh);

} // namespace simpli::mli::adaptive

#pragma once
// Adaptive (display) meshes of MLI layers: per layer a triangle mesh whose density follows the
// layer's depth, for real-time rendering with the layer's RGBA as a full-resolution texture.
// The per-texel form (mli/mesh.h) stays the one the differentiable rasterizer and training use.
//
// Domain: the layer's corner grid (spec §1.3): texel (i, j) is the grid point (x, y) = (j, i),
// x in [0, W-1], y in [0, H-1], seen at u = x/(W-1), v = y/(H-1) of the reference camera.
// Vertices sit on grid points, or on half-grid points inside texel quads cut at a depth
// discontinuity; a vertex at (x, y) with depth d is the reference camera's back-projection of
// (u, v) at z = d, exactly as in the per-texel mesh.
//
// Error measure (what the tolerance bounds). A point at reference-camera depth d seen from a
// camera translated by b (perpendicular to the viewing axis, no rotation) projects at
// u' = u - fx b_x / d; moving the point along its reference ray to depth d' shifts that
// projection by fx |b_x| |1/d - 1/d'| (relative units). In pixels of the layer grid, for an
// offset of length B in any lateral direction, the shift is at most
//
//     e = B * f_px * |1/d - 1/d'|,   f_px = max(fx W, fy H)   (fx, fy relative intrinsics)
//
// so the mesh is built in inverse depth (disparity): a triangle of the mesh lies in a plane,
// and over a plane 1/d is affine in (u, v), i.e. the depth the mesh shows on the ray of texel
// (i, j) is the barycentric interpolation of its vertices' 1/d. The builder guarantees
// e <= tolerancePixels at every visible texel (alpha >= alphaThreshold), measured at the texels
// (the samples of the depth map); at the reference camera itself (B = 0) every depth error is
// invisible, which is why the bound is stated for an offset camera. B defaults to 0.05 x the
// MLI's focus depth (scene::trajectoryFocusDepth of its depth range), the lateral radius of
// the spiral / orbit that `simpli render --trajectory` draws around an MLI without a scene.
//
// Texture swim (the second thing the tolerance bounds). A renderer interpolates texture
// coordinates linearly over the 3-D triangle (OpenGL's perspective-correct interpolation), but
// the texel that belongs to a surface point is where the reference camera sees it: with 3-D
// barycentrics l and vertex depths z_i, at sum l_i z_i p_i / sum l_i z_i, not sum l_i p_i. The
// two agree on triangles of constant reference depth (MPI planes) and differ by up to
// diagonal (z_max - z_min) / (4 z_min) texels elsewhere (a slanted plane 1000 texels wide with
// a depth ratio of 1.2 would swim by ~45 texels as two triangles), independently of the viewing
// camera. Cells are split until this bound is within tolerancePixels too, so slanted layers get
// cells of about sqrt(4 tolerance / (z |grad 1/z|)) texels: geometry exact, texture within the
// tolerance. (Projective texturing in a shader would avoid it, but neither ParaView's
// representations nor glTF can do that.)
//
// Construction (a quadtree over the grid's texel quads, top-down from the whole layer):
//  - a cell whose quads are all transparent (no visible corner) is dropped: no triangle covers
//    only texels below the alpha threshold;
//  - a cell is split while its two triangles (corners only, on whichever diagonal fits) miss a
//    visible texel's 1/d by more than the tolerance or swim by more than it (bound above),
//    while it contains a discontinuous texel edge, and while more than maxTransparentQuads of
//    its quads are transparent (transparent regions are cut away rather than drawn at alpha 0,
//    as far as that pays: on llvmpipe a triangle costs about as much as 40 fragments, so
//    splitting a speckled cell into more triangles costs more than the fragments it saves);
//  - a texel edge is discontinuous when one end is visible and the offset camera would see its
//    two ends more than discontinuityPixels apart beyond the reference spacing:
//    B f_px |1/d_a - 1/d_b| > discontinuityPixels. A quad with such an edge becomes a cut quad:
//    each corner keeps the quarter of the quad next to it, at its own side's depth, so the two
//    sides of the step are not bridged by a stretched triangle; quarters of corners joined by
//    continuous edges share their vertices (no crack inside a side);
//  - no cracks between cells of different sizes: every vertex of a cell that lies on a
//    neighbour's edge is part of that neighbour's boundary polygon (a leaf with such vertices is
//    triangulated as a fan: from a corner whose two edges have none, 2 + k triangles for k such
//    vertices, else from its centre, 4 + k), so neighbouring triangles share edges exactly (no
//    T-junctions); a fan that misses the tolerance is split and the leaves are checked again.
// Constant-depth layers (MPI planes) collapse to two triangles per cell that is fully visible,
// the whole layer when it is all visible; slanted planes are exact at any tolerance (their
// triangle count follows the texture swim only).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "simpli/model/mli/mli.h"

namespace simpli::mli {

struct AdaptiveMeshOptions {
  /// Largest reprojection error (pixels of the layer grid) at a visible texel for a camera
  /// displaced by cameraOffset; >= 0 (0 keeps only exactly planar regions merged).
  double tolerancePixels = 1.0; // 60-65 fps at < 0.05 dB (docs/benchmarks.md, Display)
  /// Lateral camera offset B of the error measure (scene units); 0 (the default) picks
  /// defaultCameraOffset(mli).
  double cameraOffset = 0.0;
  /// Texel edges whose ends an offset camera sees more than this many pixels apart (beyond the
  /// reference spacing) are cut, not bridged; > 0, infinity never cuts (as the per-texel mesh).
  double discontinuityPixels = 2.0;
  /// Texels with alpha below this are transparent (their depth is free, their quads dropped);
  /// in [0, 1], 0 keeps everything.
  float alphaThreshold = 1.0f / 255.0f;
  /// Partly transparent cells are split while more than this many of their texel quads are
  /// transparent (>= 0; 0 cuts transparent regions away down to single quads).
  int maxTransparentQuads = 256;
};

struct AdaptiveLayerMesh {
  std::vector<float> points;           ///< N x 3 world coordinates
  std::vector<float> grid;             ///< N x 2 corner-grid (x, y) in texels (x = column)
  std::vector<float> depth;            ///< N reference-camera z
  std::vector<std::int32_t> triangles; ///< F x 3, wound as the per-texel mesh's triangles

  std::size_t leaves = 0;   ///< quadtree cells that produced triangles
  std::size_t cutQuads = 0; ///< of which texel quads cut at a depth discontinuity
  int passes = 0;           ///< build passes (fans that missed the tolerance were split)

  std::size_t numPoints() const { return depth.size(); }
  std::size_t numTriangles() const { return triangles.size() / 3; }
};

/// Throws simpli::Error naming the field and value unless every option is in its range.
void validateAdaptiveMeshOptions(const AdaptiveMeshOptions& options);

/// 0.05 x scene::trajectoryFocusDepth(min depth, max depth) over all texels of `mli`.
double defaultCameraOffset(const MLI& mli);

/// B f_px of the error measure: reprojection pixels per unit of 1/d (the camera offset from
/// `options`, or defaultCameraOffset when it is 0).
double pixelsPerInverseDepth(const MLI& mli, const AdaptiveMeshOptions& options);

/// The adaptive mesh of layer k (validates `mli` and `options`).
AdaptiveLayerMesh buildAdaptiveLayerMesh(const MLI& mli, int k,
                                         const AdaptiveMeshOptions& options = {});

struct AdaptiveMeshError {
  double maxPixels = 0.0;                 ///< largest e over the visible texels covered
  double maxTextureSwim = 0.0;            ///< largest texture swim (texels) at those texels
  std::size_t visibleTexels = 0;          ///< texels with alpha >= alphaThreshold
  std::size_t uncoveredVisibleTexels = 0; ///< visible texels no triangle covers
};

/// Measures `mesh` against layer k of `mli`, independently of how it was built: every texel
/// inside (or on the boundary of) a triangle gets the triangle's barycentric 1/d, the error of
/// a texel is the largest over the triangles covering it (e as above, with options' offset).
/// The swim at a texel p with image barycentrics b in a triangle: the surface point seen there
/// has 3-D barycentrics l_i = (b_i / z_i) / sum (b_j / z_j), where a renderer samples the texture
/// at sum l_i p_i; the swim is |sum l_i p_i - p|.
AdaptiveMeshError measureAdaptiveMesh(const MLI& mli, int k, const AdaptiveLayerMesh& mesh,
                                      const AdaptiveMeshOptions& options = {});

} // namespace simpli::mli

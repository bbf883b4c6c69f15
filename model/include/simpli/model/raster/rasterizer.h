#pragma once
// Differentiable OpenCL rasterizer for MLI layer meshes (spec §6.6-§6.8, §10.3,
// §12 item 14): L layers on an H x W corner grid in the reference camera, rendered into any
// pinhole target camera at any resolution, with per-pixel depth-sorted fragments of all layers
// (a k-buffer, equivalent to the reference's 16-pass depth peeling) and the reference's
// front-to-back composite.
//
// Geometry (§6.6): vertex (k, i, j) is the back-projection of the corner-grid point
// u = j/(W-1), v = i/(H-1) at reference-camera z = depth[k, i, j]; every texel quad with top-left
// vertex b = i*W + j (i < H-1, j < W-1) gives the triangles (b, b+W, b+W+1) and (b, b+W+1, b+1)
// (diagonal top-left to bottom-right). Triangle ids: layer k, quad q = i*(W-1) + j, id =
// k*2(H-1)(W-1) + 2q + (0 for the first triangle, 1 for the second).
//
// Target pixels: pixel (row r, column c) samples the centre-grid point ((c+0.5)/Wt,
// (r+0.5)/Ht) of the target camera's relative intrinsics; row 0 is the top image row.
//
// Coverage: the coverage test runs on the projected vertices snapped to 2^-30 pixel (below
// float32 resolution, so in float32 this is the rounded geometry itself; in float64 a 1e-9 pixel
// rounding) and is exact (a floating-point filter with a rigorous error bound, else 128-bit
// integer products), evaluated in a canonical edge direction, with a fixed tie rule (a pixel
// centre exactly on an edge or vertex belongs to the triangle found by moving it an
// infinitesimal step right, then down: the top-left rule). So a pixel centre inside an
// unfolded layer is covered by exactly one triangle of that layer, never zero or two, whatever
// the rounding; centres exactly on a layer's right or bottom boundary are outside it. Note for
// renders at the reference camera: pixel centres coincide with vertices only for the camera
// whose W x H centre grid is the corner grid (intrinsics scaled by (W-1)/W and shifted half a
// pixel); with the reference's own intrinsics they generally do not.
// Clipping, which the reference does not do (it only clamps |z| < 0.01 and cuts z outside
// [-120, 120]):
//  - a triangle with a vertex at z <= nearZ in the target camera (behind or at the camera
//    plane) is skipped entirely (not clipped into a smaller polygon);
//  - a vertex projecting more than 2^22 pixels from the image origin (the fixed-point range)
//    skips its triangles, as does a non-finite depth;
//  - a triangle whose snapped projected corners are exactly collinear (zero area) is skipped;
//    a layer seen exactly edge-on projects to such triangles and to slivers a rounding error
//    wide, so it renders as at most a line of pixels;
//  - a fragment whose interpolated depth exceeds farZ is dropped (the reference's 120-unit
//    cut; farZ <= 0 or infinity disables it).
// No back-face culling.
//
// Interpolation (barycentrics b of the pixel centre in the projected triangle; slightly negative
// values from rounding at edges are clamped to 0 and the rest renormalised):
//  - ScreenLinear (default, the reference's w = 1 quirk): attributes and depth are linear in
//    screen space, f = sum b_i f_i, z = sum b_i z_i. This is what the reference renders and
//    what the pretrained network saw; it is not the perspective-correct surface value: for a
//    triangle spanning a range of depths, the interpolated point lies off the true surface.
//  - PerspectiveCorrect: f = sum (b_i/z_i) f_i / sum (b_i/z_i), z = 1 / sum (b_i/z_i), i.e.
//    the value at the true intersection of the pixel ray with the triangle (what OpenGL/VTK
//    render). Both modes agree when a triangle's vertices share one target-camera z.
// Depth used for ordering and output is the target camera's z interpolated as above.
//
// Composite per pixel (§6.7): the up to K nearest fragments sorted by (z, triangle id), of
// all layers together; the farthest kept fragment gets alpha := 1; w_k = a_k prod_{j<k}
// (1 - a_j + 1e-6); colour = sum w_k f_k (every non-alpha attribute; the last attribute
// channel is alpha); opacity = 1 - prod_{k<K} (1 - a_k + 1e-6) over all K slots (empty slots
// count with a = 0, as the reference's 16 peeling passes do); depth = sum w_k z_k. A pixel
// without fragments has colour 0, opacity 0, depth 0, weights 0. Alphas are used as given
// (expected in [0, 1]; not clamped, so their gradient is never cut).
//
// Gradients (recorded on the autograd tape): with respect to every attribute channel and to
// the layer depths. Depth enters through the fragment's target z and through the barycentrics
// (the projected vertex positions move with depth); which triangles cover a pixel and their
// order are treated as constant (visibility is not differentiated).
//
// Implementation (model/kernels/raster.cl): project the vertices; bin the triangles: those
// touching at most 64 pixels are rasterized per triangle into per-pixel candidate lists (counts,
// prefix sums, fill), larger ones go to per-tile lists (tileSize); one work item per pixel then
// keeps the K nearest candidates and covering large triangles in a private k-buffer; the shade
// pass interpolates and composites; its backward pass recomputes the fragments per pixel and
// scatters gradients with atomic adds (so float32 gradients may differ in the last bits between
// runs; the forward pass is deterministic). Workloads above maxBinEntries are split into
// triangle ranges merged into the same k-buffer. Target sizes up to 2^20 pixels per side.
#include "simpli/model/scene/camera.h"

#include "simpli/ocl/tensor.h"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace simpli::raster {

enum class RasterInterpolation { ScreenLinear, PerspectiveCorrect };

struct RasterSettings {
  /// K: fragments kept per pixel (the reference peels 16). 1..64.
  int maxFragments = 16;
  RasterInterpolation interpolation = RasterInterpolation::ScreenLinear;
  /// Triangles with a vertex at target-camera z <= nearZ are skipped (> 0, scene units).
  double nearZ = 0.01;
  /// Fragments farther than this are dropped; <= 0 or infinity disables the cut.
  double farZ = 120.0;
  /// Screen tile edge in pixels for binning large triangles (those whose pixel rectangle
  /// exceeds 64 pixels; smaller ones are rasterized per triangle): 4, 8, 16 or 32 (speed only).
  int tileSize = 8;
  /// Most list entries (candidate fragments of small triangles plus (large triangle, tile)
  /// pairs) binned at once; larger workloads are split into triangle ranges that are merged
  /// into the same k-buffer (memory bound only; the result is the same).
  int64_t maxBinEntries = int64_t(1) << 25;
};

/// Visibility of one rendering: per pixel the ids of the K nearest triangles, near to far.
struct RasterFragments {
  int layers = 0, height = 0, width = 0; ///< L, H, W of the layer grid
  int targetHeight = 0, targetWidth = 0; ///< Ht, Wt
  int maxFragments = 0;                  ///< K
  RasterInterpolation interpolation = RasterInterpolation::ScreenLinear;
  scene::Camera reference, target;
  double nearZ = 0, farZ = 0;
  ocl::Dtype dtype = ocl::Dtype::F32;
  /// int32 [K, Ht, Wt] triangle ids (see the header comment), -1 for an empty slot; per pixel
  /// the non-empty slots come first, sorted by (z, id).
  std::shared_ptr<ocl::Buffer> triangles;
  /// [K, Ht, Wt] target-camera z of each fragment (0 for empty slots). Not differentiable.
  ocl::Tensor depth;

  int64_t numTriangles() const { return int64_t(layers) * 2 * (height - 1) * (width - 1); }
  /// Downloads `triangles` (K*Ht*Wt ids, slot-major).
  std::vector<int32_t> triangleIds() const;
  /// [K, Ht, Wt] layer index of each fragment (0 = farthest layer by convention), -1 for
  /// empty slots, in this fragments' dtype. Not differentiable.
  ocl::Tensor layerIndex() const;
};

struct RenderedLayers {
  ocl::Tensor colour;  ///< [A-1, Ht, Wt] composited non-alpha attributes
  ocl::Tensor opacity; ///< [1, Ht, Wt]
  ocl::Tensor depth;   ///< [1, Ht, Wt] sum_k w_k z_k (target-camera z)
  ocl::Tensor weights; ///< [K, Ht, Wt] composite weight w_k of each fragment slot
};

/// Finds the visible fragments of the layer meshes given by `depth` [L, H, W] (reference-camera
/// z; L >= 1, H, W >= 2) in `target` (its width x height is the output size). Not recorded on
/// the tape. The reference camera's width/height are not used (the grid is H x W).
RasterFragments rasterizeLayers(const ocl::Tensor& depth, const scene::Camera& reference,
                                const scene::Camera& target, const RasterSettings& settings = {});

/// Interpolates `attributes` [L, A, H, W] (A >= 2, alpha last) and composites the fragments.
/// `depth` must have the shape and dtype the fragments were rasterized from; positions and
/// z are recomputed from it, so gradients flow to it (and to the attributes) through the tape.
RenderedLayers shadeFragments(const RasterFragments& fragments, const ocl::Tensor& depth,
                              const ocl::Tensor& attributes);

/// rasterizeLayers followed by shadeFragments.
RenderedLayers renderLayers(const ocl::Tensor& depth, const ocl::Tensor& attributes,
                            const scene::Camera& reference, const scene::Camera& target,
                            const RasterSettings& settings = {});

/// The three vertex indices (into the L*H*W vertices, layer-major, row-major) of triangle `id`.
std::array<int64_t, 3> layerTriangleVertices(int64_t id, int H, int W);

} // namespace simpli::raster

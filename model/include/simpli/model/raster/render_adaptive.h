#pragma once
// OpenCL rendering of the adaptive display form of an MLI (mli/adaptive_mesh.h): per layer the
// adaptive mesh with the layer's RGBA as a texture, drawn as VTK draws it (simpli_vtk_render)
// and composited by the rasterizer's rule. Forward only: training and the differentiable
// rasterizer (raster/rasterizer.h) keep the per-texel form.
//
// Per target pixel (centre (c + 0.5, r + 0.5), row 0 = top), layer by layer from the back:
//  - the layer's fragment is the nearest (target z) of its triangles covering the pixel centre
//    (edges inclusive; a triangle with a vertex at target z <= nearZ is skipped), with
//    perspective-correct interpolation of the vertices' corner-grid positions;
//  - its RGBA is the bilinear sample of the layer's texels there (straight alpha; texel (i, j)
//    sits at grid position (j, i), as the per-texel mesh's vertex colours);
//  - it is composited over what is behind, c = a c_layer + (1 - a) c, opacity likewise, except
//    that the pixel's first (farthest) fragment is opaque, as the rasterizer's farthest fragment
//    is (spec §6.7).
// A pixel without fragments is 0 (colour and opacity). The triangles are binned to square
// screen tiles on the host (tileSize pixels).
#include "simpli/model/mli/adaptive_mesh.h"
#include "simpli/model/mli/mli.h"
#include "simpli/model/scene/camera.h"

#include "simpli/ocl/tensor.h"

#include <vector>

namespace simpli::raster {

/// An MLI with the adaptive mesh of each of its layers.
struct AdaptiveMLI {
  mli::MLI mli;
  std::vector<mli::AdaptiveLayerMesh> meshes; ///< one per layer, in layer order
  std::size_t numTriangles() const;
};

/// The adaptive meshes of every layer of `mli` (validated).
AdaptiveMLI buildAdaptiveMLI(const mli::MLI& mli, const mli::AdaptiveMeshOptions& options = {});

struct AdaptiveRenderSettings {
  double nearZ = 0.01; ///< triangles with a vertex at target z <= nearZ are skipped (> 0)
  int tileSize = 16;   ///< screen tile edge in pixels: 4 .. 64
};

struct AdaptiveRender {
  ocl::Tensor colour;  ///< [3, Ht, Wt] RGB in [0, 1] over a background of 0
  ocl::Tensor opacity; ///< [1, Ht, Wt]
};

/// An AdaptiveMLI ready to render many views: checked once, its texels uploaded once.
class AdaptiveRenderer {
public:
  /// Throws simpli::Error for a mesh that does not belong to the MLI (count, indices,
  /// positions).
  explicit AdaptiveRenderer(AdaptiveMLI adaptive, ocl::Dtype dtype = ocl::Dtype::F32);
  /// Renders into `target` (its width x height is the output size). Throws simpli::Error for a
  /// bad camera or settings.
  AdaptiveRender render(const scene::Camera& target,
                        const AdaptiveRenderSettings& settings = {}) const;
  const AdaptiveMLI& adaptive() const { return adaptive_; }

private:
  AdaptiveMLI adaptive_;
  ocl::Dtype dtype_;
  ocl::Tensor rgba_; ///< [L, 4, H, W]
};

/// AdaptiveRenderer(adaptive, dtype).render(target, settings).
AdaptiveRender renderAdaptiveMLI(const AdaptiveMLI& adaptive, const scene::Camera& target,
                                 const AdaptiveRenderSettings& settings = {},
                                 ocl::Dtype dtype = ocl::Dtype::F32);

} // namespace simpli::raster

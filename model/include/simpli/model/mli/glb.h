#pragma once
// An MLI as binary glTF 2.0 (.glb), for viewers and engines that know nothing of MLIs: every
// layer a textured triangle mesh (its RGBA at full resolution as a PNG texture, straight
// alpha, alphaMode BLEND, unlit: KHR_materials_unlit), listed back to front, plus the
// reference camera as a glTF perspective camera.
//
// Frames. glTF cameras look down -z with +y up; MLI cameras (OpenCV) look down +z with y down.
// The layers hang below a node "MLI" whose matrix takes world coordinates into the reference
// camera's frame and flips y and z (F [R | t], F = diag(1, -1, -1)), and the camera node
// "reference camera" sits at the origin: opening the file shows the layers as the reference
// camera saw them. yfov = 2 atan(1 / (2 fy)) and aspectRatio = fy / fx with relative
// intrinsics (fy / fx = W / H for square pixels); glTF has no principal point, so a camera
// whose cx, cy are off the image centre is shown slightly shifted (the file's "extras" keep
// the exact intrinsics).
//
// Draw order. glTF does not define the order in which viewers draw blended primitives; most
// sort them by distance, which for nested layers is back to front. The nodes are also in
// back-to-front order for viewers that draw in file order.
#include "simpli/model/mli/adaptive_mesh.h"
#include "simpli/model/mli/mesh.h"
#include "simpli/model/mli/mli.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace simpli::mli {

struct GlbOptions {
  /// Triangles whose three vertices all have alpha below this are left out (1/255: those an
  /// 8-bit texture shows fully transparent); a layer left with none is left out.
  float dropAlphaBelow = 1.0f / 255.0f;
  /// The mesh of layer k, vertices with corner-grid uv (mli/mesh.h); empty = buildLayerMesh,
  /// one vertex per texel. The texture is always the layer's full W x H RGBA.
  std::function<MLIMesh(const MLI& mli, int k, const MLIMeshOptions& options)> layerMesh;
};

/// GlbOptions::layerMesh for the adaptive display mesh (mli/adaptive_mesh.h) with `options`
/// (its alpha threshold replaced by the GLB's dropAlphaBelow when that is larger).
std::function<MLIMesh(const MLI&, int, const MLIMeshOptions&)>
adaptiveGlbMesh(const AdaptiveMeshOptions& options);

/// What encodeGlb put in the file, for reports.
struct GlbSummary {
  int layers = 0; ///< layers written (empty ones left out)
  std::size_t vertices = 0, triangles = 0, bytes = 0;
};

/// The .glb bytes of `mli` (validated first; throws simpli::Error naming the layer and value).
std::vector<std::uint8_t> encodeGlb(const MLI& mli, const GlbOptions& options = {},
                                    GlbSummary* summary = nullptr);

/// encodeGlb written atomically to `path` (a temporary beside it, then renamed).
GlbSummary writeGlb(const MLI& mli, const std::string& path, const GlbOptions& options = {});

/// Texture coordinates of corner-grid (u, v) in a W x H texture: the centre of texel (i, j)
/// for u = j / (W - 1), v = i / (H - 1), so that the texture reproduces the vertex colours.
inline float texelCentre(float u, int size) {
  return (u * float(size - 1) + 0.5f) / float(size);
}

} // namespace simpli::mli

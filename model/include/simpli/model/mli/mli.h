#pragma once
// Multi-layer image (MLI): SIMPLI's output representation (spec §6.6, §10).
// L layers, each a depth map and a straight-alpha RGBA texture of the same size H x W, plus the
// reference camera they were built in. Layer 0 is the FARTHEST layer (§12 item 1): the index
// order is back to front, as in the reference implementation and its exported files.
//
// Texel (i, j) of every layer lives on the reference ray through the corner-grid point
// u = j/(W-1), v = i/(H-1) (§1.3), at camera-space z = depth(i, j); this is what the mesh
// builder (mli/mesh.h) turns into vertices.
#include <cstddef>
#include <string>
#include <vector>

#include "simpli/model/scene/camera.h"

namespace simpli::mli {

struct MLILayer {
  /// Reference-camera z (not ray length), scene units, row-major H x W, row 0 = top image row.
  std::vector<float> depth;
  /// Straight (not premultiplied) colour and opacity, all in [0, 1]; interleaved R,G,B,A,
  /// row-major H x W x 4.
  std::vector<float> rgba;
};

struct MLI {
  /// Reference camera; camera.width / camera.height are the layer resolution W / H.
  scene::Camera camera;
  /// Back to front: layers[0] is the farthest.
  std::vector<MLILayer> layers;

  int width() const { return camera.width; }
  int height() const { return camera.height; }
  int numLayers() const { return static_cast<int>(layers.size()); }
  std::size_t texels() const {
    return static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height);
  }

  /// An MLI of `numLayers` layers sized from `camera` (width/height), depth 1, RGBA 0.
  static MLI allocate(const scene::Camera& camera, int numLayers);
};

/// Throws simpli::Error unless `mli` is well formed: at least one layer; H, W >= 2 (the corner
/// grid divides by W-1 and H-1); every layer's vectors sized H*W and H*W*4; all depths finite
/// and > 0; all RGBA finite and in [0, 1]; the camera valid by scene::validateCamera
/// (scene/camera_checks.h: finite, relative fx, fy in [1e-3, 1e3]) with R orthonormal within
/// 1e-4. The message starts with `context`
/// (e.g. the file being written) and names the layer, field, texel and value at fault.
void validateMLI(const MLI& mli, const std::string& context = "MLI");

/// The parts of validateMLI, for readers that check one file at a time; `context` (e.g. the
/// file name) starts every message. Depth: H*W values, finite, > 0. RGBA: H*W*4 values, finite,
/// in [0, 1]. Camera: as in validateMLI.
void validateMLIDepth(const std::vector<float>& depth, int H, int W, const std::string& context);
void validateMLIRgba(const std::vector<float>& rgba, int H, int W, const std::string& context);
void validateMLICamera(const scene::Camera& camera, const std::string& context);

/// Largest alpha of `layer` (0 when it has no texels).
float maxAlpha(const MLILayer& layer);

/// Indices of the layers whose every alpha is below `threshold` (nothing visible). Such layers
/// are kept by the builder (the representation has a fixed L); callers may skip drawing them.
std::vector<int> emptyLayers(const MLI& mli, float threshold = 1.0f / 255.0f);

} // namespace simpli::mli

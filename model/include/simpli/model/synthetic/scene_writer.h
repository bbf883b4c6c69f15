#pragma once
// Writing a rendered synthetic scene to disk: LLFF files (scene/llff_writer.h) — poses_bounds.npy,
// images/NNN.png, depth/NNN.png (16-bit, depth = value * depth scale) — plus scene.json with
// the generator parameters, the seed, the depth encoding, the cameras and every shape.
//
// The folder appears atomically: everything is written into a hidden temporary folder beside
// it, which is then renamed, so a failure or interruption never leaves a partial scene.
#include "simpli/model/synthetic/renderer.h"

#include <string>
#include <vector>

namespace simpli::synthetic {

/// The "generator" value in scene.json; an existing folder is only ever replaced when its
/// scene.json carries it.
constexpr const char* kSceneGenerator = "simpli make-scene";

struct SceneWriteOptions {
  /// Replace `dir` when it exists and holds a scene written by this writer (any other existing
  /// path is an error either way).
  bool overwrite = false;
  /// Scene units per depth count; 0 = 0.001, or the smallest larger power of ten that keeps
  /// the largest depth within 65535 counts.
  double depthScale = 0;
};

struct WrittenScene {
  std::string dir; ///< the folder as written (absolute)
  std::vector<DepthBounds> bounds;
  double depthScale = 0;
};

/// Depth scale chosen for depthScale = 0 (see SceneWriteOptions).
double chooseDepthScale(const std::vector<RenderedView>& views);

/// scene.json contents (pretty-printed JSON).
std::string sceneDescriptionJson(const SyntheticScene& scene,
                                 const std::vector<DepthBounds>& bounds, double depthScale);

/// Writes the scene; `views` are the renderings of scene.cameras (renderViews). Throws
/// simpli::Error naming the folder when it exists (and may not be replaced), its parent does
/// not exist or is not writable, or any file cannot be written; nothing is left behind then.
WrittenScene writeSyntheticScene(const std::string& dir, const SyntheticScene& scene,
                                 const std::vector<RenderedView>& views,
                                 const SceneWriteOptions& options = {});

} // namespace simpli::synthetic

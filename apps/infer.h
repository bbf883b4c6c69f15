#pragma once
// `simpli infer`, shared by its two forms: one scene (cmd_infer.cpp) and a folder of scene
// folders spread over the ranks of an MPI job (cmd_infer_scenes.cpp).
#include "simpli/model/generator/mli_builder.h"
#include "simpli/model/mli/files.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/scene/scene_folders.h"

#include <string>
#include <vector>

namespace simpli::app {

struct InferOptions {
  std::string scene, weights, config, layers = "all", device, out;
  std::vector<int> views, renderViews;
  int corrections = -1;
  double inputScale = 1.0; ///< sources resized by this before the network (the MLI's size)
  double referenceMargin = scene::recommendedReferenceMargin; ///< the reference camera widened on
                                                              ///< every side (widenedCamera)
  int64_t initRandom = -1; ///< >= 0: random weights with this seed
};

/// The network of a run, loaded once and used for every scene.
struct InferNetwork {
  generator::MLIBuilder builder;
  const network::LoadedNetwork* loaded = nullptr;
  /// What every scene's pass shares: corrections, the layer threshold, keepOutput.
  generator::MLIBuildOptions build;
};

/// Loads the network `o` names (once: later calls return at once) and checks the options that
/// concern it (--corrections, --layers, --input-scale). Throws simpli::Error.
void loadInferNetwork(const InferOptions& o, InferNetwork& net);

/// What inferring one scene did.
struct SceneInference {
  int exitCode = 0; ///< 0 written; 128 + signal: cancelled by SIGINT / SIGTERM, nothing written
  int layers = 0, width = 0, height = 0;
  double ms = 0; ///< from reading the scene to the commit
};

/// One scene into the folder `out` by the rules of `simpli infer SCENE --out DIR` (staged,
/// replaced only when it holds nothing but an earlier simpli infer output); `verbose` prints the
/// full report with a progress bar, else nothing. Throws simpli::Error on bad input.
SceneInference inferScene(const InferOptions& o, const std::string& scenePath,
                          const std::string& out, InferNetwork& net, bool verbose);

/// `simpli infer SCENES_DIR --out OUT`: every scene of `scenes` into OUT/<name>, dealt round
/// robin over the ranks of parallel::world(); one report on rank 0. Returns the exit code.
int inferScenes(const InferOptions& o, const std::vector<scene::SceneFolder>& scenes);

/// What `simpli infer` writes into DIR besides the JPEG MLI: the lossless MLI, rendered views,
/// the random weights.
mli::MLIFolderExtras inferOutputExtras();

} // namespace simpli::app

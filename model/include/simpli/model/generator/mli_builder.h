#pragma once
// From a scene to its MLI with a SIMPLI network, for every user alike (`simpli infer`,
// vtkSIMPLIBuildMLI): the network cache, the forward-reuse policy and the scene -> generator
// input, testable without VTK.
//
// The network is loaded on first use and again only when what it comes from changes (weights
// file and its modification time, config, random seed, OpenCL device). The last forward pass's
// MLI is kept and returned again, without a pass, when the network, the source images, their
// cameras, the correction count and the depth range are the same (what happens when a filter
// property that only changes how the layers become meshes is edited).
#include "simpli/model/generator/generator.h"
#include "simpli/model/generator/scene_input.h"
#include "simpli/model/mli/mli.h"
#include "simpli/model/network/loader.h"
#include "simpli/model/scene/scene.h"

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace simpli::generator {

/// Where the network comes from (network::loadNetwork's arguments).
struct NetworkSource {
  std::string config;                 ///< name or JSON path; empty = the weights' metadata
  std::string weights;                ///< safetensors path; empty = the default weights
  std::optional<uint64_t> randomSeed; ///< set: random weights with this seed instead
};

struct MLIBuildOptions {
  std::vector<int> views; ///< source view indices; empty = every view
  DepthRangeSource depthRange = DepthRangeSource::Config;
  int corrections = -1;         ///< MLI corrections to run; -1 = all of the config's
  double inputScale = 1.0;      ///< SceneInputOptions::inputScale: the MLI is built at that size
  double referenceMargin = 0.0; ///< SceneInputOptions::referenceMargin
  /// Surfaces whose largest alpha is below this are left out of the MLI (toMLI); 0 keeps all.
  float dropEmptyBelow = 0.0f;
  /// Keep the pass's GeneratorOutput (device tensors) in the result, e.g. to render views;
  /// a reused pass has none, so this also disables reuse.
  bool keepOutput = false;
  /// Called after every stage of the pass (GeneratorOptions::progress); false cancels it and
  /// build() throws GeneratorCancelled, keeping nothing.
  GeneratorOptions::ProgressFn progress;
};

struct MLIBuild {
  std::vector<int> views; ///< the source views used
  GeneratorInput input;   ///< what the pass ran on (images, cameras, depth range)
  mli::MLI mli;
  std::optional<GeneratorOutput> output; ///< with keepOutput
  /// (stage, ms): the pass's stages (device-finished times) and "to_mli", or "forward_reused".
  std::vector<std::pair<std::string, double>> stageMs;
  bool reused = false; ///< the MLI is the previous pass's
};

class MLIBuilder {
public:
  /// The network for `source`, loaded when there is none yet or `source`, the weights file's
  /// modification time or the current OpenCL device differ from the last load. Throws
  /// simpli::Error (loadNetwork's) when it cannot be loaded; nothing is kept then.
  const network::LoadedNetwork& network(const NetworkSource& source);

  /// The MLI of `scene` with the network of the last network() call (which must have
  /// succeeded). Throws simpli::Error for bad views or sizes (sceneInput's) and
  /// GeneratorCancelled when options.progress cancels the pass.
  MLIBuild build(const scene::Scene& scene, const MLIBuildOptions& options);

  /// Forgets the network and the last pass (before the OpenCL device changes: every tensor of
  /// the old device must be gone first).
  void release();
  bool hasNetwork() const { return loaded_.network != nullptr; }

private:
  network::LoadedNetwork loaded_;
  std::string networkKey_; ///< what loaded_ came from, see network()
  // The last pass: its key (network, corrections, depth range, cameras), images and MLI.
  std::string lastKey_;
  std::vector<float> lastPixels_;
  std::optional<mli::MLI> lastMLI_;
};

} // namespace simpli::generator

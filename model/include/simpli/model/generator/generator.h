#pragma once
// The SIMPLI generator: the forward pass that connects the network's modules (network.h) with
// the geometry (plane sweep, MPI rendering, layer unprojection, mesh rasterization) as
// GeneratorSIMPLI.manual_forward does (spec §3, §7). Differentiable: with the
// autograd tape enabled every step is recorded, so a loss on the outputs trains the network.
//
// This header is the contract between the generator and its users (training, `simpli infer`,
// the VTK filters). Extend it; do not change what is here without updating every user.
#include "simpli/model/mli/mli.h"
#include "simpli/model/network/network.h"
#include "simpli/model/raster/rasterizer.h"
#include "simpli/model/scene/camera.h"

#include "simpli/ocl/tensor.h"

#include <exception>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace simpli::generator {

/// One forward pass's inputs (batch size 1, as the reference's inference).
struct GeneratorInput {
  ocl::Tensor images;                 ///< [V, 3, H, W] RGB in [-1, 1], V >= 1, the network's dtype
  std::vector<scene::Camera> sources; ///< V source cameras (relative intrinsics; size W x H)
  scene::Camera reference;            ///< the virtual reference camera (size W x H)
  /// Plane depth range (scene units). <= 0 means the config's min_depth / max_depth. maxDepth
  /// may be +infinity: the farthest plane then goes to 1e6 x minDepth (docs/numerics.md). The
  /// corrections' rasterizer cut (GeneratorOptions::raster) is widened to cover the range.
  double minDepth = 0, maxDepth = 0;
};

/// Renders the current surfaces into every source view for the MLI corrections (levels 2..):
/// rgba [S, 4, h, w] (RGB in [-1, 1]), depth [S, h, w] -> [V, 3, H, W]. The default is the
/// OpenCL rasterizer; tests substitute the golden's stub renderer (golden README §4).
using SourceRenderer = std::function<ocl::Tensor(const ocl::Tensor& rgba, const ocl::Tensor& depth,
                                                 const GeneratorInput& input, int level)>;

struct GeneratorOptions {
  /// MLI correction steps to run: -1 = all in the config, 0..config (fewer is faster).
  int corrections = -1;
  /// Keep the intermediate source renders the training losses need.
  bool keepIntermediates = false;
  /// Finish the device queue after every stage so stageMs are wall times of that stage.
  bool timeStages = false;
  /// Rasterizer settings for the source renders of the corrections.
  raster::RasterSettings raster;
  /// Empty = the OpenCL rasterizer.
  SourceRenderer sourceRenderer;
  /// Aggregate the views of a correction level with attention in one fused
  /// kernel (ViewAttention::aggregate) instead of the composed ops: same values to rounding,
  /// about 10x less time at 512x384, V = 8; in training its fused backward too. Not used when a
  /// stageHook wants the attention's tokens, or above ViewAttention::kMaxFusedViews views.
  bool fusedAggregation = true;
  /// Test / debugging aid: when set, receives named intermediate tensors as they are computed
  /// (names follow the golden files' stage keys, e.g. "features_extractor.out",
  /// "sampi_block_lvl1.out", "layered_depth"; layouts are this implementation's, see
  /// src/generator/). Not called when empty (no cost).
  std::function<void(const std::string& name, const ocl::Tensor& value)> stageHook;
  /// Progress and cancellation: called after every stage (the names of GeneratorOutput::stageMs)
  /// with the stages done and their total for this pass; returning false cancels the pass
  /// (forward then throws GeneratorCancelled). With timeStages the device has finished the
  /// stage's work; without it, `done` counts enqueued stages.
  using ProgressFn = std::function<bool(const std::string& stage, int done, int total)>;
  ProgressFn progress;
};

/// Thrown by Generator::forward when GeneratorOptions::progress returns false.
struct GeneratorCancelled : std::exception {
  const char* what() const noexcept override { return "the forward pass was cancelled"; }
};

struct GeneratorOutput {
  /// [S, 4, H, W]: RGB in [-1, 1], alpha in [0, 1]; S = the config's layers (planes when
  /// MPI-only); surface 0 is the farthest.
  ocl::Tensor rgba;
  /// [S, H, W] reference-camera z of every surface texel (constant per plane when MPI-only).
  ocl::Tensor depth;
  /// With keepIntermediates: what the reference's intermediate losses compare with the clean
  /// sources (§8.1): [0] the level-1 MPI render, channels 9-11, [V, 3, h1, w1]; then for every
  /// correction run, the mesh render that fed it, [V, 3, H, W].
  std::vector<ocl::Tensor> intermediateSourceRenders;
  /// With keepIntermediates: the per-plane compositing weights of that level-0 MPI render,
  /// [V, P, 1, h, w] (plane 0 the farthest), and the plane depths (reference-camera z).
  ocl::Tensor level0SourceWeights;
  std::vector<double> planeDepths;
  /// (stage name, milliseconds) in execution order. Without timeStages these are host times
  /// to enqueue the stage's work (the device may still be running it).
  std::vector<std::pair<std::string, double>> stageMs;
  /// True when the surfaces are the MPI's planes (config mpi_only); renderNovelView then keeps
  /// at least one fragment per plane (up to the rasterizer's 64).
  bool mpiOnly = false;
};

class Generator {
public:
  explicit Generator(network::SimpliNetwork& network);
  GeneratorOutput forward(const GeneratorInput& input, const GeneratorOptions& options = {}) const;
  network::SimpliNetwork& network() const { return network_; }

private:
  network::SimpliNetwork& network_;
};

/// Renders the generator's output into `target` (differentiable, as §6.8): colour RGB in
/// [-1, 1] (clamped), opacity, depth, weights.
raster::RenderedLayers renderNovelView(const GeneratorOutput& output,
                                       const scene::Camera& reference, const scene::Camera& target,
                                       const raster::RasterSettings& settings = {});

/// The output as a CPU MLI in the reference camera (RGB mapped to [0, 1]). With
/// dropEmptyBelow > 0, surfaces whose largest alpha is below it are left out (no empty layers).
mli::MLI toMLI(const GeneratorOutput& output, const scene::Camera& reference,
               float dropEmptyBelow = 0.0f);

} // namespace simpli::generator

#pragma once
// The steps of Generator::forward (spec §3), one concept per source file in
// model/src/generator/:
//  mpi_levels.cpp        features, level-0 MPI, level-1 discrepancy and corrected MPI
//  planes_to_layers.cpp  planes -> layers (deformer, group opacities, depths, RGBA1)
//  mli_corrections.cpp   the MLI corrections (render, unproject, attend, aggregate)
//  generator.cpp         input checks, orchestration, stage timing
//  output.cpp            novel-view rendering and conversion to a CPU MLI
//  scene_input.cpp       a scene read from disk -> GeneratorInput
// The view attention and the planes deformer (with the engine's fused attention core) are
// network modules: model/src/network/attention.cpp.
#include "simpli/model/generator/generator.h"

#include <chrono>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace simpli::generator {

/// Records (stage, milliseconds) pairs; with `finish` the device queue is drained at every
/// mark so the times are the stages' wall times. Reports each mark to GeneratorOptions::progress
/// (of `total` marks) and throws GeneratorCancelled when it returns false.
class StageClock {
public:
  StageClock(bool finish, std::vector<std::pair<std::string, double>>* out,
             const GeneratorOptions::ProgressFn* progress = nullptr, int total = 0);
  /// Closes the stage that started at the previous mark (or construction).
  void mark(const std::string& name);

private:
  bool finish_;
  std::vector<std::pair<std::string, double>>* out_;
  const GeneratorOptions::ProgressFn* progress_;
  int total_, done_ = 0;
  std::chrono::steady_clock::time_point last_;
};

/// f(x) computed on slices of `chunk` entries along axis 0 and concatenated, when no gradient
/// is being recorded (inference: bounds the memory of per-sample work such as per-view
/// features or per-plane convolutions, which the reference also loops over in eval mode);
/// with gradients, f(x) in one call. f must treat the entries of axis 0 independently.
ocl::Tensor chunked(const ocl::Tensor& x, int64_t chunk,
                    const std::function<ocl::Tensor(const ocl::Tensor&)>& f);

/// Everything the steps share: the network, the input, the options, derived sizes.
struct Context {
  const network::SimpliNetwork& net;
  const GeneratorInput& input;
  const GeneratorOptions& options;
  std::vector<double> planeDepths; ///< P depths, index 0 = farthest
  int V = 0, H = 0, W = 0;         ///< views and source image size
  int h0 = 0, w0 = 0;              ///< level 0 (scale_lvl0)
  int h1 = 0, w1 = 0;              ///< level 1 (scale_lvl1)
  int h2 = 0, w2 = 0;              ///< levels 2.. (scale_lvl2)
  StageClock* clock = nullptr;

  void hook(const std::string& name, const ocl::Tensor& value) const {
    if (options.stageHook)
      options.stageHook(name, value);
  }
};

/// Steps 1-4: the corrected MPI.
struct MpiLevels {
  ocl::Tensor features;      ///< [V, Cf, Hf, Wf] feature-extractor output
  ocl::Tensor fmpi0;         ///< [P, C0 + 1, h0, w0] level-0 features (tanh quirk applied) + alpha
  ocl::Tensor rendered;      ///< [V, C0, Hf, Wf] fMPI0 composited into every source
  ocl::Tensor renderWeights; ///< [V, P, 1, Hf, Wf] its per-plane compositing weights
  ocl::Tensor fmpi1;         ///< [P, Cs, h1, w1] corrected MPI features
};
MpiLevels runMpiLevels(const Context& ctx);

/// A surface set with its decoded RGBA: the mesh a correction renders, or the output.
struct Surfaces {
  ocl::Tensor rgba;  ///< [S, 4, h, w] RGB in [-1, 1], alpha in [0, 1]
  ocl::Tensor depth; ///< [S, h, w] reference-camera z
};

/// Step 5 (or its MPI-only replacement): the level-1 surfaces and what the corrections need.
struct Level1Surfaces {
  ocl::Tensor features;   ///< [S, Cs, h1, w1] fMLI0 (or fMPI1 when MPI-only)
  Surfaces mesh;          ///< RGBA1 and D1 at h1 x w1 (the level-2 discrepancy mesh)
  ocl::Tensor finalDepth; ///< [S, h2, w2] D, frozen for the corrections
};
Level1Surfaces planesToLayers(const Context& ctx, const MpiLevels& mpi);

/// One MLI correction (levels 2, 3, ...): `level` = 2 for the first. Renders `mesh` into the
/// sources, aggregates [error | image] on the final surfaces (`depth`) and refines `state`
/// ([S, Cs, h2, w2], already at the final resolution). Returns the new features; `render`
/// receives the source renders [V, 3, H, W].
ocl::Tensor mliCorrection(const Context& ctx, int level, const Surfaces& mesh,
                          const ocl::Tensor& depth, const ocl::Tensor& state, ocl::Tensor* render);

/// The default source renderer: the OpenCL rasterizer, one render per source view.
ocl::Tensor rasterizeIntoSources(const ocl::Tensor& rgba, const ocl::Tensor& depth,
                                 const GeneratorInput& input,
                                 const raster::RasterSettings& settings);

/// Raster settings that keep one fragment per surface for `surfaces` MPI planes (the
/// rasterizer keeps the K nearest fragments; K is raised up to its maximum of 64).
raster::RasterSettings settingsForSurfaces(raster::RasterSettings settings, int surfaces,
                                           bool mpiOnly);

} // namespace simpli::generator

#pragma once
// Evaluation with the paper's protocol: for every scene (or `scenes` synthetic scenes), R
// repeats of: draw V sources and N targets from a window of consecutive frames (training/sampler.h,
// no crop, no MixUp), build the layers from the sources, render every target, and score it
// against the held-out photo with PSNR / SSIM on the central 90 % crop (metrics/image_quality.h).
// The same samples are scored for the nearest-source-view baseline: the source image whose camera
// centre is closest to the target's, compared as it is. The samples depend only on the data and
// the options (not on the network), so evaluations of several networks are paired view by view.
#include "simpli/model/generator/generator.h"
#include "simpli/model/generator/scene_input.h"
#include "simpli/model/io/image.h"
#include "simpli/model/metrics/image_quality.h"
#include "simpli/model/network/network.h"
#include "simpli/model/raster/rasterizer.h"
#include "simpli/model/training/data.h"
#include "simpli/model/training/sampler.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace simpli::training {

struct EvalOptions {
  int repeats = 1;
  int views = 4;      ///< V
  int novelViews = 4; ///< N (fewer when the scene is short)
  int window = 0;     ///< frame window (0 = whole scene)
  int scenes = 1;     ///< scenes to use from endless (synthetic) data
  uint64_t seed = 0;
  int corrections = -1;
  raster::RasterSettings raster;
  double keptArea = 0.9;
  /// The sources are resized by this factor before the network (sampleInput); the MLI is built
  /// at that size and rendered into the targets at theirs. 1 = the sources as they are.
  double inputScale = 1.0;
  /// Every sample's reference camera widened by this fraction on every side
  /// (scene::widenedCamera): the MLI also covers what the targets see beyond the sources.
  double referenceMargin = 0.0;
  /// One untimed forward pass before the first timed one (PoCL compiles kernels on first use);
  /// off where build time is not reported (validation during training).
  bool warmUp = true;
};

/// Which frames one scored target view came from (indices into the scene's views).
struct EvalView {
  uint64_t scene = 0;
  int sample = 0; ///< repeat within the scene
  std::vector<int> sourceFrames;
  int targetFrame = 0, nearestFrame = 0;
};

/// The pictures of one scored view, for comparison grids: all [3, H, W] in [0, 1].
struct EvalViewImages {
  const EvalView& view;
  const io::Image &truth, &render, &nearest;
};

struct EvalResult {
  std::vector<EvalView> views;                        ///< per target view
  std::vector<metrics::ImageQuality> model, baseline; ///< per target view
  metrics::MeanStd modelPsnr, modelSsim, baselinePsnr, baselineSsim;
  /// Per sample: the forward pass (building the surfaces), after one untimed warm-up pass.
  std::vector<double> buildMs;
  metrics::MeanStd build; ///< of buildMs
};

/// The generator's input for one sample: its sources, their cameras and the sample's reference
/// camera through generator::scaledInput (exactly 1 keeps the images as they are; otherwise each
/// side becomes scaledSize(side, inputScale)). The targets keep their size. Throws simpli::Error
/// for a scale outside (0, 2].
generator::GeneratorInput sampleInput(const TrainingSample& sample, double inputScale,
                                      ocl::Dtype dtype);

/// Index of the camera in `sources` whose centre is closest to `target`'s (first on ties).
int nearestSourceView(const std::vector<scene::Camera>& sources, const scene::Camera& target);

/// The samples evaluate() scores, in its order (scene by scene, `repeats` per scene): `onSample`
/// gets each one with its scene index and repeat. The same options draw the same samples, so
/// other measurements (`simpli bench trade`) are paired with evaluate()'s view by view. Throws
/// simpli::Error for bad options or a scene with too few views.
void forEachEvalSample(
    TrainingData& data, const EvalOptions& options,
    const std::function<void(const TrainingSample& sample, uint64_t scene, int repeat)>& onSample);

/// A rendered colour [3, H, W] (RGB in [-1, 1]) as an image; `what` names the caller in errors.
io::Image renderedImage(const ocl::Tensor& colour, const char* what);

/// Builds the surfaces of one sample: a network's generator, or a non-learned baseline
/// (baselines/plane_sweep_stereo.h).
using SurfaceBuilder =
    std::function<generator::GeneratorOutput(const generator::GeneratorInput& input)>;

/// `onView`, when given, sees every scored view's pictures (to save comparison grids).
EvalResult evaluate(network::SimpliNetwork& network, TrainingData& data, const EvalOptions& options,
                    const std::function<void(int done, int total)>& progress = {},
                    const std::function<void(const EvalViewImages&)>& onView = {});

/// The same protocol for any builder; the sources reach it as `inputDtype` tensors.
/// options.corrections does not apply (the builder decides).
EvalResult evaluate(const SurfaceBuilder& build, ocl::Dtype inputDtype, TrainingData& data,
                    const EvalOptions& options,
                    const std::function<void(int done, int total)>& progress = {},
                    const std::function<void(const EvalViewImages&)>& onView = {});

} // namespace simpli::training

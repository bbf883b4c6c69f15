#pragma once
// Per-sample drawing of training views (spec §8.3, adapted to small scenes):
// pick a scene, V in [min_views, max_views] clipped so that at least one target remains, N =
// min(novel_views, frames - V) targets, a window of consecutive frames (sampling.window frames,
// widened to V + N, clipped to the scene; 0 = whole scene) at a random start, then V + N
// distinct frames of it in random order: the first V are the sources, the rest the targets.
// The reference camera is referenceCamera(sources). Optionally a zoom factor drawn from
// sampling.zoom (images resized by it and centre-cropped back, §8.3's random resize), then one
// random crop window (the same for every view), intrinsics updated for both; and source-only MixUp:
// with probability p a source image becomes (1 - lambda) * itself + lambda * another source of the
// sample, lambda ~ U[low, high]; the clean sources are kept for the intermediate losses. MixUp
// and the other photometric augmentations are in training/augment.h.
//
// Everything random comes from one TrainRandom whose state goes into checkpoints, so a
// resumed run draws the same samples as an uninterrupted one.
#include "simpli/model/io/image.h"
#include "simpli/model/scene/camera.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/data.h"
#include "simpli/model/training/random.h"

#include <array>
#include <string>
#include <vector>

namespace simpli::training {

struct TrainingSample {
  uint64_t sceneIndex = 0;
  std::string sceneRoot;
  std::vector<int> sourceFrames, targetFrames;
  std::vector<io::Image> sources;      ///< after MixUp (the network's input)
  std::vector<io::Image> cleanSources; ///< before MixUp (intermediate-loss targets)
  std::vector<io::Image> targets;
  std::vector<scene::Camera> sourceCameras, targetCameras;
  scene::Camera reference;
  double zoom = 1.0;               ///< zoom factor applied before the crop
  int cropX = 0, cropY = 0;        ///< crop window origin in the (zoomed) scene's pixels
  std::vector<int> mixupPartner;   ///< per source: the blended source index, -1 = none
  std::vector<double> mixupLambda; ///< per source: lambda (0 when not blended)
  /// Per source: the RGB gains of the photometric jitter (SamplingConfig::sourceExposureStd;
  /// empty when off).
  std::vector<std::array<double, 3>> sourceGains;
  /// Unsharp-mask amount applied to every view (SamplingConfig::sharpenProbability; 0 = none).
  double sharpen = 0.0;
  /// Per target, when the data knows it (synthetic scenes): height x width camera z in
  /// normalised units, 0 = no surface, after the same zoom and crop as the target image
  /// (nearest texel); empty otherwise.
  std::vector<std::vector<float>> targetDepths;
  /// The same per source (sourceFrames order).
  std::vector<std::vector<float>> sourceDepths;
};

/// Frames of one draw (indices into the scene's views).
struct FrameDraw {
  std::vector<int> sources, targets;
  int windowStart = 0, windowLength = 0;
};

/// Draws the frames for a scene of `frames` views (>= 2). Throws when frames < 2.
FrameDraw drawFrames(int frames, const SamplingConfig& config, TrainRandom& random);

/// The camera of the pixel window [x, x + width) x [y, y + height) of `camera`'s image:
/// pixel intrinsics keep their values, the principal point moves by (-x, -y), and the result
/// is made relative to the new size.
scene::Camera cropCamera(const scene::Camera& camera, int x, int y, int width, int height);
/// The pixels of that window (must lie inside the image).
io::Image cropImage(const io::Image& image, int x, int y, int width, int height);

/// The camera of `camera`'s image resized by `factor` (>= 1; relative intrinsics unchanged, size
/// rounded) and centre-cropped back to width x height: a zoom about the image centre.
scene::Camera zoomCamera(const scene::Camera& camera, double factor);
/// The pixels of that zoom (bilinear resize, then the centre crop zoomCamera describes).
io::Image zoomImage(const io::Image& image, double factor);
/// A width x height depth map through the same zoom (by `factor`) and then the crop window
/// [x, x + cropWidth) x [y, y + cropHeight), sampling the nearest texel (depths are not
/// averaged across edges).
std::vector<float> zoomCropDepth(const std::vector<float>& depth, int width, int height,
                                 double factor, int x, int y, int cropWidth, int cropHeight);

class Sampler {
public:
  Sampler(const SamplingConfig& config, uint64_t seed);
  /// Draws a scene (uniformly; for endless data a random 31-bit index) and a sample of it.
  TrainingSample draw(TrainingData& data);
  /// A sample of a given scene (the scene-drawing step skipped); `depths` (per view, as
  /// TrainingData::depths) fills targetDepths. Depths draw no random numbers, so a sample's
  /// frames, crop and MixUp are the same with or without them.
  TrainingSample drawFromScene(const scene::Scene& scene, uint64_t sceneIndex,
                               const std::vector<std::vector<float>>* depths = nullptr);

  TrainRandom& random() { return random_; }
  const SamplingConfig& config() const { return config_; }

private:
  // drawFromScene after its frames are drawn (draw() draws them before the scene's images
  // exist, so that only those views need rendering; the random stream is the same).
  TrainingSample drawWithFrames(const scene::Scene& scene, uint64_t sceneIndex,
                                const std::vector<std::vector<float>>* depths, const FrameDraw& d);
  SamplingConfig config_;
  TrainRandom random_;
};

} // namespace simpli::training

#pragma once
// A training run's settings, read from JSON. Defaults follow the reference (the method spec
// §8): Adam lr 3e-4, betas 0.9 / 0.999, eps 1e-8, ExponentialLR gamma 0.999994 per step, global
// gradient-norm clip 20, and the loss weights of configs/tblock4_train.yaml (l1 1, perceptual
// 0, the four intermediate L1 losses 1 each, smooth_layers 0.01). Sampling (§8.3) is adapted
// so that it works on small scenes: V is drawn uniformly from [min_views, max_views] clipped
// to what the scene allows, and the frame window and crop are plain settings.
//
// JSON layout (only "network" is required; unknown keys are errors so that a typo cannot fall
// back to a default silently):
// {
//   "network": "official-4l" | "official-8l" | "path/to/net.json" (relative to this file)
//              | { ...a network config object (config.h)... },
//   "dtype": "f32" | "f64",                 // parameters and computation (f64: reference runs)
//   "seed": 0,                              // network initialisation and sampling
//   "steps": 1000, "checkpoint_every": 100,
//   "corrections": -1,                      // MLI corrections run in training (-1 = all)
//   "max_fragments": 16,                    // rasterizer k-buffer size
//   "ema_decay": 0,                         // > 0: keep an EMA of the weights (reference 0.9)
//   "optimizer": {"lr": 3e-4, "beta1": 0.9, "beta2": 0.999, "eps": 1e-8,
//                 "gamma": 0.999994, "clip_grad_norm": 20,
//                 "warmup_steps": 0},        // not in the reference: linear lr warm-up
//   "loss_weights": {"l1": 1, "perceptual": 0, "intermediate_loss_0_l1": 1,
//                    "intermediate_loss_1_l1": 1, "intermediate_loss_2_l1": 1,
//                    "intermediate_loss_3_l1": 1, "smooth_layers": 0.01,
//                    "depth": 0, "mpi_depth": 0, "ssim": 0}, // not in the reference:
//                                                           // training/losses.h
//   "sampling": {"min_views": 2, "max_views": 8, "novel_views": 4, "window": 0,
//                "crop": [0, 0],            // [height, width]; 0 = the whole image
//                "zoom": [1.0],             // zoom factors >= 1, one drawn per sample
//                "mixup_probability": 0.9, "mixup_lambda": [0.0, 0.4],
//                "reference_margin": 0,   // not in the reference: widenedCamera
//                "source_gain_std": [0, 0],   // not in the reference: [exposure, channel]
//                "sharpen": [0, 0]},          // not in the reference: [probability, max amount]
//   "synthetic": {"style": "objects" | "world",   // the scenes of data synthetic[:SEED]
//                 "textures": "procedural" | "photo", "photo_probability": 0.85,
//                 "photo_dir": "",                  // "" = the Debian photo packages
//                 "photos_required": true,          // photo textures but no photos: error
//                                                   // (true) or procedural + notice (false)
//                 "views": 12, "objects": 8, "antialias": 4,
//                 "size": "192x128",                // WxH; --size overrides; "" = 192x128
//                 "translation": [0.01, 0.3],       // world style: camera spread / near depth
//                 "object_size": [0.08, 0.6],       // world style: occluder width / image width
//                 "bushes": [0, 0],                 // world style: leaf clusters per scene
//                 "bush_scale": [1, 1],             // world style: x their size, log-uniform
//                 "bush_shared_texture": 0}         // world style: P(leaves share a photo)
// }
#include "simpli/model/network/config.h"
#include "simpli/model/synthetic/scene.h"

#include "simpli/ocl/program_cache.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace simpli::training {

struct OptimizerConfig {
  double lr = 3e-4;
  double beta1 = 0.9, beta2 = 0.999, eps = 1e-8;
  double gamma = 0.999994; ///< ExponentialLR factor per step
  double clipGradNorm = 20.0;
  /// Linear lr warm-up over the run's first steps (ocl::ExponentialLr); 0 = none, as in the
  /// reference. For runs warm-started from trained weights with a fresh Adam state.
  int64_t warmupSteps = 0;
};

/// Per-sample drawing of sources and targets (sampler.h).
struct SamplingConfig {
  int minViews = 2, maxViews = 8; ///< V range, clipped to frames - 1
  int novelViews = 4;             ///< N: up to this many targets (fewer when the scene is short)
  /// Frames in the window of consecutive frames the views are drawn from; it is widened to
  /// V + N and clipped to the scene; 0 = the whole scene.
  int window = 0;
  int cropHeight = 0, cropWidth = 0; ///< random crop (same window for every view); 0 = none
  /// Zoom factors, one drawn uniformly per sample (for every view): the images are resized by
  /// it and centre-cropped back to their size before the random crop (the reference's random
  /// resize, §8.3: {1.0, 1.2, ..., 1.6}). {1.0} = no zoom and no random draw.
  std::vector<double> zoomScales{1.0};
  double mixupProbability = 0.9; ///< per source image
  double mixupLambdaMin = 0.0, mixupLambdaMax = 0.4;
  /// The reference camera widened by this fraction of the image on every side
  /// (scene::widenedCamera; not in the reference, which uses 0): the MLI then also covers what
  /// the targets see beyond the sources' common frame, and the network learns to fill that
  /// border. The training monitor scores with the same margin.
  double referenceMargin = 0.0;
  /// Per-source photometric jitter (not in the reference; 0 = none): every source image the
  /// network sees (after MixUp) is multiplied, in [0, 1], by exp(e + c_ch) and clipped, with
  /// e ~ N(0, sourceExposureStd) per source and c_ch ~ N(0, sourceChannelStd) per channel.
  /// Frames of a real capture differ by a few % (LLFF flower: 0.95 .. 1.06 of the mean of five
  /// views at matched points); synthetic renders agree exactly, so a network trained on them
  /// alone may rely on exact colour agreement. The draws are a function of the sample (they do
  /// not advance the sampler's stream): the same seed draws the same samples with or without it.
  double sourceExposureStd = 0.0, sourceChannelStd = 0.0;
  /// Sharpening of every image of a sample (not in the reference; 0 = none): with probability
  /// sharpenProbability, all views (sources and targets alike) get the same unsharp mask
  /// x + a (x - G(x)), G a Gaussian of sigma 1 pixel, a uniform in [0, sharpenMax], clipped to
  /// [-1, 1]. Flower's frames at 256x192 carry ~4x the high-frequency energy (mean |Laplacian|
  /// 0.11) of the world scenes (0.026 .. 0.033), whose photo textures are smooth; sharpening the
  /// held-out synthetic views costs the shipped network 0.9 dB of its lead over plane-sweep
  /// stereo, gains and noise cost it ~0.1 (docs/training.md, session 17). Drawn like the gains,
  /// from the sampler's state without advancing it.
  double sharpenProbability = 0.0, sharpenMax = 0.0;
};

/// The procedural scenes of `simpli train synthetic[:SEED]` (synthetic/scene.h; ignored for
/// scene folders). The defaults are the generator's, so a config without the section trains
/// on the scenes it always did.
struct SyntheticConfig {
  synthetic::SceneStyle style = synthetic::SceneStyle::Objects;
  synthetic::TextureSet textures = synthetic::TextureSet::Procedural;
  double photoProbability = 0.85; ///< per surface, with photo textures
  std::string photoDir;           ///< photos from this folder; "" = the Debian photo packages
  /// Photo textures asked for but no photographs found: true = an error naming the config
  /// field and how to install them; false = procedural textures and a one-line notice.
  bool photosRequired = true;
  int views = 12;  ///< frames per scene (a camera path the sampler draws windows from)
  int objects = 8; ///< objects (objects style) or occluders (world style)
  int antialias = 4;
  int width = 0, height = 0; ///< 0 = the generator's 192 x 128; --size overrides
  /// World style: the farthest camera centre's distance from the mean centre / nearest depth,
  /// drawn log-uniform in [min, max] per scene (synthetic::WorldStyleParams; the objects style
  /// ignores it). Real handheld captures reach 0.25 .. 0.55 (LLFF flower: ~0.28).
  double translationMin = synthetic::WorldStyleParams{}.translationMin;
  double translationMax = synthetic::WorldStyleParams{}.translationMax;
  /// World style: the occluders' apparent width / image width, log-uniform in [min, max].
  double objectSizeMin = synthetic::WorldStyleParams{}.objectSizeMin;
  double objectSizeMax = synthetic::WorldStyleParams{}.objectSizeMax;
  /// World style: bushes (clusters of small leaves) per scene, uniform in [min, max].
  int bushesMin = synthetic::WorldStyleParams{}.bushesMin;
  int bushesMax = synthetic::WorldStyleParams{}.bushesMax;
  /// World style: each bush's size x a factor, log-uniform in [min, max] (1 = as before).
  double bushScaleMin = synthetic::WorldStyleParams{}.bushScaleMin;
  double bushScaleMax = synthetic::WorldStyleParams{}.bushScaleMax;
  /// World style: probability that a bush's leaves share one photo (0 = a texture each).
  double bushSharedTexture = synthetic::WorldStyleParams{}.bushSharedTexture;
};

/// The loss terms, in log order, with the reference's key names.
const std::vector<std::string>& lossTermNames();

struct TrainingConfig {
  network::NetworkConfig network;
  ocl::Dtype dtype = ocl::Dtype::F32;
  uint64_t seed = 0;
  int64_t steps = 1000;
  int64_t checkpointEvery = 100;
  int corrections = -1;
  int maxFragments = 16;
  /// Decay of the exponential moving average of the weights written beside them
  /// (training/average.h); 0 = none.
  double emaDecay = 0;
  OptimizerConfig optimizer;
  std::map<std::string, double> lossWeights; ///< every lossTermNames() key
  SamplingConfig sampling;
  SyntheticConfig synthetic;

  TrainingConfig(); ///< the defaults above; `network` is NetworkConfig{} until set
  double weight(const std::string& term) const;
  /// Throws simpli::Error naming `source` and the field for a bad value.
  void validate(const std::string& source) const;
};

/// Parses a training config; relative network paths are resolved against `baseDir`.
TrainingConfig parseTrainingConfig(const std::string& jsonText, const std::string& source,
                                   const std::string& baseDir);
TrainingConfig loadTrainingConfig(const std::string& path);
/// Self-contained JSON (the network inline); parseTrainingConfig reads it back to an equal
/// config.
std::string toJson(const TrainingConfig& config);

/// The settings a resumed run must share with the run it continues (everything except steps
/// and checkpoint_every); returns the first differing field's name, or "" when they agree.
std::string firstIncompatibleField(const TrainingConfig& a, const TrainingConfig& b);

/// The network of a config named as resolveTrainingConfig() takes it (`simpli eval --config`): a
/// shipped name (official-4l, tiny-prior, a training recipe) or a path to a training config (its
/// "network") or to a network config.
network::NetworkConfig resolveNetworkOrTrainingConfig(const std::string& nameOrPath);

/// The training config a user names (`simpli train --config`, vtkSIMPLITrain's Config): a name
/// is the shipped <networkConfigDir()>/training/<name>.json if it exists, else the network
/// config of that name trained with the default settings; a path (containing '/' or ending in
/// .json) is a training config or, failing that, a network config with default settings.
/// Throws simpli::Error naming the config.
TrainingConfig resolveTrainingConfig(const std::string& nameOrPath);

} // namespace simpli::training

#pragma once
// From a scene read from disk (scene/readers.h) to the generator's input: the chosen source
// views' images as one [V, 3, H, W] tensor, their cameras, and the virtual reference camera
// (the pose average of the sources, spec §6.1) at the sources' size.
#include "simpli/model/generator/generator.h"
#include "simpli/model/io/image.h"
#include "simpli/model/scene/scene.h"

#include <string>
#include <vector>

namespace simpli::generator {

/// Where the planes' depth range comes from.
enum class DepthRangeSource {
  Config, ///< the network config's min/max depth (1..100 in the reference; what it trained on)
  Scene   ///< the scene's near/far bounds (normalised units): planes only where the scene is
};

struct SceneInputOptions {
  std::vector<int> views; ///< source view indices; empty = every view
  DepthRangeSource depthRange = DepthRangeSource::Config;
  ocl::Dtype dtype = ocl::Dtype::F32;
  /// The images are resized to scaledSize(size, inputScale) before the network (the MLI is
  /// built at that size); 1 = as they are. A network holds best near the size it was trained
  /// at (README, "Input size").
  double inputScale = 1.0;
  /// The reference camera widened by this fraction on every side (scene::widenedCamera).
  double referenceMargin = 0.0;
};

/// `size` x `scale` rounded to a multiple of 16 (the network's grid), at least 16.
int scaledSize(int size, double scale);

/// Throws simpli::Error naming `what` unless 0 < scale <= 2.
void checkInputScale(double scale, const std::string& what);

/// The sources as the network sees them at `inputScale`: every image resized to scaledSize of
/// each side (exactly 1 keeps them as they are, whatever their size), as one [V, 3, h, w] tensor;
/// the cameras and `reference` with that size (relative intrinsics: only the size changes). The
/// depth range is left to the caller. Throws simpli::Error for a scale outside (0, 2], no images,
/// images of different sizes or a camera count that is not the image count.
GeneratorInput scaledInput(const std::vector<const io::Image*>& images,
                           std::vector<scene::Camera> cameras, scene::Camera reference,
                           double inputScale, ocl::Dtype dtype);

/// Throws simpli::Error naming the scene and the index for a view out of range, a repeated
/// view, an empty scene, views of different sizes or an input scale outside (0, 2].
GeneratorInput sceneInput(const scene::Scene& scene, const SceneInputOptions& options = {});

/// The views sceneInput uses (options.views, or all), validated as sceneInput does.
std::vector<int> sceneInputViews(const scene::Scene& scene, const std::vector<int>& views);

} // namespace simpli::generator

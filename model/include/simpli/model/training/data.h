#pragma once
// Where training scenes come from: a folder of scenes (every subfolder a scene readScene
// understands), a single scene folder, or the procedural synthetic source ("synthetic" or
// "synthetic:SEED": endless random scenes generated in memory), or a weighted mixture of those.
#include "simpli/model/scene/scene.h"
#include "simpli/model/training/config.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace simpli::training {

struct DataOptions {
  /// Resize every image to height x width (relative intrinsics unchanged); 0 = keep (scene
  /// readers already floor sizes to multiples of 16).
  int height = 0, width = 0;
  /// Scene folders: read images_<factor> (LLFF / NeRF layout); 0 = the folder whose images are
  /// closest to `width` when that is given, else images/ (scene::chooseImageFolder).
  int imagesFactor = 0;
  /// The synthetic source's scenes (a training config's "synthetic" section); height / width
  /// above, when given, override its size.
  SyntheticConfig synthetic;
  /// Names the config in errors about the synthetic section (its file or name).
  std::string configSource = "training config";
};

class TrainingData {
public:
  virtual ~TrainingData() = default;
  /// Number of scenes; 0 means endless (synthetic): any index is valid.
  virtual uint64_t sceneCount() const = 0;
  /// Scene `index`; the reference stays valid until the next call.
  virtual const scene::Scene& scene(uint64_t index) = 0;
  /// Number of views of scene `index` (without rendering it, where that is cheaper).
  virtual int frameCount(uint64_t index) { return int(scene(index).size()); }
  /// Scene `index` with the images of (at least) the views in `frames`; the other views may
  /// have none: the synthetic source renders only their depth, which is most of a training
  /// step's scene cost saved. Everything else is as scene(index).
  virtual const scene::Scene& sceneForFrames(uint64_t index, const std::vector<int>& frames) {
    (void)frames;
    return scene(index);
  }
  /// One line for logs: "3 scenes under /data" or "synthetic scenes, seed 7".
  virtual std::string describe() const = 0;
  /// Ground-truth depth of scene `index` (call scene(index) first): per view, height x width
  /// camera z in the scene's normalised units, 0 where no surface is hit (sky); null when the
  /// data has none (photographed scenes). Valid as long as the scene reference.
  virtual const std::vector<std::vector<float>>* depths(uint64_t index) {
    (void)index;
    return nullptr;
  }
};

/// One source of a training mixture and its share of the samples (relative to the others).
struct DataSource {
  std::string spec; ///< as openTrainingData's spec
  double weight = 1;
};

/// "SPEC" or "SPEC@WEIGHT" (WEIGHT a positive finite number, e.g. "synthetic:1@3" or
/// "scenes/llff@0.5"); text that names an existing path is taken whole. Throws naming the text.
DataSource parseDataSource(const std::string& text);

/// Several sources mixed: every sample's scene comes from source k with probability weight_k /
/// sum(weights), decided by the scene index the sampler draws (the mixture is endless), so a
/// resumed run draws the same scenes. A synthetic source gets that index itself (its scenes
/// are those of the same source alone); a folder source a hash of it modulo its scene count.
/// One source is opened as openTrainingData(spec) (its weight does not matter). Throws naming
/// the source on any problem, and when `sources` is empty.
std::unique_ptr<TrainingData> openTrainingData(const std::vector<DataSource>& sources,
                                               const DataOptions& options = {});

/// Opens `spec` (see the header comment). Folder scenes are read lazily and kept in memory.
/// Throws simpli::Error naming the path when it does not exist, holds no scene, or a subfolder
/// is not a readable scene; for synthetic data with photo textures, reads the photographs once
/// (synthetic::PhotoLibrary::cached) and, when there are none, throws an error naming
/// options.configSource, the field and how to install them (photos_required) or falls back
/// to procedural textures, saying so in describe().
std::unique_ptr<TrainingData> openTrainingData(const std::string& spec,
                                               const DataOptions& options = {});

/// "WxH" (e.g. "192x128"; io::parseImageSize) -> width, height: what the network trains and
/// evaluates on, both multiples of 16 in 16..16384; `what` names the option in errors.
void parseWidthHeight(const std::string& text, const std::string& what, int& width, int& height);

} // namespace simpli::training

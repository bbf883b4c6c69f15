// Training scene sources: scene folders (read lazily, cached) and the procedural source.
#include "simpli/model/training/data.h"

#include "simpli/error.h"
#include "simpli/model/io/image_size.h"
#include "simpli/model/scene/scene_folders.h"
#include "simpli/model/synthetic/photos.h"
#include "simpli/model/synthetic/procedural_source.h"
#include "simpli/model/synthetic/random.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <numeric>
#include <optional>
#include <regex>
#include <sstream>

namespace simpli::training {
namespace {

namespace fs = std::filesystem;

void resizeScene(scene::Scene& scene, const DataOptions& o) {
  if (o.height <= 0 || o.width <= 0)
    return;
  for (scene::SceneView& v : scene.views) {
    if (!v.image.empty() && (v.image.width != o.width || v.image.height != o.height))
      v.image = io::resizeImage(v.image, o.width, o.height);
    // Relative intrinsics describe the image extent, which a resize maps onto itself.
    v.camera.width = o.width;
    v.camera.height = o.height;
  }
}

class FolderData : public TrainingData {
public:
  FolderData(std::string root, std::vector<std::string> scenes, const DataOptions& o)
      : root_(std::move(root)), paths_(std::move(scenes)), options_(o) {}
  uint64_t sceneCount() const override { return paths_.size(); }
  const scene::Scene& scene(uint64_t index) override {
    if (index >= paths_.size())
      fail("training data ", root_, ": scene index ", index, " out of range (", paths_.size(),
           " scenes)");
    auto it = cache_.find(index);
    if (it == cache_.end()) {
      scene::SceneReadOptions ro;
      ro.imagesFactor = options_.imagesFactor;
      ro.preferredWidth = options_.width;
      // A size given: one resize from the stored images to it (not a floor to 16 first).
      if (options_.width > 0 && options_.height > 0)
        ro.sizeMultiple = 1;
      scene::Scene s = scene::readScene(paths_[index], ro);
      resizeScene(s, options_);
      if (s.size() < 2)
        fail("training data: scene ", paths_[index], " has ", s.size(),
             " view(s); training needs at least 2 (a source and a target)");
      it = cache_.emplace(index, std::move(s)).first;
    }
    return it->second;
  }
  std::string describe() const override {
    return paths_.size() == 1 && paths_[0] == root_
               ? "scene " + root_
               : std::to_string(paths_.size()) + " scenes under " + root_;
  }

private:
  std::string root_;
  std::vector<std::string> paths_;
  DataOptions options_;
  std::map<uint64_t, scene::Scene> cache_;
};

class SyntheticData : public TrainingData {
public:
  SyntheticData(uint64_t seed, const DataOptions& o)
      : seed_(seed), source_(params(o, textureNote_), seed) {}
  uint64_t sceneCount() const override { return 0; }
  const scene::Scene& scene(uint64_t index) override {
    const int n = frameCount(index);
    std::vector<int> all(static_cast<size_t>(n));
    std::iota(all.begin(), all.end(), 0);
    return sceneForFrames(index, all);
  }
  int frameCount(uint64_t index) override { return int(geometry(index).cameras.size()); }
  const scene::Scene& sceneForFrames(uint64_t index, const std::vector<int>& frames) override {
    const bool covered =
        current_ && currentIndex_ == index && std::all_of(frames.begin(), frames.end(), [&](int f) {
          return f >= 0 && f < int(current_->size()) && !current_->views[size_t(f)].image.empty();
        });
    if (!covered) {
      synthetic::SyntheticSample s = source_.sample(geometry(index), index, frames);
      current_ = std::move(s.scene);
      depths_ = std::move(s.depths);
      currentIndex_ = index;
    }
    return *current_;
  }
  const std::vector<std::vector<float>>* depths(uint64_t index) override {
    if (!current_ || currentIndex_ != index)
      fail("synthetic data: depths of scene ", index, " asked before the scene");
    return &depths_;
  }
  std::string describe() const override {
    const synthetic::SyntheticSceneParams& p = source_.params();
    return "synthetic scenes (seed " + std::to_string(seed_) + ", " + synthetic::toString(p.style) +
           " style, " + std::to_string(p.views) + " views of " + std::to_string(p.width) + "x" +
           std::to_string(p.height) + ", " + textureNote_ + ")";
  }

private:
  // The generated scene of `index` (cheap next to rendering it), kept for the render after
  // frameCount.
  const synthetic::SyntheticScene& geometry(uint64_t index) {
    if (!geometry_ || geometryIndex_ != index) {
      geometry_ = source_.geometry(index);
      geometryIndex_ = index;
    }
    return *geometry_;
  }
  static synthetic::SyntheticSceneParams params(const DataOptions& o, std::string& note) {
    const SyntheticConfig& c = o.synthetic;
    synthetic::SyntheticSceneParams p;
    p.style = c.style;
    p.views = c.views;
    p.objects = c.objects;
    p.antialias = c.antialias;
    p.photoProbability = c.photoProbability;
    p.world.translationMin = c.translationMin;
    p.world.translationMax = c.translationMax;
    p.world.objectSizeMin = c.objectSizeMin;
    p.world.objectSizeMax = c.objectSizeMax;
    p.world.bushesMin = c.bushesMin;
    p.world.bushesMax = c.bushesMax;
    p.world.bushScaleMin = c.bushScaleMin;
    p.world.bushScaleMax = c.bushScaleMax;
    p.world.bushSharedTexture = c.bushSharedTexture;
    if (c.height > 0 && c.width > 0) {
      p.height = c.height;
      p.width = c.width;
    }
    if (o.height > 0 && o.width > 0) {
      p.height = o.height;
      p.width = o.width;
    }
    note = "procedural textures";
    if (c.textures == synthetic::TextureSet::Photo) {
      p.photos = synthetic::PhotoLibrary::cached(c.photoDir);
      const std::string where =
          c.photoDir.empty() ? "the Debian photo packages" : "'" + c.photoDir + "'";
      if (p.photos->empty()) {
        if (c.photosRequired)
          fail(o.configSource,
               ": field \"synthetic.textures\" is \"photo\", but no photographs "
               "were found in ",
               where, "; ",
               c.photoDir.empty() ? synthetic::photoInstallHint() : "add .jpg or .png files",
               ", or set \"synthetic.photos_required\": false to fall back to procedural "
               "textures");
        note = "procedural textures: NO PHOTOGRAPHS FOUND in " + where + " (" +
               (c.photoDir.empty() ? synthetic::photoInstallHint() : "add .jpg or .png files") +
               ")";
      } else {
        p.textures = synthetic::TextureSet::Photo;
        note = "photo textures on " + std::to_string(int(std::lround(100 * c.photoProbability))) +
               " % of the surfaces: " + p.photos->describe();
      }
    }
    return p;
  }
  uint64_t seed_;
  std::string textureNote_;
  synthetic::ProceduralSceneSource source_;
  std::optional<scene::Scene> current_;
  std::vector<std::vector<float>> depths_; ///< of current_
  uint64_t currentIndex_ = 0;
  std::optional<synthetic::SyntheticScene> geometry_;
  uint64_t geometryIndex_ = 0;
};

// Sources drawn by weight from the sampler's scene index (sceneCount 0: the sampler draws a
// 31-bit index, and every index maps to one source's scene).
class MixedData : public TrainingData {
public:
  MixedData(std::vector<std::unique_ptr<TrainingData>> parts, const std::vector<double>& weights)
      : parts_(std::move(parts)) {
    const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
    double sum = 0;
    for (double w : weights)
      cumulative_.push_back(sum += w / total);
    cumulative_.back() = 1;
  }
  uint64_t sceneCount() const override { return 0; }
  const scene::Scene& scene(uint64_t index) override {
    const auto [part, inner] = locate(index);
    return parts_[part]->scene(inner);
  }
  const std::vector<std::vector<float>>* depths(uint64_t index) override {
    const auto [part, inner] = locate(index);
    return parts_[part]->depths(inner);
  }
  int frameCount(uint64_t index) override {
    const auto [part, inner] = locate(index);
    return parts_[part]->frameCount(inner);
  }
  const scene::Scene& sceneForFrames(uint64_t index, const std::vector<int>& frames) override {
    const auto [part, inner] = locate(index);
    return parts_[part]->sceneForFrames(inner, frames);
  }
  std::string describe() const override {
    std::ostringstream out;
    out << "a mixture of " << parts_.size() << " sources: ";
    double previous = 0;
    for (size_t k = 0; k < parts_.size(); ++k) {
      out << (k ? "; " : "") << std::fixed << std::setprecision(1)
          << 100 * (cumulative_[k] - previous) << " % " << parts_[k]->describe();
      previous = cumulative_[k];
    }
    return out.str();
  }

private:
  // (source, its scene index) of mixture index `index`.
  std::pair<size_t, uint64_t> locate(uint64_t index) const {
    const uint64_t h = synthetic::mix64(index);
    const double u = double(h >> 11) * 0x1.0p-53; // uniform in [0, 1)
    const size_t part =
        size_t(std::upper_bound(cumulative_.begin(), cumulative_.end(), u) - cumulative_.begin());
    const size_t k = std::min(part, parts_.size() - 1);
    const uint64_t count = parts_[k]->sceneCount();
    return {k, count == 0 ? index : synthetic::mix64(h) % count};
  }
  std::vector<std::unique_ptr<TrainingData>> parts_;
  std::vector<double> cumulative_; ///< the sources' shares, summed: source k ends at [k]
};

} // namespace

DataSource parseDataSource(const std::string& text) {
  const size_t at = text.rfind('@');
  if (at == std::string::npos || fs::exists(text))
    return {text, 1.0};
  const std::string spec = text.substr(0, at), weight = text.substr(at + 1);
  static const std::regex number("^[0-9]*\\.?[0-9]+([eE][-+]?[0-9]+)?$");
  if (spec.empty() || !std::regex_match(weight, number))
    fail("training data '", text, "': expected SPEC or SPEC@WEIGHT with a positive number ",
         "as WEIGHT, e.g. synthetic:1@3");
  const double w = std::stod(weight);
  if (!(w > 0) || !std::isfinite(w))
    fail("training data '", text, "': weight ", weight, " must be positive and finite");
  return {spec, w};
}

std::unique_ptr<TrainingData> openTrainingData(const std::vector<DataSource>& sources,
                                               const DataOptions& o) {
  if (sources.empty())
    fail("training data: no source given");
  if (sources.size() == 1)
    return openTrainingData(sources[0].spec, o);
  std::vector<std::unique_ptr<TrainingData>> parts;
  std::vector<double> weights;
  for (const DataSource& d : sources) {
    if (!(d.weight > 0) || !std::isfinite(d.weight))
      fail("training data '", d.spec, "': weight ", d.weight, " must be positive and finite");
    parts.push_back(openTrainingData(d.spec, o));
    weights.push_back(d.weight);
  }
  return std::make_unique<MixedData>(std::move(parts), weights);
}

void parseWidthHeight(const std::string& text, const std::string& what, int& width, int& height) {
  const io::ImageSize size = io::parseImageSize(text, what, {16, 16384, 16});
  width = size.width;
  height = size.height;
}

std::unique_ptr<TrainingData> openTrainingData(const std::string& spec, const DataOptions& o) {
  if (spec == "synthetic" || spec.rfind("synthetic:", 0) == 0) {
    uint64_t seed = 0;
    if (spec.size() > 10) {
      const std::string s = spec.substr(10);
      if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos || s.size() > 19)
        fail("training data '", spec, "': expected synthetic or synthetic:SEED (SEED >= 0)");
      seed = std::stoull(s);
    }
    return std::make_unique<SyntheticData>(seed, o);
  }
  const fs::path root(spec);
  if (!fs::exists(root))
    fail("training data '", spec, "' does not exist");
  if (!fs::is_directory(root))
    fail("training data '", spec, "' is not a folder");
  // A scene folder itself, or a folder of scene folders.
  std::vector<std::string> scenes;
  if (scene::isSceneFolder(spec)) {
    scenes.push_back(spec);
  } else {
    for (const scene::SceneFolder& s : scene::listSceneFolders(spec)) {
      if (!s.problem.empty())
        fail("training data '", spec, "': subfolder '", s.name, "' is not a scene: ", s.problem);
      scenes.push_back(s.path);
    }
    if (scenes.empty())
      fail("training data '", spec,
           "' is neither a scene folder nor a folder of scene folders (no subfolders)");
  }
  return std::make_unique<FolderData>(spec, std::move(scenes), o);
}

} // namespace simpli::training

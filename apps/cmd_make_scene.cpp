// `simpli make-scene --out DIR`: generates a random forward-facing scene with exact ground
// truth (model/synthetic/) and writes it in LLFF layout with depth maps and scene.json.
#include "commands.h"

#include "simpli/error.h"
#include "simpli/model/io/image_size.h"
#include "simpli/model/io/staged_folder.h"
#include "simpli/model/synthetic/photos.h"
#include "simpli/model/synthetic/scene_writer.h"
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

namespace simpli::app {

namespace {

struct MakeSceneOptions {
  std::string out;
  int64_t seed = 0;
  int views = 12;
  std::string size = "192x128";
  int objects = 8;
  int antialias = 4;
  std::string style = "objects";
  std::string textures = "procedural";
  std::string photoDir;
  std::vector<double> objectSize;          ///< world style: MIN,MAX occluder width / image width
  std::vector<int> bushes;                 ///< world style: MIN,MAX leaf clusters per scene
  std::vector<double> bushScale;           ///< world style: MIN,MAX factor on each bush's size
  std::optional<double> bushSharedTexture; ///< world style: P(a bush's leaves share a photo)
  bool force = false;
};

// An option of the form MIN,MAX (one value is taken, and refused later with its name).
template <typename T>
void addMinMaxOption(CLI::App* cmd, const char* name, std::vector<T>& out,
                     const std::string& help) {
  cmd->add_option(name, out, help)->delimiter(',')->expected(1, 2);
}

// A world-style option's MIN,MAX (two `what`: numbers, counts) within [lowest, highest].
template <typename T>
std::pair<T, T> worldRange(const std::vector<T>& values, const char* flag,
                           synthetic::SceneStyle style, T lowest, T highest, const char* what,
                           const char* unit) {
  if (style != synthetic::SceneStyle::World)
    fail(flag, ": only with --style world");
  if (values.size() != 2)
    fail(flag, ": expected MIN,MAX (two ", what, "), got ", values.size());
  const T low = values[0], high = values[1];
  if (!(low >= lowest && low <= high && high <= highest))
    fail(flag, " ", low, ",", high, ": need ", lowest, " <= MIN <= MAX <= ", highest, unit);
  return {low, high};
}

void runMakeScene(const MakeSceneOptions& o) {
  using namespace synthetic;
  synthetic::SyntheticSceneParams p;
  if (o.seed < 0)
    fail("--seed ", o.seed, ": must be >= 0");
  p.seed = static_cast<uint64_t>(o.seed);
  if (o.views < 1)
    fail("--views ", o.views, ": need at least 1 view");
  if (o.objects < 0)
    fail("--objects ", o.objects, ": must be >= 0");
  if (o.antialias < 1 || o.antialias > 16)
    fail("--antialias ", o.antialias, ": must be 1 .. 16");
  p.views = o.views;
  p.objects = o.objects;
  p.antialias = o.antialias;
  p.style = synthetic::parseSceneStyle(o.style, "--style");
  p.textures = synthetic::parseTextureSet(o.textures, "--textures");
  if (!o.photoDir.empty() && p.textures != synthetic::TextureSet::Photo)
    fail("--photo-dir '", o.photoDir, "': only with --textures photo");
  const io::ImageSize size = io::parseImageSize(o.size, "--size");
  p.width = size.width;
  p.height = size.height;
  using World = synthetic::WorldStyleParams;
  if (!o.objectSize.empty())
    std::tie(p.world.objectSizeMin, p.world.objectSizeMax) =
        worldRange(o.objectSize, "--object-size", p.style, World::kObjectSizeLow,
                   World::kObjectSizeHigh, "numbers", " (x the image width)");
  if (!o.bushes.empty())
    std::tie(p.world.bushesMin, p.world.bushesMax) =
        worldRange(o.bushes, "--bushes", p.style, 0, World::kBushesHigh, "counts", "");
  if (!o.bushScale.empty())
    std::tie(p.world.bushScaleMin, p.world.bushScaleMax) =
        worldRange(o.bushScale, "--bush-scale", p.style, World::kBushScaleLow,
                   World::kBushScaleHigh, "numbers", "");
  if (o.bushSharedTexture) {
    const double share = *o.bushSharedTexture;
    if (p.style != synthetic::SceneStyle::World || p.textures != synthetic::TextureSet::Photo)
      fail("--bush-shared-texture: only with --style world --textures photo");
    if (!(share >= 0 && share <= 1))
      fail("--bush-shared-texture ", share, ": must be 0 .. 1 (a probability)");
    p.world.bushSharedTexture = share;
  }
  p.validate(); // the remaining limits (e.g. views <= 10000), named by field
  io::checkOutputLocation(o.out, "--out");

  const auto start = std::chrono::steady_clock::now();
  if (p.textures == synthetic::TextureSet::Photo) {
    p.photos = synthetic::PhotoLibrary::cached(o.photoDir);
    if (p.photos->empty())
      std::fprintf(
          stderr, "note: no photographs found in %s; using procedural textures (%s)\n",
          o.photoDir.empty() ? "the Debian photo packages" : ("'" + o.photoDir + "'").c_str(),
          o.photoDir.empty() ? synthetic::photoInstallHint().c_str() : "add .jpg or .png files");
  }
  const synthetic::SyntheticScene scene = synthetic::generateSyntheticScene(p);
  const std::vector<synthetic::RenderedView> views = synthetic::renderViews(scene);
  synthetic::SceneWriteOptions wo;
  wo.overwrite = o.force;
  const synthetic::WrittenScene written = synthetic::writeSyntheticScene(o.out, scene, views, wo);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::map<std::string, int> roles;
  for (const synthetic::Shape& s : scene.objects)
    ++roles[toString(s.role)];
  std::string contents;
  for (const auto& [role, count] : roles)
    contents += (contents.empty() ? "" : ", ") + std::to_string(count) + " " + role;
  double nearB = written.bounds[0].near, farB = written.bounds[0].far;
  for (const synthetic::DepthBounds& b : written.bounds) {
    nearB = std::min(nearB, b.near);
    farB = std::max(farB, b.far);
  }
  const double slant = std::acos(std::min(1.0, -scene.background.axes.col(2).z())) * 180.0 / M_PI;
  if (p.style == synthetic::SceneStyle::World) {
    const synthetic::WorldLayout& w = scene.world;
    std::printf("wrote %s: %d views of %d x %d, seed %llu, world style: %zu shapes (%s) in "
                "front of %s at %.4g scene units; fov %.1f degrees, camera offsets <= %.3g x "
                "the near depth\n",
                written.dir.c_str(), p.views, p.width, p.height, (unsigned long long)p.seed,
                scene.objects.size(), contents.empty() ? "none" : contents.c_str(),
                w.sky ? "a skyline under a sky at infinity" : "a far plane", w.farDepth,
                w.fovDegrees, w.translation);
  } else {
    std::printf("wrote %s: %d views of %d x %d, seed %llu, %d objects (%s) in front of a "
                "background plane slanted %.1f degrees\n",
                written.dir.c_str(), p.views, p.width, p.height, (unsigned long long)p.seed,
                p.objects, contents.empty() ? "none" : contents.c_str(), slant);
  }
  if (scene.params.usesPhotos()) {
    int photoSurfaces = scene.background.texture.pattern == synthetic::Pattern::Photo;
    for (const synthetic::Shape& s : scene.objects)
      photoSurfaces += s.texture.pattern == synthetic::Pattern::Photo;
    std::printf("  photo textures on %d of %d surfaces (%s)\n", photoSurfaces, scene.shapeCount(),
                p.photos->describe().c_str());
  }
  std::printf("  near / far %.4g .. %.4g scene units; depth/NNN.png = z / %g; %.1f s\n", nearB,
              farB, written.depthScale, seconds);
  if (p.width % 16 != 0 || p.height % 16 != 0)
    std::printf("  note: the network needs sizes divisible by 16; readers will shrink %d x %d "
                "to %d x %d\n",
                p.width, p.height, p.width / 16 * 16, p.height / 16 * 16);
}

} // namespace

void addMakeSceneCommand(CLI::App& app) {
  auto opts = std::make_shared<MakeSceneOptions>();
  CLI::App* cmd = app.add_subcommand(
      "make-scene",
      "Generate a synthetic forward-facing scene with exact ground truth (LLFF layout: "
      "poses_bounds.npy, images/, depth/, scene.json)");
  cmd->add_option("--out", opts->out, "Output scene folder (created atomically)")->required();
  cmd->add_option("--seed", opts->seed, "Random seed (the scene is a function of it)")
      ->capture_default_str();
  cmd->add_option("--views", opts->views, "Number of views")->capture_default_str();
  cmd->add_option("--size", opts->size,
                  "Image size WIDTHxHEIGHT in pixels (multiples of 16 "
                  "for the network)")
      ->capture_default_str();
  cmd->add_option("--objects", opts->objects,
                  "Objects in front of the background (planes, boxes, spheres, poles, wires)")
      ->capture_default_str();
  cmd->add_option("--antialias", opts->antialias, "Anti-aliasing: N x N jittered samples per pixel")
      ->capture_default_str();
  cmd->add_option("--style", opts->style,
                  "Scene layout: objects (objects in front of a background plane) or world "
                  "(FlyingThings-like: far layer or skyline under a sky, occluders, thin "
                  "structures, handheld rig; docs/training_data.md)")
      ->capture_default_str();
  cmd->add_option("--textures", opts->textures,
                  "Surface textures: procedural or photo (photographs, see --photo-dir)")
      ->capture_default_str();
  cmd->add_option("--photo-dir", opts->photoDir,
                  "With --textures photo: a folder of .jpg/.png photographs (default: the "
                  "Debian photo packages, scripts/install-photos.sh)");
  addMinMaxOption(cmd, "--object-size", opts->objectSize,
                  "With --style world: MIN,MAX apparent width of the occluders / image width, "
                  "log-uniform (default 0.08,0.6; dense small clutter: e.g. 0.03,0.2 with "
                  "--objects 40)");
  addMinMaxOption(cmd, "--bushes", opts->bushes,
                  "With --style world: MIN,MAX bushes per scene, uniform (clusters of 20 .. 60 "
                  "small leaves at one depth; default 0,0)");
  addMinMaxOption(cmd, "--bush-scale", opts->bushScale,
                  "With --style world: MIN,MAX factor on each bush's size (its leaves and their "
                  "ball), log-uniform (default 1,1: leaves 3 .. 10 % of the image width; LLFF "
                  "flower's are 10 .. 35 %)");
  cmd->add_option("--bush-shared-texture", opts->bushSharedTexture,
                  "With --style world --textures photo: probability that a bush's leaves share "
                  "one photo (own crops and turns; default 0: a texture each)");
  cmd->add_flag("--force", opts->force, "Replace DIR if it holds a scene written by make-scene");
  cmd->callback([opts] { runMakeScene(*opts); });
}

} // namespace simpli::app

// Writing synthetic scenes (see synthetic/scene_writer.h).
#include "simpli/model/synthetic/scene_writer.h"

#include "simpli/error.h"
#include "simpli/model/io/files.h"
#include "simpli/model/scene/llff_writer.h"
#include "simpli/model/synthetic/photos.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace fs = std::filesystem;
using nlohmann::json;

namespace simpli::synthetic {

namespace {

json vec(const Eigen::Vector3d& v) {
  return json::array({v.x(), v.y(), v.z()});
}

json mat(const Eigen::Matrix3d& m) {
  json rows = json::array();
  for (int r = 0; r < 3; ++r)
    rows.push_back(json::array({m(r, 0), m(r, 1), m(r, 2)}));
  return rows;
}

json textureJson(const Texture& t) {
  if (t.pattern == Pattern::Photo) {
    const PhotoMapping& m = t.mapping;
    return json{{"pattern", toString(t.pattern)},
                {"photo", t.photo ? t.photo->name : std::string()},
                {"photo_size", t.photo ? json::array({t.photo->width, t.photo->height}) : json()},
                {"scale", m.scale},
                {"angle", t.angle},
                {"offset", json::array({m.offset.x(), m.offset.y()})},
                {"mirror", m.mirror},
                {"gain", vec(m.gain)},
                {"saturation", m.saturation},
                {"contrast", m.contrast},
                {"brightness", m.brightness}};
  }
  return json{{"pattern", toString(t.pattern)},
              {"colour_a", vec(t.colourA)},
              {"colour_b", vec(t.colourB)},
              {"frequency", t.frequency},
              {"angle", t.angle},
              {"detail", t.detail},
              {"seed", t.seed}};
}

json shapeJson(const Shape& s) {
  return json{{"role", toString(s.role)}, {"kind", toString(s.kind)},
              {"centre", vec(s.centre)},  {"axes", mat(s.axes)},
              {"size", vec(s.size)},      {"texture", textureJson(s.texture)}};
}

// The shortest decimal text that reads back as x (0.03, not 0.029999999999999999).
std::string shortestText(double x) {
  char text[32];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, x);
    if (std::strtod(text, nullptr) == x)
      break;
  }
  return text;
}

// The make-scene command that reproduces the scene, when the parameters it cannot set are at
// their defaults.
std::string commandFor(const SyntheticSceneParams& p) {
  const SyntheticSceneParams d;
  if (p.fovDegrees != d.fovDegrees || p.nearDepth != d.nearDepth ||
      p.backgroundDepthMin != d.backgroundDepthMin ||
      p.backgroundDepthMax != d.backgroundDepthMax ||
      p.maxBackgroundSlantDegrees != d.maxBackgroundSlantDegrees ||
      p.translation != d.translation || p.rotationDegrees != d.rotationDegrees)
    return "";
  const WorldStyleParams dw;
  const WorldStyleParams& w = p.world;
  if (p.style == SceneStyle::World &&
      (w.fovDegreesMin != dw.fovDegreesMin || w.fovDegreesMax != dw.fovDegreesMax ||
       w.farRatioMin != dw.farRatioMin || w.farRatioMax != dw.farRatioMax ||
       w.skyProbability != dw.skyProbability || w.translationMin != dw.translationMin ||
       w.translationMax != dw.translationMax || w.rotationDegreesMax != dw.rotationDegreesMax ||
       w.thinStructuresMin != dw.thinStructuresMin || w.thinStructuresMax != dw.thinStructuresMax))
    return "";
  if (p.textures == TextureSet::Photo && p.photoProbability != d.photoProbability)
    return "";
  std::string command = "simpli make-scene --out DIR --seed " + std::to_string(p.seed) +
                        " --views " + std::to_string(p.views) + " --size " +
                        std::to_string(p.width) + "x" + std::to_string(p.height) + " --objects " +
                        std::to_string(p.objects) + " --antialias " + std::to_string(p.antialias);
  if (p.style != SceneStyle::Objects)
    command += " --style " + std::string(toString(p.style));
  if (p.style == SceneStyle::World &&
      (w.objectSizeMin != dw.objectSizeMin || w.objectSizeMax != dw.objectSizeMax)) {
    command +=
        " --object-size " + shortestText(w.objectSizeMin) + "," + shortestText(w.objectSizeMax);
  }
  if (p.style == SceneStyle::World && (w.bushesMin != dw.bushesMin || w.bushesMax != dw.bushesMax))
    command += " --bushes " + std::to_string(w.bushesMin) + "," + std::to_string(w.bushesMax);
  if (p.style == SceneStyle::World &&
      (w.bushScaleMin != dw.bushScaleMin || w.bushScaleMax != dw.bushScaleMax))
    command += " --bush-scale " + shortestText(w.bushScaleMin) + "," + shortestText(w.bushScaleMax);
  if (p.style == SceneStyle::World && w.bushSharedTexture != dw.bushSharedTexture)
    command += " --bush-shared-texture " + shortestText(w.bushSharedTexture);
  if (p.textures != TextureSet::Procedural)
    command +=
        " --textures " + std::string(toString(p.textures)) +
        (p.photos && p.photos->source().rfind('\'', 0) == 0 ? " --photo-dir " + p.photos->source()
                                                            : std::string());
  return command;
}

bool isGeneratedScene(const fs::path& dir) {
  std::error_code ec;
  const fs::path file = dir / "scene.json";
  if (!fs::is_regular_file(file, ec))
    return false;
  std::ifstream in(file);
  const json j = json::parse(in, nullptr, false);
  return j.is_object() && j.value("generator", std::string()) == kSceneGenerator;
}

} // namespace

double chooseDepthScale(const std::vector<RenderedView>& views) {
  double largest = 0;
  for (const RenderedView& v : views)
    for (float d : v.depth)
      largest = std::max(largest, double(d));
  double scale = 0.001;
  while (largest / scale > 65535.0)
    scale *= 10.0;
  return scale;
}

std::string sceneDescriptionJson(const SyntheticScene& scene,
                                 const std::vector<DepthBounds>& bounds, double depthScale) {
  const SyntheticSceneParams& p = scene.params;
  json j;
  j["generator"] = kSceneGenerator;
  j["format_version"] = 1;
  j["seed"] = p.seed;
  const std::string command = commandFor(p);
  if (!command.empty())
    j["command"] = command;
  j["params"] = {{"seed", p.seed},
                 {"views", p.views},
                 {"width", p.width},
                 {"height", p.height},
                 {"objects", p.objects},
                 {"fov_degrees", p.fovDegrees},
                 {"near_depth", p.nearDepth},
                 {"background_depth_min", p.backgroundDepthMin},
                 {"background_depth_max", p.backgroundDepthMax},
                 {"max_background_slant_degrees", p.maxBackgroundSlantDegrees},
                 {"translation", p.translation},
                 {"rotation_degrees", p.rotationDegrees},
                 {"antialias", p.antialias}};
  // Only for what the first format had no word for, so that its scenes stay byte-identical.
  if (p.style != SceneStyle::Objects) {
    const WorldStyleParams& w = p.world;
    j["params"]["style"] = toString(p.style);
    j["params"]["world"] = {{"fov_degrees", {w.fovDegreesMin, w.fovDegreesMax}},
                            {"far_ratio", {w.farRatioMin, w.farRatioMax}},
                            {"sky_probability", w.skyProbability},
                            {"translation", {w.translationMin, w.translationMax}},
                            {"rotation_degrees_max", w.rotationDegreesMax},
                            {"thin_structures", {w.thinStructuresMin, w.thinStructuresMax}}};
    // Only when not the default, so that default world scenes stay byte-identical.
    if (w.objectSizeMin != WorldStyleParams{}.objectSizeMin ||
        w.objectSizeMax != WorldStyleParams{}.objectSizeMax)
      j["params"]["world"]["object_size"] = {w.objectSizeMin, w.objectSizeMax};
    if (w.bushesMin != WorldStyleParams{}.bushesMin || w.bushesMax != WorldStyleParams{}.bushesMax)
      j["params"]["world"]["bushes"] = {w.bushesMin, w.bushesMax};
    if (w.bushScaleMin != WorldStyleParams{}.bushScaleMin ||
        w.bushScaleMax != WorldStyleParams{}.bushScaleMax)
      j["params"]["world"]["bush_scale"] = {w.bushScaleMin, w.bushScaleMax};
    if (w.bushSharedTexture != WorldStyleParams{}.bushSharedTexture)
      j["params"]["world"]["bush_shared_texture"] = w.bushSharedTexture;
    const WorldLayout& l = scene.world;
    j["world"] = {{"fov_degrees", l.fovDegrees},
                  {"far_depth", l.farDepth},
                  {"translation", l.translation},
                  {"rotation_degrees", l.rotationDegrees},
                  {"sky", l.sky}};
  }
  if (p.textures != TextureSet::Procedural) {
    j["params"]["textures"] = toString(p.textures);
    j["params"]["photo_probability"] = p.photoProbability;
    json photos = json::array();
    if (p.photos)
      for (size_t i = 0; i < p.photos->size(); ++i)
        photos.push_back(p.photos->photo(i)->name);
    j["params"]["photos"] = photos;
  }
  if (scene.hasSky)
    j["sky"] = {{"texture", textureJson(scene.sky)},
                {"depth", "infinity (depth maps: 0); texture at (azimuth, elevation) of the ray "
                          "direction, radians"}};
  j["frames"] = "world = OpenCV frame of the mean camera (x right, y down, z forward); scene "
                "units; cameras world->camera Xc = R Xw + t, relative intrinsics";
  j["images"] = {{"files", "images/NNN.png"}, {"encoding", "8-bit RGB"}};
  j["depth"] = {{"files", "depth/NNN.png"},
                {"encoding", "16-bit grey PNG; camera-space z (scene units) = value * scale; "
                             "0 = no surface; sampled at the pixel centre"},
                {"scale", depthScale}};
  j["poses"] = {{"file", "poses_bounds.npy"},
                {"encoding", "LLFF: N x 17 float64; 3x5 camera-to-world [down, right, "
                             "backwards, centre, (h, w, focal)] row-major, then near, far"},
                {"bounds", "per view: near = 0.9 x min depth, far = 1.1 x max depth"}};
  json cams = json::array();
  for (size_t i = 0; i < scene.cameras.size(); ++i) {
    const scene::Camera& c = scene.cameras[i];
    json cam = {{"name", scene::llffViewName(i, scene.cameras.size()) + ".png"},
                {"R", mat(c.R)},
                {"t", vec(c.t)},
                {"centre", vec(c.centre())},
                {"fx", c.fx},
                {"fy", c.fy},
                {"cx", c.cx},
                {"cy", c.cy},
                {"width", c.width},
                {"height", c.height}};
    if (i < bounds.size()) {
      cam["near"] = bounds[i].near;
      cam["far"] = bounds[i].far;
    }
    cams.push_back(cam);
  }
  j["cameras"] = cams;
  j["light_direction"] = vec(scene.lightDirection);
  j["background"] = shapeJson(scene.background);
  json objects = json::array();
  for (const Shape& s : scene.objects)
    objects.push_back(shapeJson(s));
  j["objects"] = objects;
  return j.dump(2) + "\n";
}

WrittenScene writeSyntheticScene(const std::string& dir, const SyntheticScene& scene,
                                 const std::vector<RenderedView>& views,
                                 const SceneWriteOptions& options) {
  if (dir.empty())
    fail("output folder: empty path");
  if (views.size() != scene.cameras.size() || views.empty())
    fail("writeSyntheticScene '", dir, "': ", views.size(), " rendered views for ",
         scene.cameras.size(), " cameras");
  std::error_code ec;
  fs::path target = fs::absolute(fs::path(dir), ec).lexically_normal();
  if (ec)
    fail("output folder '", dir, "': ", ec.message());
  if (!target.has_filename())
    target = target.parent_path();
  const fs::path parent = target.parent_path();
  if (!fs::is_directory(parent, ec))
    fail("output folder '", dir, "': parent folder '", parent.string(), "' does not exist");
  const bool exists = fs::exists(fs::symlink_status(target, ec));
  if (exists) {
    if (!options.overwrite)
      fail("output folder '", dir, "' already exists (--force replaces a scene written by ",
           kSceneGenerator, ")");
    if (!fs::is_directory(target, ec) || !isGeneratedScene(target))
      fail("output folder '", dir, "' exists and is not a scene written by ", kSceneGenerator,
           "; refusing to replace it");
  }

  WrittenScene written;
  written.dir = target.string();
  written.depthScale = options.depthScale > 0 ? options.depthScale : chooseDepthScale(views);
  scene::LlffSceneData data;
  data.cameras = scene.cameras;
  data.depthScale = written.depthScale;
  for (const RenderedView& v : views) {
    written.bounds.push_back(depthBounds(v));
    data.images.push_back(v.image());
    data.depths.push_back(v.depth);
    data.near.push_back(written.bounds.back().near);
    data.far.push_back(written.bounds.back().far);
  }

  // Hidden temporary folder beside the target (same file system, so the rename is atomic).
  const std::string pid = std::to_string(::getpid());
  const fs::path tmp = parent / ("." + target.filename().string() + ".tmp-" + pid);
  fs::remove_all(tmp, ec);
  if (!fs::create_directory(tmp, ec) || ec)
    fail("cannot create output folder '", dir, "': cannot create '", tmp.string(),
         "': ", ec ? ec.message() : std::string("it already exists"));
  try {
    scene::writeLlffScene(tmp.string(), data);
    const std::string text = sceneDescriptionJson(scene, written.bounds, written.depthScale);
    io::writeFileAtomically((tmp / "scene.json").string(), text.data(), text.size());
    if (exists) {
      // Move the old scene aside, move the new one in, then delete the old one; if the second
      // rename fails the old scene goes back.
      const fs::path old = parent / ("." + target.filename().string() + ".old-" + pid);
      fs::remove_all(old, ec);
      fs::rename(target, old, ec);
      if (ec)
        fail("cannot replace '", dir, "': ", ec.message());
      fs::rename(tmp, target, ec);
      if (ec) {
        std::error_code ignored;
        fs::rename(old, target, ignored);
        fail("cannot replace '", dir, "': ", ec.message());
      }
      fs::remove_all(old, ec);
    } else {
      fs::rename(tmp, target, ec);
      if (ec)
        fail("cannot move '", tmp.string(), "' to '", dir, "': ", ec.message());
    }
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(tmp, ignored);
    throw;
  }
  return written;
}

} // namespace simpli::synthetic

// `simpli info SCENE`: reads a scene (LLFF, COLMAP text, RealEstate10K) and prints what the
// network will see: format, views, image size, intrinsics, bounds, normalisation, baseline and
// the reference camera. Images are decoded (to validate them) but not kept.
#include "commands.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include "simpli/error.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/scene/scene.h"

#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

namespace simpli::app {

namespace {

struct InfoOptions {
  std::string scene;
  std::string format = "auto";
  std::string imagesDir;
  std::string normalise = "auto";
  double near = 0, far = 0;
  double minDepth = 1.0;
  int sizeMultiple = 16;
  bool json = false;
};

scene::NormalisationMode parseNormalisation(const std::string& s) {
  if (s == "auto")
    return scene::NormalisationMode::Auto;
  if (s == "none")
    return scene::NormalisationMode::None;
  if (s == "near")
    return scene::NormalisationMode::NearBound;
  if (s == "points")
    return scene::NormalisationMode::PointPercentile;
  fail("--normalise: unknown value '", s, "' (expected auto, none, near or points)");
}

std::string vec(const Eigen::Vector3d& v) {
  std::ostringstream os;
  os.precision(6);
  os << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return os.str();
}

std::string intrinsics(const scene::Camera& c) {
  std::ostringstream os;
  os.precision(6);
  os << "relative fx " << c.fx << " fy " << c.fy << " cx " << c.cx << " cy " << c.cy
     << "; pixels fx " << c.fx * c.width << " fy " << c.fy * c.height << " cx " << c.cx * c.width
     << " cy " << c.cy * c.height;
  return os.str();
}

bool sameIntrinsics(const std::vector<scene::Camera>& cams) {
  for (const scene::Camera& c : cams)
    if (c.fx != cams[0].fx || c.fy != cams[0].fy || c.cx != cams[0].cx || c.cy != cams[0].cy)
      return false;
  return true;
}

nlohmann::json cameraJson(const scene::Camera& c) {
  nlohmann::json j;
  j["R"] = {{c.R(0, 0), c.R(0, 1), c.R(0, 2)},
            {c.R(1, 0), c.R(1, 1), c.R(1, 2)},
            {c.R(2, 0), c.R(2, 1), c.R(2, 2)}};
  j["t"] = {c.t.x(), c.t.y(), c.t.z()};
  const Eigen::Vector3d C = c.centre();
  j["centre"] = {C.x(), C.y(), C.z()};
  j["fx"] = c.fx;
  j["fy"] = c.fy;
  j["cx"] = c.cx;
  j["cy"] = c.cy;
  j["width"] = c.width;
  j["height"] = c.height;
  return j;
}

void printJson(const scene::Scene& s, const scene::Camera& ref, double baseline) {
  nlohmann::json j;
  j["root"] = s.root;
  j["format"] = toString(s.format);
  j["poses_file"] = s.posesFile;
  j["width"] = s.width();
  j["height"] = s.height();
  j["near"] = s.near;
  j["far"] = s.far;
  j["near_scene"] = s.sceneNear();
  j["far_scene"] = s.sceneFar();
  j["bounds_source"] = s.boundsSource;
  j["normalisation"] = {{"rule", toString(s.normalisation.rule)},
                        {"scale", s.normalisation.scale},
                        {"anchor_scene", s.normalisation.anchorScene},
                        {"anchor_target", s.normalisation.anchorTarget}};
  j["baseline"] = baseline;
  j["baseline_scene"] = s.normalisation.toScene(baseline);
  j["points"] = s.points.size();
  j["views"] = nlohmann::json::array();
  for (const scene::SceneView& v : s.views) {
    nlohmann::json jv = cameraJson(v.camera);
    jv["name"] = v.name;
    jv["image"] = v.imagePath;
    jv["original_width"] = v.originalWidth;
    jv["original_height"] = v.originalHeight;
    j["views"].push_back(jv);
  }
  j["reference"] = cameraJson(ref);
  std::cout << j.dump(2) << "\n";
}

void printText(const scene::Scene& s, const scene::Camera& ref, double baseline, int sizeMultiple) {
  const std::vector<scene::Camera> cams = s.cameras();
  const scene::Normalisation& n = s.normalisation;
  std::cout.precision(6);
  std::cout << "scene          " << s.root << "\n"
            << "format         " << toString(s.format) << " (cameras from " << s.posesFile << ")\n"
            << "views          " << s.size() << "\n"
            << "image size     " << s.width() << " x " << s.height() << " (W x H)";
  const scene::SceneView& v0 = s.views[0];
  if (v0.originalWidth != s.width() || v0.originalHeight != s.height())
    std::cout << ", stored " << v0.originalWidth << " x " << v0.originalHeight
              << ", resized down to a multiple of " << sizeMultiple;
  std::cout << "\n";
  if (sameIntrinsics(cams))
    std::cout << "intrinsics     " << intrinsics(cams[0]) << " (all views)\n";
  else
    std::cout << "intrinsics     differ between views (listed below); view 0: "
              << intrinsics(cams[0]) << "\n";
  std::cout << "near / far     " << s.sceneNear() << " .. " << s.sceneFar() << " scene units, "
            << s.near << " .. " << s.far << " normalised (" << s.boundsSource << ")\n"
            << "normalisation  " << n.describe() << "\n"
            << "baseline       " << n.toScene(baseline) << " scene units, " << baseline
            << " normalised (largest distance between camera centres)\n";
  if (!s.points.empty())
    std::cout << "SfM points     " << s.points.size() << "\n";
  std::cout << "reference camera (normalised units; rotation = quaternion average, centre = "
               "mean, intrinsics of view 0):\n";
  for (int r = 0; r < 3; ++r)
    std::cout << "  [R|t] row " << r << "  " << ref.R(r, 0) << " " << ref.R(r, 1) << " "
              << ref.R(r, 2) << " | " << ref.t[r] << "\n";
  std::cout << "  centre       " << vec(ref.centre()) << "\n"
            << "  intrinsics   " << intrinsics(ref) << "\n"
            << "views (centres in normalised units):\n";
  const bool same = sameIntrinsics(cams);
  for (size_t i = 0; i < s.size(); ++i) {
    std::cout << "  " << i << "  " << s.views[i].name << "  centre " << vec(cams[i].centre());
    if (!same)
      std::cout << "  " << intrinsics(cams[i]);
    std::cout << "\n";
  }
}

void runInfo(const InfoOptions& o) {
  if (o.sizeMultiple < 1)
    fail("--size-multiple ", o.sizeMultiple, ": must be >= 1 (1: no resize)");
  scene::SceneReadOptions ro;
  ro.format = scene::parseSceneFormat(o.format);
  ro.loadImages = false;
  ro.sizeMultiple = o.sizeMultiple;
  ro.imagesDir = o.imagesDir;
  ro.near = o.near;
  ro.far = o.far;
  ro.normalisation.mode = parseNormalisation(o.normalise);
  ro.normalisation.minDepth = o.minDepth;
  const scene::Scene scene = scene::readScene(o.scene, ro);
  const std::vector<scene::Camera> cams = scene.cameras();
  const scene::Camera ref = scene::referenceCamera(cams);
  const double baseline = scene::maxBaseline(cams);
  if (o.json)
    printJson(scene, ref, baseline);
  else
    printText(scene, ref, baseline, o.sizeMultiple);
}

} // namespace

void addInfoCommand(CLI::App& app) {
  auto opts = std::make_shared<InfoOptions>();
  CLI::App* cmd = app.add_subcommand(
      "info", "Read a scene (LLFF poses_bounds.npy, COLMAP text model or RealEstate10K camera "
              "file) and print its cameras, bounds, normalisation and reference camera");
  cmd->add_option("scene", opts->scene,
                  "Scene folder (or a poses_bounds.npy / RealEstate10K .txt file)")
      ->required();
  cmd->add_option("--format", opts->format, "Scene format: auto, llff, colmap, re10k")
      ->capture_default_str();
  cmd->add_option("--images", opts->imagesDir,
                  "Image folder relative to the scene (default: images, e.g. images_4 for LLFF)");
  cmd->add_option("--near", opts->near, "Near bound in scene units (overrides the scene's)");
  cmd->add_option("--far", opts->far, "Far bound in scene units (overrides the scene's)");
  cmd->add_option("--normalise", opts->normalise,
                  "Scene scaling: auto (points p10 -> 1.25 if SfM points, else near -> "
                  "--min-depth), none, near, points")
      ->capture_default_str();
  cmd->add_option("--min-depth", opts->minDepth,
                  "Normalised depth the near bound maps to (the network's nearest plane)")
      ->capture_default_str();
  cmd->add_option("--size-multiple", opts->sizeMultiple,
                  "Images are resized down to a multiple of this (the network needs 16)")
      ->capture_default_str();
  cmd->add_flag("--json", opts->json, "Print machine-readable JSON");
  cmd->callback([opts] { runInfo(*opts); });
}

} // namespace simpli::app

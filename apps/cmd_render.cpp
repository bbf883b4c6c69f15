// `simpli render MLI --out DIR`: renders an MLI folder (either form, model/mli_io.h) with the
// OpenCL rasterizer (model/rasterizer.h) into
//   - its own reference camera and size (no camera option),
//   - a view of a scene (--scene SCENE --view K; the scene is read by readScene, normalised as
//     the network sees it, which is the frame an MLI built from it lives in), or
//   - a spiral / orbit trajectory around the reference camera (--trajectory KIND --frames N;
//     with --scene, the radii and focus depth come from the scene's cameras and bounds as in
//     LLFF, otherwise from the MLI's depth range; see model/trajectory.h),
// at --size WxH if given (relative intrinsics are size-free).
//
// Per frame i, DIR gets rgb_NNN.png (8-bit RGB, background black) and depth_NNN.png (16-bit
// grey: round(z * depth-scale) of the composited target-camera z, 0 where nothing is hit,
// clamped to 65535; default scale 1000, i.e. millimetres when the MLI is in metres, the
// convention of datasets_small), plus render.json with the depth scale and each frame's camera
// (reference-format extrinsic_re / intrinsics_re / frame_size). Every file appears atomically
// (temporary + rename).
#include "commands.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include "simpli/error.h"
#include "simpli/model/mli/files.h"
#include "simpli/model/raster/render_mli.h"
#include "simpli/model/scene/scene.h"
#include "simpli/model/scene/trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <regex>
#include <string>
#include <vector>

namespace simpli::app {

namespace {

namespace fs = std::filesystem;

struct RenderOptions {
  std::string mli, scene, trajectory, size, out;
  int view = -1;
  int frames = 60;
  bool perspectiveCorrect = false;
  double depthScale = 1000.0;
  int maxFragments = 16;
};

void parseRenderSize(const std::string& text, int& width, int& height) {
  std::smatch m;
  static const std::regex pattern("^\\s*(-?[0-9]+)\\s*[xX]\\s*(-?[0-9]+)\\s*$");
  if (!std::regex_match(text, m, pattern))
    fail("--size '", text, "': expected WIDTHxHEIGHT in pixels, e.g. 192x128");
  long long w = 0, h = 0;
  try {
    w = std::stoll(m[1].str());
    h = std::stoll(m[2].str());
  } catch (const std::exception&) {
    fail("--size '", text, "': number out of range");
  }
  if (w <= 0 || h <= 0 || w > 16384 || h > 16384)
    fail("--size '", text, "': width and height must be in 1..16384");
  width = int(w);
  height = int(h);
}

// Writes `bytes` through a temporary sibling renamed into place.
void writeAtomically(const fs::path& path, const std::vector<uchar>& bytes) {
  const fs::path tmp = path.parent_path() / ("." + path.filename().string() + ".tmp");
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!f)
      fail("cannot write ", tmp.string());
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    fail("cannot rename ", tmp.string(), " to ", path.string());
  }
}

void writePng(const fs::path& path, const cv::Mat& image) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", image, bytes))
    fail("cannot encode ", path.string(), " as PNG");
  writeAtomically(path, bytes);
}

std::string frameName(const char* prefix, int i) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%03d.png", prefix, i);
  return buf;
}

// Removes rgb_NNN.png / depth_NNN.png frames with NNN >= frames, left by an earlier, longer
// render into the same folder (so the folder matches render.json). Other files are kept.
int removeStaleFrames(const fs::path& out, size_t frames) {
  static const std::regex pattern(R"((rgb|depth)_(\d{1,9})\.png)");
  int removed = 0;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(out, ec)) {
    std::smatch m;
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, m, pattern) && std::stoull(m[2].str()) >= frames &&
        fs::remove(entry.path(), ec))
      ++removed;
  }
  return removed;
}

nlohmann::json cameraJson(const scene::Camera& c) {
  nlohmann::json j;
  std::vector<double> e, k;
  for (int r = 0; r < 3; ++r) {
    for (int col = 0; col < 3; ++col)
      e.push_back(c.R(r, col));
    e.push_back(c.t(r));
  }
  const Eigen::Matrix3d K = c.relativeK();
  for (int r = 0; r < 3; ++r)
    for (int col = 0; col < 3; ++col)
      k.push_back(K(r, col));
  j["extrinsic_re"] = e;
  j["intrinsics_re"] = k;
  j["frame_size"] = {c.height, c.width};
  return j;
}

void runRender(const RenderOptions& o) {
  // Options first, so that nothing is read or written for a bad command line.
  if (o.view >= 0 && o.scene.empty())
    fail("--view ", o.view, " needs --scene");
  if (o.view >= 0 && !o.trajectory.empty())
    fail("--view and --trajectory exclude each other");
  if (!o.scene.empty() && o.view < 0 && o.trajectory.empty())
    fail("--scene ", o.scene, " needs --view K or --trajectory KIND");
  if (o.frames < 1)
    fail("--frames ", o.frames, ": need at least 1");
  if (!(o.depthScale > 0 && std::isfinite(o.depthScale)))
    fail("--depth-scale ", o.depthScale, ": must be finite and > 0");
  if (o.maxFragments < 1 || o.maxFragments > 64)
    fail("--max-fragments ", o.maxFragments, ": must be in 1..64");
  int width = 0, height = 0;
  if (!o.size.empty())
    parseRenderSize(o.size, width, height);
  scene::TrajectoryOptions traj;
  if (!o.trajectory.empty()) {
    try {
      traj.kind = scene::parseTrajectoryKind(o.trajectory);
    } catch (const Error& e) {
      fail("--trajectory: ", e.what());
    }
    traj.frames = o.frames;
  }
  const fs::path out = o.out;
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec))
    fail("--out ", o.out, " exists and is not a folder");
  if (!out.parent_path().empty() && !fs::is_directory(out.parent_path(), ec) &&
      !fs::exists(out, ec))
    fail("--out ", o.out, ": parent folder ", out.parent_path().string(), " does not exist");

  const mli::MLI mli = mli::readMLI(o.mli);
  std::vector<scene::Camera> cameras;
  if (!o.scene.empty()) {
    scene::SceneReadOptions so;
    so.loadImages = false;
    const scene::Scene scene = scene::readScene(o.scene, so);
    if (o.view >= 0) {
      if (o.view >= int(scene.size()))
        fail("--view ", o.view, ": the scene ", o.scene, " has ", scene.size(), " views");
      cameras.push_back(scene.views[size_t(o.view)].camera);
    } else {
      traj = scene::resolveTrajectory(traj, mli.camera, scene.cameras(), scene.near, scene.far);
      cameras = scene::makeTrajectory(mli.camera, traj);
    }
  } else if (!o.trajectory.empty()) {
    double near = std::numeric_limits<double>::infinity(), far = 0;
    for (const mli::MLILayer& layer : mli.layers)
      for (float d : layer.depth) {
        near = std::min(near, double(d));
        far = std::max(far, double(d));
      }
    traj = scene::resolveTrajectory(traj, mli.camera, {}, near, far);
    cameras = scene::makeTrajectory(mli.camera, traj);
  } else {
    cameras.push_back(mli.camera);
  }
  for (scene::Camera& c : cameras)
    if (width > 0) {
      c.width = width;
      c.height = height;
    }

  fs::create_directories(out, ec);
  if (!fs::is_directory(out, ec))
    fail("--out ", o.out, ": cannot create the folder");

  raster::RasterSettings settings;
  settings.maxFragments = o.maxFragments;
  settings.interpolation = o.perspectiveCorrect ? raster::RasterInterpolation::PerspectiveCorrect
                                                : raster::RasterInterpolation::ScreenLinear;
  nlohmann::json meta;
  meta["mli"] = o.mli;
  meta["interpolation"] = o.perspectiveCorrect ? "perspective-correct" : "screen-linear";
  meta["depth_scale"] = 1.0 / o.depthScale;
  meta["depth_note"] = "depth_NNN.png: 16-bit, target-camera z = value * depth_scale (MLI "
                       "units), 0 = no surface";
  meta["frames"] = nlohmann::json::array();
  long long clamped = 0;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const scene::Camera& cam = cameras[i];
    const raster::RenderedLayers r = raster::renderMLI(mli, cam, settings);
    const std::vector<float> colour = r.colour.toVectorF32();
    const std::vector<float> depth = r.depth.toVectorF32();
    const int W = cam.width, H = cam.height;
    const size_t n = size_t(W) * H;
    cv::Mat rgb(H, W, CV_8UC3), z(H, W, CV_16UC1);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const size_t p = size_t(y) * W + x;
        cv::Vec3b& px = rgb.at<cv::Vec3b>(y, x);
        for (int c = 0; c < 3; ++c) // OpenCV stores BGR
          px[2 - c] = cv::saturate_cast<uchar>(std::round(255.0 * colour[c * n + p]));
        const double q = std::round(double(depth[p]) * o.depthScale);
        if (q > 65535)
          ++clamped;
        z.at<uint16_t>(y, x) = uint16_t(q < 0 ? 0 : (q > 65535 ? 65535 : q));
      }
    const std::string rgbName = frameName("rgb", int(i)), depthName = frameName("depth", int(i));
    writePng(out / rgbName, rgb);
    writePng(out / depthName, z);
    nlohmann::json f = cameraJson(cam);
    f["rgb"] = rgbName;
    f["depth"] = depthName;
    meta["frames"].push_back(f);
  }
  const std::string text = meta.dump(2) + "\n";
  writeAtomically(out / "render.json", std::vector<uchar>(text.begin(), text.end()));
  if (const int stale = removeStaleFrames(out, cameras.size()))
    std::printf("removed %d frame file(s) of an earlier render from %s\n", stale, o.out.c_str());
  std::printf("rendered %zu frame(s) of %s (%d layers) at %d x %d -> %s\n", cameras.size(),
              o.mli.c_str(), mli.numLayers(), cameras[0].width, cameras[0].height, o.out.c_str());
  if (clamped > 0)
    std::printf("note: %lld depth pixel(s) exceeded 65535 / depth-scale and were clamped; use a "
                "smaller --depth-scale\n",
                clamped);
}

} // namespace

void addRenderCommand(CLI::App& app) {
  auto opts = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render an MLI with the OpenCL rasterizer: at its reference camera, at a scene "
                "view, or along a spiral/orbit trajectory (PNG colour + 16-bit depth per frame)");
  cmd->add_option("mli", opts->mli, "MLI folder (reference JPEG form or lossless form)")
      ->required();
  cmd->add_option("--scene", opts->scene,
                  "Scene folder (LLFF, COLMAP, RealEstate10K) for --view or trajectory defaults");
  cmd->add_option("--view", opts->view, "Render the camera of this scene view (0-based)");
  cmd->add_option("--trajectory", opts->trajectory, "Camera path: spiral or orbit");
  cmd->add_option("--frames", opts->frames, "Frames of the trajectory")->capture_default_str();
  cmd->add_option("--size", opts->size, "Output size WIDTHxHEIGHT (default: the camera's)");
  cmd->add_flag("--perspective-correct", opts->perspectiveCorrect,
                "Perspective-correct interpolation (as OpenGL); default screen-linear, as the "
                "reference implementation");
  cmd->add_option("--depth-scale", opts->depthScale,
                  "16-bit depth value per MLI unit (1000: millimetres for metres)")
      ->capture_default_str();
  cmd->add_option("--max-fragments", opts->maxFragments, "Fragments kept per pixel (1..64)")
      ->capture_default_str();
  cmd->add_option("--out", opts->out, "Output folder (created)")->required();
  cmd->callback([opts] { runRender(*opts); });
}

} // namespace simpli::app

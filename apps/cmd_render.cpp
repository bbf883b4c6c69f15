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
// convention of datasets_small), plus render.json with the depth scale, each frame's camera
// (reference-format extrinsic_re / intrinsics_re / frame_size) and "written_by": "simpli render".
//
// DIR is written as a whole (io/staged_folder.h): the frames and render.json go into a hidden
// staging sibling that replaces DIR in one step, so a failure (a full disk) or a kill leaves the
// old complete DIR or the new one, never a mix. An existing DIR is replaced only when it holds
// nothing but an earlier `simpli render` output (renderReplaceRefusal); anything else is refused
// before any work. SIGINT / SIGTERM stop after the current frame, write nothing and exit with
// 130 / 143 (stop_signals.h).
#include "commands.h"
#include "stop_signals.h"

#include "simpli/error.h"
#include "simpli/model/io/image_size.h"
#include "simpli/model/io/staged_folder.h"
#include "simpli/model/mli/files.h"
#include "simpli/model/raster/render_mli.h"
#include "simpli/model/scene/scene.h"
#include "simpli/model/scene/trajectory.h"
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
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
  bool framesGiven = false; ///< --frames was on the command line
};

/// Most frames one render writes (two files each, all staged before the switch).
constexpr int kMaxRenderFrames = 10000;
/// Most pixels x kept fragments per frame: the rasterizer keeps maxFragments fragments per pixel
/// on the device (about 6 bytes x 16 per pixel), so this bounds device memory to about 2 GiB;
/// 4096 x 4096 at the default 16 fragments.
constexpr long long kMaxRenderFragments = 4096LL * 4096LL * 16;

/// render.json's mark of a folder written by `simpli render`.
constexpr const char* kWrittenByKey = "written_by";
constexpr const char* kWrittenByValue = "simpli render";

// Writes `bytes` to `path` (inside the staging folder: atomicity comes from the folder).
void writeFile(const fs::path& path, const std::vector<uchar>& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  f.close();
  if (!f)
    fail("--out: cannot write ", path.string(), " (", std::strerror(errno), ")");
}

void writePng(const fs::path& path, const cv::Mat& image) {
  std::vector<uchar> bytes;
  if (!cv::imencode(".png", image, bytes))
    fail("cannot encode ", path.string(), " as PNG");
  writeFile(path, bytes);
}

std::string frameName(const char* prefix, int i) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%03d.png", prefix, i);
  return buf;
}

bool isFrameName(const std::string& name) {
  static const std::regex pattern(R"((rgb|depth)_\d{3,10}\.png)");
  return std::regex_match(name, pattern);
}

/// Why the existing, non-empty folder `path` must not be replaced by a new render; "" when it may:
/// its render.json has the mark of `simpli render`, and it holds nothing but render.json and
/// rgb_NNN.png / depth_NNN.png frames (the rule of mli::mliReplaceRefusal for renders).
std::string renderReplaceRefusal(const std::string& path) {
  const fs::path folder(path), meta = folder / "render.json";
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(meta, ec)))
    return "it is not a simpli render (no render.json)";
  nlohmann::json root;
  try {
    std::ifstream in(meta, std::ios::binary);
    root = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    return std::string("its render.json is not valid JSON (") + e.what() + ")";
  }
  const auto mark = root.is_object() ? root.find(kWrittenByKey) : root.end();
  if (!root.is_object() || mark == root.end() || !mark->is_string() ||
      mark->get<std::string>() != kWrittenByValue)
    return std::string("its render.json has no \"") + kWrittenByKey + "\": \"" + kWrittenByValue +
           "\" (not a render written by simpli)";
  fs::directory_iterator it(folder, ec), end;
  if (ec)
    return "its contents cannot be listed (" + ec.message() + ")";
  for (; it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (fs::is_regular_file(it->symlink_status(ec)) && (name == "render.json" || isFrameName(name)))
      continue;
    return "it holds \"" + name + "\", which is not a file of the render simpli wrote there";
  }
  if (ec)
    return "its contents cannot be listed (" + ec.message() + ")";
  return "";
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

int cancelled(const std::string& out) {
  const int sig = stopSignal();
  std::fprintf(stderr, "simpli render: %s received; cancelled, nothing written to %s\n",
               sig == SIGTERM ? "SIGTERM" : "SIGINT", out.c_str());
  return 128 + sig;
}

int runRender(const RenderOptions& o) {
  // Before anything else (stop_signals.h), and until the output is committed: a signal stops
  // the render after the current frame, and nothing is written.
  StopSignals signals;
  // Options first, so that nothing is read or written for a bad command line.
  if (o.view >= 0 && o.scene.empty())
    fail("--view ", o.view, " needs --scene");
  if (o.view >= 0 && !o.trajectory.empty())
    fail("--view and --trajectory exclude each other");
  if (!o.scene.empty() && o.view < 0 && o.trajectory.empty())
    fail("--scene ", o.scene, " needs --view K or --trajectory KIND");
  if (o.framesGiven && o.trajectory.empty())
    fail("--frames ", o.frames, " needs --trajectory KIND (without it, render draws one frame)");
  if (o.frames < 1)
    fail("--frames ", o.frames, ": need at least 1");
  if (o.frames > kMaxRenderFrames)
    fail("--frames ", o.frames, ": more than the limit of ", kMaxRenderFrames,
         " frames per render (render longer paths in parts)");
  if (!(o.depthScale > 0 && std::isfinite(o.depthScale)))
    fail("--depth-scale ", o.depthScale, ": must be finite and > 0");
  if (o.maxFragments < 1 || o.maxFragments > 64)
    fail("--max-fragments ", o.maxFragments, ": must be in 1..64");
  io::ImageSize size; // 0 x 0: each camera's own size
  if (!o.size.empty())
    size = io::parseImageSize(o.size, "--size");
  const int width = size.width, height = size.height;
  scene::TrajectoryOptions traj;
  if (!o.trajectory.empty()) {
    try {
      traj.kind = scene::parseTrajectoryKind(o.trajectory);
    } catch (const Error& e) {
      fail("--trajectory: ", e.what());
    }
    traj.frames = o.frames;
  }
  // The output before any work: a path that cannot be written, or a folder that is not an
  // earlier render, fails now.
  const io::ReplaceCheck replaceable = [](const fs::path& folder) {
    return renderReplaceRefusal(folder.string());
  };
  io::checkReplaceable(o.out, replaceable, "--out");
  io::checkOutputLocation(o.out, "--out");

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
  // The size is known now (--size or the camera's): bound the rasterizer's memory before it runs.
  const long long fragments =
      static_cast<long long>(cameras[0].width) * cameras[0].height * o.maxFragments;
  if (fragments > kMaxRenderFragments)
    fail("--size ", cameras[0].width, "x", cameras[0].height, " with --max-fragments ",
         o.maxFragments, ": ", fragments, " fragments per frame, more than the limit of ",
         kMaxRenderFragments, " (4096 x 4096 x 16, about 2 GiB of device memory)");

  std::error_code ec;
  const bool replacing = fs::is_directory(o.out, ec) && !fs::is_empty(o.out, ec);
  io::StagedFolder staged(o.out, replaceable, {"--out"});
  const fs::path& out = staged.path();

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
  meta[kWrittenByKey] = kWrittenByValue;
  long long clamped = 0;
  for (size_t i = 0; i < cameras.size(); ++i) {
    if (stopSignal() != 0)
      return cancelled(o.out); // the staging folder goes with `staged`
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
  writeFile(out / "render.json", std::vector<uchar>(text.begin(), text.end()));
  if (stopSignal() != 0)
    return cancelled(o.out);
  staged.commit();
  if (replacing)
    std::printf("replaced the earlier render in %s\n", o.out.c_str());
  std::printf("rendered %zu frame(s) of %s (%d layers) at %d x %d -> %s\n", cameras.size(),
              o.mli.c_str(), mli.numLayers(), cameras[0].width, cameras[0].height, o.out.c_str());
  if (clamped > 0)
    std::printf("note: %lld depth pixel(s) exceeded 65535 / depth-scale and were clamped; use a "
                "smaller --depth-scale\n",
                clamped);
  return 0;
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
  CLI::Option* frames =
      cmd->add_option("--frames", opts->frames, "Frames of the trajectory (1..10000)")
          ->capture_default_str();
  cmd->add_option("--size", opts->size, "Output size WIDTHxHEIGHT (default: the camera's)");
  cmd->add_flag("--perspective-correct", opts->perspectiveCorrect,
                "Perspective-correct interpolation (as OpenGL); default screen-linear, as the "
                "reference implementation");
  cmd->add_option("--depth-scale", opts->depthScale,
                  "16-bit depth value per MLI unit (1000: millimetres for metres)")
      ->capture_default_str();
  cmd->add_option("--max-fragments", opts->maxFragments, "Fragments kept per pixel (1..64)")
      ->capture_default_str();
  cmd->add_option("--out", opts->out,
                  "Output folder, written as a whole; an existing one is replaced only if it "
                  "holds nothing but an earlier simpli render output")
      ->required();
  cmd->callback([opts, frames] {
    opts->framesGiven = frames->count() > 0;
    if (const int code = runRender(*opts); code != 0) {
      std::fflush(nullptr);
      std::exit(code);
    }
  });
}

} // namespace simpli::app

// `simpli bench render`: times VTK/OpenGL rendering (an offscreen window, e.g. under xvfb-run)
// of the per-texel and the adaptive form of the same MLI along a small orbit, and prints per
// form the mesh build time, triangles, points, the bytes a GPU holds, frames per second, and
// the PSNR of its images against the per-texel form's at the same cameras (central 90 % crop,
// the paper's). --raster times the OpenCL rasterizer on both forms too. Measures, never
// asserts.
//
// The MLI is an MLI folder, or (--synthetic) a 4-layer 1008 x 752 MLI made here for a standard
// measurement (see syntheticMLI). Both forms are drawn as simpli_vtk_render draws them: one
// unlit actor per layer, back to front, straight alpha, a texture per adaptive layer.
// Cameras: the orbit `simpli render --trajectory orbit` uses for an MLI without a scene (radius
// 0.05 x the focus depth, in the reference image plane), with the reference camera's vertical
// field of view and principal point at the window size (square pixels: fx' = fy' H / W).
// Timing: after --warmup frames (shader compilation, uploads), --frames frames, each rendered
// and finished (WaitForCompletion), capped at --max-seconds per form; fps = frames / time.
#include "SIMPLILayerActors.h"
#include "SIMPLIMLIToVTK.h"
#include "synthetic_mli.h"

#include <vtkCamera.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <CLI/CLI.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "simpli/error.h"
#include "simpli/model/io/image_size.h"
#include "simpli/model/metrics/image_quality.h"
#include "simpli/model/mli/files.h"
#include "simpli/model/raster/render_adaptive.h"
#include "simpli/model/raster/render_mli.h"
#include "simpli/model/scene/trajectory.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace simpli::app {

namespace {

using Clock = std::chrono::steady_clock;

struct BenchRenderOptions {
  std::string mli;
  bool synthetic = false;
  bool quick = false;
  std::string size = "1024x768";
  int frames = 60;
  int warmup = 5;
  double maxSeconds = 20.0;
  std::vector<double> tolerances{1.0};
  std::string saveMli;    ///< write the MLI rendered (e.g. the synthetic one) here, lossless form
  bool raster = false;    ///< also time the OpenCL rasterizer on both forms
  std::string saveImages; ///< write every form's images at the sample cameras here (PNG)
  std::string device;     ///< OpenCL device for --raster
};

// ---- the two forms -----------------------------------------------------------------------

struct Form {
  std::string name;
  vtkSmartPointer<vtkPartitionedDataSetCollection> layers;
  double buildMs = 0;
  long long triangles = 0, points = 0;
  double bytes = 0; ///< positions, colours or texture coordinates, indices, textures
};

Form buildForm(const mli::MLI& mli, vtkmli::MeshMode mode, double tolerance) {
  Form form;
  char name[64];
  if (mode == vtkmli::MeshMode::Adaptive)
    std::snprintf(name, sizeof name, "adaptive %.3g px", tolerance);
  else
    std::snprintf(name, sizeof name, "per-texel");
  form.name = name;
  vtkmli::LayerOptions options;
  options.meshMode = mode;
  options.meshTolerance = tolerance;
  form.layers = vtkSmartPointer<vtkPartitionedDataSetCollection>::New();
  const auto t0 = Clock::now();
  vtkmli::mliToCollection(mli, options, form.layers);
  form.buildMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  for (unsigned int k = 0; k < form.layers->GetNumberOfPartitionedDataSets(); ++k) {
    auto* pd = vtkPolyData::SafeDownCast(form.layers->GetPartitionedDataSet(k)->GetPartition(0));
    const long long n = pd->GetNumberOfPoints(), t = pd->GetNumberOfPolys();
    form.points += n;
    form.triangles += t;
    form.bytes += 12.0 * n + 12.0 * t;
    if (vtkDataArray* texture = pd->GetFieldData()->GetArray(vtkmli::kTextureRGBAArray))
      form.bytes += 8.0 * n + 4.0 * static_cast<double>(texture->GetNumberOfTuples());
    else
      form.bytes += 4.0 * n;
  }
  return form;
}

// The fill unit, the reference of the timings: one opaque textured plane where the MLI's image
// is (the back layer's colours at the focus depth, alpha 1), two triangles covering the window.
Form fillUnitForm(const mli::MLI& mli) {
  mli::MLI plane = mli;
  plane.layers.resize(1);
  double near = std::numeric_limits<double>::infinity(), far = 0;
  for (const mli::MLILayer& layer : mli.layers)
    for (float d : layer.depth) {
      near = std::min(near, static_cast<double>(d));
      far = std::max(far, static_cast<double>(d));
    }
  const float depth = static_cast<float>(scene::trajectoryFocusDepth(near, far));
  std::fill(plane.layers[0].depth.begin(), plane.layers[0].depth.end(), depth);
  for (std::size_t p = 0; p < plane.texels(); ++p)
    plane.layers[0].rgba[4 * p + 3] = 1.0f;
  Form form = buildForm(plane, vtkmli::MeshMode::Adaptive, 0.25);
  form.name = "fill unit (1 plane)";
  return form;
}

// ---- timing ------------------------------------------------------------------------------

// CPU time of the whole process (Mesa's llvmpipe rasterizes on threads of this process), so
// that a loaded machine's share of the cores shows as wall time > CPU time / threads.
double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// One form in its own offscreen window, ready to draw (actors built, shaders compiled and
// buffers uploaded by the warm-up frames).
class FormWindow {
public:
  FormWindow(const Form& form, int W, int H, double nearZ, double farZ)
      : nearZ_(nearZ), farZ_(farZ) {
    renderer_->SetBackground(0, 0, 0);
    vtkrender::useLayerOrderBlending(renderer_);
    vtkrender::addLayerActors(renderer_, form.layers);
    window_->SetOffScreenRendering(1);
    window_->SetMultiSamples(0);
    window_->SetSize(W, H);
    window_->AddRenderer(renderer_);
  }
  void draw(const scene::Camera& c) {
    vtkrender::setCamera(renderer_->GetActiveCamera(), c, nearZ_, farZ_);
    window_->Render();
    window_->WaitForCompletion();
  }
  std::vector<float> grab() { return vtkrender::grabRGB(window_); }

private:
  vtkNew<vtkRenderer> renderer_;
  vtkNew<vtkRenderWindow> window_;
  double nearZ_, farZ_;
};

struct Timing {
  int frames = 0;
  double seconds = 0, cpuSeconds = 0;
  std::vector<double> roundMsPerFrame;    ///< per round
  std::vector<std::vector<float>> images; ///< at the sample cameras
};

// Draws cameras[begin, end) (or fewer, when `budget` seconds run out) and adds them to `t`.
void timeRound(FormWindow& w, const std::vector<scene::Camera>& cameras, std::size_t begin,
               std::size_t end, double budget, Timing& t) {
  const auto t0 = Clock::now();
  const double cpu0 = processCpuSeconds();
  int frames = 0;
  double seconds = 0;
  for (std::size_t f = begin; f < end && seconds <= budget; ++f) {
    w.draw(cameras[f]);
    ++frames;
    seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  }
  t.frames += frames;
  t.seconds += seconds;
  t.cpuSeconds += processCpuSeconds() - cpu0;
  t.roundMsPerFrame.push_back(1000.0 * seconds / std::max(frames, 1));
}

// Times every form in rounds that take turns (each round draws the next stretch of the orbit
// with every form), so that a change of the machine's load between forms shows in all of them
// alike; then renders the sample cameras.
std::vector<Timing> timeForms(const std::vector<Form>& forms,
                              const std::vector<scene::Camera>& cameras,
                              const std::vector<std::size_t>& samples, double nearZ, double farZ,
                              const BenchRenderOptions& o) {
  std::vector<std::unique_ptr<FormWindow>> windows;
  for (const Form& form : forms) {
    windows.push_back(
        std::make_unique<FormWindow>(form, cameras[0].width, cameras[0].height, nearZ, farZ));
    for (int f = 0; f < o.warmup; ++f)
      windows.back()->draw(cameras[static_cast<std::size_t>(f) % cameras.size()]);
  }
  const std::size_t rounds = std::min<std::size_t>(5, cameras.size());
  std::vector<Timing> timings(forms.size());
  for (std::size_t r = 0; r < rounds; ++r)
    for (std::size_t f = 0; f < forms.size(); ++f)
      timeRound(*windows[f], cameras, r * cameras.size() / rounds,
                (r + 1) * cameras.size() / rounds, o.maxSeconds / rounds, timings[f]);
  for (std::size_t f = 0; f < forms.size(); ++f)
    for (std::size_t s : samples) {
      windows[f]->draw(cameras[s]);
      timings[f].images.push_back(windows[f]->grab());
    }
  return timings;
}

// Median over rounds of (frame time of `t` / frame time of `unit`).
double fillUnits(const Timing& t, const Timing& unit) {
  std::vector<double> ratios;
  for (std::size_t r = 0; r < t.roundMsPerFrame.size(); ++r)
    ratios.push_back(t.roundMsPerFrame[r] / unit.roundMsPerFrame[r]);
  std::sort(ratios.begin(), ratios.end());
  const std::size_t n = ratios.size();
  return n % 2 ? ratios[n / 2] : 0.5 * (ratios[n / 2 - 1] + ratios[n / 2]);
}

// Writes interleaved RGB in [0, 1] (row 0 = top) as DIR/NAME_sampleS.png (8-bit).
void saveImages(const BenchRenderOptions& o, const std::string& name, const Timing& t, int W,
                int H) {
  if (o.saveImages.empty())
    return;
  std::filesystem::create_directories(o.saveImages);
  std::string stem = name;
  std::replace(stem.begin(), stem.end(), ' ', '_');
  for (std::size_t s = 0; s < t.images.size(); ++s) {
    cv::Mat bgr(H, W, CV_8UC3);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)
        for (int c = 0; c < 3; ++c) // OpenCV stores BGR
          bgr.at<cv::Vec3b>(y, x)[2 - c] = cv::saturate_cast<unsigned char>(
              255.0 * t.images[s][3 * (static_cast<std::size_t>(y) * W + x) + c] + 0.5);
    const std::string path = o.saveImages + "/" + stem + "_sample" + std::to_string(s) + ".png";
    if (!cv::imwrite(path, bgr))
      fail("--save-images: cannot write ", path);
  }
}

// ---- the OpenCL rasterizer ---------------------------------------------------------------

double psnrAgainst(const Timing& a, const Timing& reference, int W, int H,
                   const std::vector<std::vector<std::uint8_t>>* masks = nullptr);

// Median wall time (ms) of `render` over the first frames of the orbit (at most `budget` s), and
// its RGB at the sample cameras, interleaved like the VTK images.
template <typename Render>
std::pair<double, Timing> timeRaster(Render&& render, const std::vector<scene::Camera>& cameras,
                                     const std::vector<std::size_t>& samples, int frames,
                                     double budget) {
  render(cameras[0]); // warm-up: kernel compilation, buffer pool
  Timing t;
  std::vector<double> ms;
  const auto start = Clock::now();
  for (int f = 0;
       f < frames && std::chrono::duration<double>(Clock::now() - start).count() <= budget; ++f) {
    const auto t0 = Clock::now();
    render(cameras[static_cast<std::size_t>(f) % cameras.size()]);
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  t.frames = static_cast<int>(ms.size());
  for (std::size_t s : samples) {
    const std::vector<float> planar = render(cameras[s]);
    const std::size_t n = planar.size() / 3;
    std::vector<float> rgb(planar.size());
    for (std::size_t p = 0; p < n; ++p)
      for (std::size_t c = 0; c < 3; ++c)
        rgb[3 * p + c] = planar[c * n + p];
    t.images.push_back(std::move(rgb));
  }
  std::sort(ms.begin(), ms.end());
  return {ms[ms.size() / 2], t};
}

// Per sample camera, the pixels whose farthest per-texel fragment is on the back layer (layer
// 0): elsewhere (past the back layer's edge, seen from an orbit camera) the farthest-fragment
// rule shows whatever front-layer texel is there, transparent ones included in the per-texel
// form but not in the adaptive one, so the two forms differ by design.
std::vector<std::vector<std::uint8_t>> backLayerMasks(const raster::MLITensors& tensors,
                                                      const mli::MLI& mli,
                                                      const std::vector<scene::Camera>& cameras,
                                                      const std::vector<std::size_t>& samples,
                                                      const raster::RasterSettings& settings) {
  std::vector<std::vector<std::uint8_t>> masks;
  for (std::size_t s : samples) {
    const raster::RasterFragments f =
        raster::rasterizeLayers(tensors.depth, mli.camera, cameras[s], settings);
    const std::vector<double> layer = f.layerIndex().toVector();
    const std::size_t n = static_cast<std::size_t>(f.targetHeight) * f.targetWidth;
    std::vector<std::uint8_t> mask(n, 0);
    for (std::size_t p = 0; p < n; ++p) {
      double farthest = -1;
      for (int k = 0; k < f.maxFragments; ++k)
        if (layer[k * n + p] >= 0)
          farthest = layer[k * n + p];
      mask[p] = farthest == 0;
    }
    masks.push_back(std::move(mask));
  }
  return masks;
}

void benchRaster(const mli::MLI& mli, const std::vector<scene::Camera>& cameras,
                 const std::vector<std::size_t>& samples, const BenchRenderOptions& o) {
  if (!o.device.empty()) {
    const auto [platform, device] = ocl::Device::parseSelector(o.device, "--device");
    ocl::Device::select(platform, device);
  }
  ocl::NoGradGuard noGrad;
  const int W = cameras[0].width, H = cameras[0].height;
  std::printf("\nOpenCL rasterizer on %s (median of up to %d frames, at most %.0f s per form; "
              "per-texel: the differentiable rasterizer, 16 fragments, perspective-correct; "
              "adaptive: raster/render_adaptive.h; PSNR where the back layer is seen)\n",
              ocl::Device::current().info().deviceName.c_str(), std::min(o.frames, 10),
              o.maxSeconds);
  std::printf("%-22s %9s %10s %8s %9s %14s\n", "form", "build ms", "triangles", "fps", "ms/frame",
              "PSNR/per-texel");
  const raster::MLITensors tensors = raster::mliTensors(mli);
  raster::RasterSettings perspective; // as OpenGL interpolates
  perspective.interpolation = raster::RasterInterpolation::PerspectiveCorrect;
  auto perTexel = [&](const scene::Camera& c) {
    return raster::renderLayers(tensors.depth, tensors.rgba, mli.camera, c, perspective)
        .colour.toVectorF32();
  };
  const auto [perTexelMs, perTexelTiming] =
      timeRaster(perTexel, cameras, samples, std::min(o.frames, 10), o.maxSeconds);
  const auto masks = backLayerMasks(tensors, mli, cameras, samples, perspective);
  saveImages(o, "raster per-texel", perTexelTiming, W, H);
  std::printf("%-22s %9s %10lld %8.2f %9.1f %14s\n", "per-texel", "-",
              static_cast<long long>(mli.numLayers()) * 2 * (mli.height() - 1) * (mli.width() - 1),
              1000.0 / perTexelMs, perTexelMs, "-");
  for (double tolerance : o.tolerances) {
    mli::AdaptiveMeshOptions options;
    options.tolerancePixels = tolerance;
    const auto t0 = Clock::now();
    const raster::AdaptiveRenderer renderer(raster::buildAdaptiveMLI(mli, options));
    const double buildMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    auto render = [&](const scene::Camera& c) { return renderer.render(c).colour.toVectorF32(); };
    const auto [ms, timing] =
        timeRaster(render, cameras, samples, std::min(o.frames, 10), o.maxSeconds);
    char name[64], psnr[32];
    std::snprintf(name, sizeof name, "adaptive %.3g px", tolerance);
    std::snprintf(psnr, sizeof psnr, "%.2f dB", psnrAgainst(timing, perTexelTiming, W, H, &masks));
    saveImages(o, std::string("raster ") + name, timing, W, H);
    std::printf("%-22s %9.1f %10zu %8.2f %9.1f %14s\n", name, buildMs,
                renderer.adaptive().numTriangles(), 1000.0 / ms, ms, psnr);
    std::fflush(stdout);
  }
}

// PSNR of `a`'s images against `reference`'s over the paper's central crop (90 % of the area):
// at the image border an orbit camera sees past the back layer, where the rasterizer's
// farthest-fragment rule makes whatever front-layer fragment is there opaque, the per-texel
// form's transparent texels included.
double psnrAgainst(const Timing& a, const Timing& reference, int W, int H,
                   const std::vector<std::vector<std::uint8_t>>* masks) {
  const metrics::CropWindow crop = metrics::centralCrop(W, H);
  double se = 0;
  std::size_t n = 0;
  for (std::size_t s = 0; s < a.images.size(); ++s)
    for (int y = crop.y; y < crop.y + crop.height; ++y)
      for (int x = crop.x; x < crop.x + crop.width; ++x)
        for (int c = 0; c < 3; ++c) {
          if (masks && !(*masks)[s][static_cast<std::size_t>(y) * W + x])
            continue;
          const std::size_t i = 3 * (static_cast<std::size_t>(y) * W + x) + c;
          const double d = static_cast<double>(a.images[s][i]) - reference.images[s][i];
          se += d * d;
          ++n;
        }
  return se == 0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(n / se);
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (!(in >> a >> b >> c))
    return "unknown";
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.2f %.2f %.2f (1, 5, 15 min) on %u hardware threads", a, b, c,
                std::thread::hardware_concurrency());
  return buf;
}

void validate(const BenchRenderOptions& o) {
  if (o.synthetic == !o.mli.empty())
    fail(o.synthetic ? "--synthetic and an MLI folder exclude each other"
                     : "give an MLI folder or --synthetic");
  if (o.frames < 1)
    fail("--frames ", o.frames, ": need at least 1");
  if (o.warmup < 0)
    fail("--warmup ", o.warmup, ": must be >= 0");
  if (!(o.maxSeconds > 0))
    fail("--max-seconds ", o.maxSeconds, ": must be > 0");
  for (double t : o.tolerances)
    if (!(t >= 0) || !std::isfinite(t))
      fail("--tolerance ", t, ": must be finite and >= 0");
}

void runBenchRender(BenchRenderOptions o) {
  if (o.quick) {
    o.synthetic = o.synthetic || o.mli.empty();
    o.size = "320x240";
    o.frames = std::min(o.frames, 8);
    o.warmup = std::min(o.warmup, 1);
    o.maxSeconds = std::min(o.maxSeconds, 5.0);
  }
  validate(o);
  const io::ImageSize size = io::parseImageSize(o.size, "--size", {16, 8192, 1});
  const int W = size.width, H = size.height;
  if (!vtkrender::holdXDisplay())
    fail("bench render needs an X server (DISPLAY=",
         std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "unset",
         "): run it under xvfb-run -a, or on a desktop");
  const mli::MLI mli = o.synthetic ? (o.quick ? syntheticMLI(160, 120) : syntheticMLI(1008, 752))
                                   : mli::readMLI(o.mli);
  mli::validateMLI(mli, o.synthetic ? "synthetic MLI" : o.mli);
  if (!o.saveMli.empty())
    mli::writeMLI(o.saveMli, mli, mli::MLIFormat::Lossless);

  double near = std::numeric_limits<double>::infinity(), far = 0;
  for (const mli::MLILayer& layer : mli.layers)
    for (float d : layer.depth) {
      near = std::min(near, static_cast<double>(d));
      far = std::max(far, static_cast<double>(d));
    }
  scene::TrajectoryOptions orbit;
  orbit.kind = scene::TrajectoryKind::Orbit;
  orbit.frames = o.frames;
  orbit = scene::resolveTrajectory(orbit, mli.camera, {}, near, far);
  std::vector<scene::Camera> cameras = scene::makeTrajectory(mli.camera, orbit);
  for (scene::Camera& c : cameras) {
    c.width = W;
    c.height = H;
    c.fx = c.fy * H / W;
  }
  std::vector<std::size_t> samples;
  for (std::size_t s = 0; s < 4; ++s)
    samples.push_back(s * cameras.size() / 4);
  const double nearZ = 0.25 * near, farZ = 4.0 * far;

  std::printf("bench render: %s, %d layers of %d x %d texels; offscreen window %d x %d; orbit "
              "of %zu cameras, radius %.4g (focus depth %.4g); %d warm-up frame(s), up to %d "
              "timed (at most %.0f s per form)\n",
              o.synthetic ? "synthetic MLI" : o.mli.c_str(), mli.numLayers(), mli.width(),
              mli.height(), W, H, cameras.size(), orbit.radii.x(), orbit.focusDepth, o.warmup,
              o.frames, o.maxSeconds);
  std::printf("load average at start: %s\n", loadAverage().c_str());
  std::printf("%-22s %9s %10s %10s %8s %8s %9s %9s %7s %6s %14s\n", "form", "build ms", "triangles",
              "points", "MiB", "fps", "ms/frame", "CPU ms/f", "frames", "units", "PSNR/per-texel");
  std::fflush(stdout);

  std::vector<Form> forms;
  forms.push_back(fillUnitForm(mli));
  forms.push_back(buildForm(mli, vtkmli::MeshMode::PerTexel, 0.0));
  for (double t : o.tolerances)
    forms.push_back(buildForm(mli, vtkmli::MeshMode::Adaptive, t));
  const std::vector<Timing> timings = timeForms(forms, cameras, samples, nearZ, farZ, o);
  for (std::size_t f = 0; f < forms.size(); ++f) {
    const Timing& t = timings[f];
    saveImages(o, "vtk " + forms[f].name, t, W, H);
    const double ms = 1000.0 * t.seconds / t.frames;
    char psnr[32] = "-";
    if (f > 1)
      std::snprintf(psnr, sizeof psnr, "%.2f dB", psnrAgainst(t, timings[1], W, H));
    std::printf("%-22s %9.1f %10lld %10lld %8.2f %8.2f %9.2f %9.2f %7d %6.2f %14s\n",
                forms[f].name.c_str(), forms[f].buildMs, forms[f].triangles, forms[f].points,
                forms[f].bytes / 1048576.0, 1000.0 / ms, ms, 1000.0 * t.cpuSeconds / t.frames,
                t.frames, fillUnits(t, timings[0]), psnr);
  }
  std::printf("units: frame time / the fill unit's (one opaque textured plane covering the "
              "window) in the same round (median of %zu rounds); the same on any machine to the "
              "extent that both are fill-bound\n",
              std::min<std::size_t>(5, cameras.size()));
  if (o.raster)
    benchRaster(mli, cameras, samples, o);
  std::printf("load average at end: %s\n", loadAverage().c_str());
}

} // namespace

void addBenchRenderCommand(CLI::App& bench) {
  auto o = std::make_shared<BenchRenderOptions>();
  auto* cmd = bench.add_subcommand(
      "render", "Time VTK/OpenGL rendering of an MLI's per-texel and adaptive forms (needs X)");
  cmd->add_option("mli", o->mli, "MLI folder (reference JPEG form or lossless form)");
  cmd->add_flag("--synthetic", o->synthetic,
                "A synthetic 4-layer 1008 x 752 MLI (the standard measurement)");
  cmd->add_flag("--quick", o->quick,
                "Small: a 160 x 120 synthetic MLI, a 320 x 240 window, 8 frames (a smoke test)");
  cmd->add_option("--size", o->size, "Window size WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--frames", o->frames, "Timed frames per form (one orbit)")
      ->capture_default_str();
  cmd->add_option("--warmup", o->warmup, "Untimed frames first")->capture_default_str();
  cmd->add_option("--max-seconds", o->maxSeconds, "Stop timing a form after this long")
      ->capture_default_str();
  cmd->add_option("--tolerance", o->tolerances,
                  "Adaptive mesh tolerances in pixels, comma separated (one form each)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--save-mli", o->saveMli,
                  "Also write the MLI measured (e.g. the synthetic one) here, lossless form");
  cmd->add_option("--save-images", o->saveImages,
                  "Write every form's images at the 4 sample cameras here (PNG)");
  cmd->add_flag("--raster", o->raster,
                "Also time the OpenCL rasterizer (per-texel and adaptive) at the same cameras");
  cmd->add_option("--device", o->device,
                  "OpenCL device for --raster as platform:device (see simpli devices)");
  cmd->callback([o] { runBenchRender(*o); });
}

} // namespace simpli::app

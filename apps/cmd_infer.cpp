// `simpli infer SCENE --out DIR`: builds the MLI of a scene with the SIMPLI network
// (generator::MLIBuilder, model/generator/mli_builder.h) and writes it in both MLI forms
// (mli/files.h): the reference's JPEG form in DIR and simpli's lossless float form in DIR/lossless.
// Source views: all views of the scene, or --views; the reference camera is the pose average of the
// sources (spec §6.1). Optionally renders views of the scene (--render-views; held-out ones measure
// quality) to PNG and prints PSNR / SSIM on the paper's 90 % central crop, and prints the time of
// every generator stage. The forward pass shows a progress bar over its stages; SIGINT / SIGTERM
// cancel it after the current stage (or after the write, before the commit), write nothing and
// exit with 130 / 143.
//
// SCENE may also be a folder of scene folders: `simpli infer SCENES_DIR --out OUT` builds each
// into OUT/<scene> (cmd_infer_scenes.cpp), spread over the ranks under mpiexec.
//
// DIR is written as a whole (io/staged_folder.h): both MLI forms, the rendered views and the
// random weights go into one hidden staging sibling that replaces DIR in one step, so a failure or
// a kill leaves the old complete DIR or the new one. An existing DIR is replaced only when it
// holds nothing but what an earlier `simpli infer` wrote (mli::mliReplaceRefusal with the extras
// below); anything else is refused before the forward pass.
#include "commands.h"
#include "infer.h"
#include "progress_bar.h"
#include "reference_margin_option.h"
#include "simpli/model/network/loader.h"
#include "stop_signals.h"

#include "simpli/error.h"
#include "simpli/model/generator/layer_choice.h"
#include "simpli/model/generator/mli_builder.h"
#include "simpli/model/io/image.h"
#include "simpli/model/io/staged_folder.h"
#include "simpli/model/metrics/image_quality.h"
#include "simpli/model/mli/files.h"
#include "simpli/model/raster/render_mli.h"
#include "simpli/model/scene/scene.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_elementwise.h"
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace simpli::app {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

void checkViewIndices(const std::vector<int>& indices, std::size_t count, const char* option) {
  std::set<int> seen;
  for (int i : indices) {
    if (i < 0 || static_cast<std::size_t>(i) >= count)
      fail(option, " ", i, ": the scene has views 0..", count - 1);
    if (!seen.insert(i).second)
      fail(option, ": view ", i, " is listed twice");
  }
}

/// MLIBuildOptions::dropEmptyBelow for --layers: "all" keeps every surface, "auto" first drops
/// those with nothing visible after 8-bit export (then chooseLayers, in inferScene, keeps the
/// fewest of the rest within 0.2 dB on the source views), N checks that the network has N
/// surfaces.
float layersThreshold(const std::string& layers, const network::NetworkConfig& config) {
  if (layers == "all")
    return 0.0f;
  if (layers == "auto")
    return 1.0f / 255.0f;
  int n = 0;
  try {
    std::size_t used = 0;
    n = std::stoi(layers, &used);
    if (used != layers.size())
      n = -1;
  } catch (const std::exception&) {
    n = -1;
  }
  if (n <= 0)
    fail("--layers '", layers, "': expected auto, all or a number of layers");
  if (n != config.surfaces())
    fail("--layers ", n, ": the network (config '", config.name, "') has ", config.surfaces(),
         config.mpiOnly ? " planes" : " layers",
         "; choose a config with that many layers (e.g. official-", n, "l)");
  return 0.0f;
}

int cancelled(const std::string& out, bool verbose) {
  const int sig = stopSignal();
  if (verbose)
    std::fprintf(stderr, "simpli infer: %s received; cancelled, nothing written to %s\n",
                 sig == SIGTERM ? "SIGTERM" : "SIGINT", out.c_str());
  return 128 + sig;
}

/// The network's image of a rendered colour [3, H, W] in [-1, 1].
io::Image toImage(const ocl::Tensor& colour) {
  io::Image image(static_cast<int>(colour.size(2)), static_cast<int>(colour.size(1)));
  image.data = colour.toVectorF32();
  return image;
}

/// printf when `on` (the one-scene report; a folder of scenes prints one table instead).
__attribute__((format(printf, 2, 3))) void report(bool on, const char* format, ...) {
  if (!on)
    return;
  va_list args;
  va_start(args, format);
  std::vfprintf(stdout, format, args);
  va_end(args);
}

/// SCENE is a folder of scene folders (not a scene, and at least one subfolder is one).
bool isSceneCollection(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_directory(path, ec) || scene::isSceneFolder(path))
    return false;
  for (const scene::SceneFolder& s : scene::listSceneFolders(path))
    if (s.problem.empty())
      return true;
  return false;
}

int runInfer(const InferOptions& o) {
  // Before the device is opened (stop_signals.h), and until the output is committed: a signal
  // cancels the forward pass or the write, and never kills the command or its helpers.
  StopSignals signals;
  if (!o.device.empty()) {
    const auto [platform, device] = ocl::Device::parseSelector(o.device, "--device");
    ocl::Device::select(platform, device);
  }
  if (o.corrections < -1)
    fail("--corrections ", o.corrections, ": must be >= 0 (or -1 for all)");
  generator::checkInputScale(o.inputScale, "--input-scale");
  checkReferenceMargin(o.referenceMargin);
  if (o.out.empty())
    fail("--out: an output folder is required");
  if (isSceneCollection(o.scene))
    return inferScenes(o, scene::listSceneFolders(o.scene));
  InferNetwork net;
  return inferScene(o, o.scene, o.out, net, /*verbose=*/true).exitCode;
}

} // namespace

mli::MLIFolderExtras inferOutputExtras() {
  mli::MLIFolderExtras extras;
  extras.mliFolders = {"lossless"};
  extras.isExtraFile = [](const std::string& name) {
    if (name == "random_weights.safetensors")
      return true;
    const std::string prefix = "render_", suffix = ".png";
    if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      return false;
    const std::string digits =
        name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    return digits.find_first_not_of("0123456789") == std::string::npos;
  };
  return extras;
}

void loadInferNetwork(const InferOptions& o, InferNetwork& net) {
  if (net.loaded)
    return;
  generator::NetworkSource source;
  source.config = o.config;
  source.weights = o.weights;
  if (o.initRandom >= 0)
    source.randomSeed = static_cast<uint64_t>(o.initRandom);
  const network::LoadedNetwork& loaded = net.builder.network(source);
  const network::NetworkConfig& config = loaded.network->config();
  if (o.corrections > config.mliCorrections())
    fail("--corrections ", o.corrections, ": config '", config.name, "' has ",
         config.mliCorrections(), " corrections");
  net.build.corrections = o.corrections;
  net.build.inputScale = o.inputScale;
  net.build.referenceMargin = o.referenceMargin;
  net.build.keepOutput = true; // for --render-views
  net.build.dropEmptyBelow = layersThreshold(o.layers, config);
  net.loaded = &loaded;
}

SceneInference inferScene(const InferOptions& o, const std::string& scenePath,
                          const std::string& out, InferNetwork& net, bool verbose) {
  namespace fs = std::filesystem;
  const auto start = Clock::now();
  SceneInference result;
  // Before the long work: an output that cannot be written or must not be replaced fails now.
  const io::ReplaceCheck replaceable = [](const fs::path& folder) {
    return mli::mliReplaceRefusal(folder.string(), inferOutputExtras());
  };
  io::checkReplaceable(out, replaceable, "--out");
  io::checkOutputLocation(out, "--out", /*createParents=*/true);

  // Scene and source views.
  auto t0 = Clock::now();
  const scene::Scene scene = scene::readScene(scenePath);
  std::vector<int> views = o.views;
  if (views.empty())
    for (std::size_t i = 0; i < scene.size(); ++i)
      views.push_back(static_cast<int>(i));
  checkViewIndices(views, scene.size(), "--views");
  checkViewIndices(o.renderViews, scene.size(), "--render-views");
  const double readMs = msSince(t0);

  // Network.
  loadInferNetwork(o, net);
  network::SimpliNetwork& network = *net.loaded->network;
  const network::NetworkConfig& config = network.config();
  generator::MLIBuildOptions options = net.build;
  options.views = views;

  const int H = scene.height(), W = scene.width();
  report(verbose, "scene      %s (%s, %zu views of %d x %d)\n", scenePath.c_str(),
         toString(scene.format), scene.size(), W, H);
  std::string list;
  for (int v : views)
    list += (list.empty() ? "" : ",") + std::to_string(v);
  report(verbose, "sources    %zu views: %s\n", views.size(), list.c_str());
  if (o.inputScale != 1.0)
    report(verbose, "input      resized to %d x %d before the network (--input-scale %g)\n",
           generator::scaledSize(W, o.inputScale), generator::scaledSize(H, o.inputScale),
           o.inputScale);
  report(verbose, "network    config %s (%s), %lld parameters\n", config.name.c_str(),
         net.loaded->configSource.c_str(), static_cast<long long>(network.parameters().count()));
  report(verbose, "weights    %s\n", net.loaded->weightsDescription.c_str());
  report(verbose, "device     %s\n", ocl::Device::current().info().deviceName.c_str());

  // Forward pass and the MLI.
  ocl::BufferPool& pool = ocl::Device::current().pool();
  pool.resetPeak();
  const std::size_t liveBefore = pool.stats().liveBytes;
  t0 = Clock::now();
  generator::MLIBuild build;
  {
    std::fflush(stdout);
    std::unique_ptr<ProgressBar> bar;
    if (verbose)
      bar = std::make_unique<ProgressBar>("forward", 1);
    options.progress = [&bar](const std::string& stage, int done, int total) {
      if (bar) { // the bar counts stages; `total` is known once the pass starts
        bar->setTotal(total);
        bar->update(done, stage);
      }
      return stopSignal() == 0;
    };
    try {
      build = net.builder.build(scene, options);
    } catch (const generator::GeneratorCancelled&) {
      if (bar)
        bar->finish();
      result.exitCode = cancelled(out, verbose);
      return result;
    }
    if (bar)
      bar->finish();
  }
  const generator::GeneratorOutput& output = *build.output;
  const generator::GeneratorInput& input = build.input;
  const double forwardMs = msSince(t0);
  // One pass per scene: hand the buffers the pool parked for reuse back to the device.
  pool.trim();
  report(verbose, "stages (ms):");
  for (const auto& [name, ms] : output.stageMs)
    report(verbose, " %s %.1f", name.c_str(), ms);
  report(verbose, "\nforward    %.1f ms, peak device memory %.1f MiB\n", forwardMs,
         (pool.stats().peakBytes - std::min(liveBefore, pool.stats().peakBytes)) / 1048576.0);

  // Everything goes into one staging folder that replaces the output at the end.
  t0 = Clock::now();
  if (o.layers == "auto") {
    // The smallest MLI within 0.2 dB PSNR of the full one on the source views
    // (generator/layer_choice.h), said in the report.
    const auto tc = Clock::now();
    std::vector<scene::Camera> cameras;
    std::vector<io::Image> images;
    for (int v : views) {
      cameras.push_back(scene.views[static_cast<std::size_t>(v)].camera);
      images.push_back(scene.views[static_cast<std::size_t>(v)].image);
    }
    const int before = build.mli.numLayers();
    generator::LayerChoice choice = generator::chooseLayers(build.mli, cameras, images);
    std::string kept;
    for (int k : choice.kept)
      kept += (kept.empty() ? "" : ",") + std::to_string(k);
    report(verbose,
           "layers     auto: kept %zu of %d visible layers (%s; farthest = 0), source-view PSNR "
           "%.2f dB against %.2f dB with all (within 0.2 dB); %d renders, %.1f ms\n",
           choice.kept.size(), before, kept.c_str(), choice.chosenPsnr, choice.fullPsnr,
           choice.renders, msSince(tc));
    build.mli = std::move(choice.mli);
  }
  const mli::MLI& mli = build.mli;
  const fs::path outDir(out);
  if (outDir.has_parent_path())
    fs::create_directories(outDir.parent_path());
  io::StagedFolder staged(out, replaceable, {"--out"});
  const fs::path& tmp = staged.path();
  mli::writeMLIFiles(tmp.string(), mli, mli::MLIFormat::Jpeg);
  fs::create_directory(tmp / "lossless");
  mli::writeMLIFiles((tmp / "lossless").string(), mli, mli::MLIFormat::Lossless);
  const std::string lossless = (outDir / "lossless").string();
  const int surfaces = static_cast<int>(output.rgba.size(0));
  report(verbose, "MLI        %d of %d %s (%d x %d) -> %s (jpeg), %s (lossless); %.1f ms\n",
         mli.numLayers(), surfaces, config.mpiOnly ? "planes" : "layers", mli.width(), mli.height(),
         out.c_str(), lossless.c_str(), msSince(t0));
  if (o.initRandom >= 0) {
    // So that the same random network can be loaded again (tests, benchmarks).
    network.parameters().save(
        (tmp / "random_weights.safetensors").string(),
        {{"config", network::toJson(config)}, {"seed", std::to_string(o.initRandom)}});
    report(verbose, "weights    saved to %s\n", (outDir / "random_weights.safetensors").c_str());
  }

  // Rendered views.
  for (int k : o.renderViews) {
    t0 = Clock::now();
    const scene::SceneView& view = scene.views[static_cast<std::size_t>(k)];
    io::Image image;
    {
      ocl::NoGradGuard noGrad;
      if (o.layers == "auto") { // what was written: the layers chosen
        const raster::RenderedLayers r = raster::renderMLI(mli, view.camera);
        image = toImage(ocl::addScalar(ocl::mulScalar(r.colour, 2.0), -1.0));
      } else {
        image = toImage(generator::renderNovelView(output, input.reference, view.camera).colour);
      }
    }
    char name[64];
    std::snprintf(name, sizeof name, "render_%03d.png", k);
    io::writeImagePng(image, (tmp / name).string());
    const bool source = std::find(views.begin(), views.end(), k) != views.end();
    const metrics::ImageQuality q = metrics::evaluateImageQuality(
        metrics::metricImageFromImage(image), metrics::metricImageFromImage(view.image));
    report(verbose, "view %-5d %s PSNR %.2f dB SSIM %.4f (%s, 90%% central crop); %.1f ms\n", k,
           (outDir / name).c_str(), q.psnr, q.ssim, source ? "source view" : "held out",
           msSince(t0));
  }
  std::fflush(stdout);
  if (stopSignal() != 0) {
    result.exitCode = cancelled(out, verbose); // the staging folder goes with `staged`
    return result;
  }
  staged.commit();
  result.ms = msSince(start);
  result.layers = mli.numLayers();
  result.width = mli.width();
  result.height = mli.height();
  report(verbose, "total      %.1f ms (scene read %.1f ms)\n", result.ms, readMs);
  return result;
}

void addInferCommand(CLI::App& app) {
  auto o = std::make_shared<InferOptions>();
  auto* cmd = app.add_subcommand(
      "infer", "Build the multi-layer image (MLI) of a scene with the SIMPLI network");
  cmd->add_option("scene", o->scene,
                  "Scene folder (LLFF, COLMAP or RealEstate10K), or a folder of scene folders "
                  "(each into OUT/<name>; spread over the ranks under mpiexec)")
      ->required();
  cmd->add_option("--out", o->out,
                  "Output folder: the MLI in JPEG form, its lossless form in OUT/lossless, "
                  "rendered views; written as a whole, and an existing one is replaced only if "
                  "it holds nothing but an earlier simpli infer output (a folder of scenes: "
                  "OUT/<scene> each by these rules)")
      ->required();
  cmd->add_option("--weights", o->weights,
                  "Network weights (safetensors, reference key names); default "
                  "model/weights/default.safetensors");
  cmd->add_option("--config", o->config,
                  "Network config: official-4l, official-8l, a name in model/configs or a .json "
                  "file; default: the weights' \"config\" metadata");
  CLI::Option* views = cmd->add_option("--views", o->views,
                                       "Source views (scene indices, comma separated); default all")
                           ->delimiter(',');
  cmd->add_option("--layers", o->layers,
                  "all (default), auto (the fewest layers within 0.2 dB PSNR of all of them on the "
                  "source views; says which) or N (check that the network has N layers)");
  cmd->add_option("--corrections", o->corrections,
                  "MLI correction steps to run (default: all of the config's)");
  cmd->add_option("--input-scale", o->inputScale,
                  "Resize the sources by this factor (0, 2] before the network: the MLI is built "
                  "at that size (the shipped network holds best near 256x192, README)")
      ->capture_default_str();
  addReferenceMarginOption(*cmd, o->referenceMargin);
  CLI::Option* renderViews =
      cmd->add_option(
             "--render-views", o->renderViews,
             "Scene views to render to OUT/render_KKK.png with PSNR / SSIM (comma separated)")
          ->delimiter(',');
  cmd->add_option("--device", o->device, "OpenCL device as platform:device (see simpli devices)");
  auto* seed =
      cmd->add_option("--init-random", o->initRandom,
                      "Testing / benchmarking only: random weights drawn with this seed (config "
                      "default official-4l), saved to OUT/random_weights.safetensors");
  cmd->callback([o, seed, views, renderViews] {
    // CLI11 converts an empty element ('' or "1,,2") to view 0.
    for (const CLI::Option* option : {views, renderViews})
      for (const std::string& value : option->results())
        if (value.empty())
          fail(option->get_name(), " '", value,
               "': expected view indices (comma separated), got an empty value");
    if (seed->count() > 0 && o->initRandom < 0)
      fail("--init-random ", o->initRandom, ": the seed must be >= 0");
    if (const int code = runInfer(*o); code != 0) {
      std::fflush(nullptr);
      std::exit(code);
    }
  });
}

} // namespace simpli::app

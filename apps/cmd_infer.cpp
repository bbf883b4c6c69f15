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
// DIR is written as a whole (io/staged_folder.h): both MLI forms, the rendered views and the
// random weights go into one hidden staging sibling that replaces DIR in one step, so a failure or
// a kill leaves the old complete DIR or the new one. An existing DIR is replaced only when it
// holds nothing but what an earlier `simpli infer` wrote (mli::mliReplaceRefusal with the extras
// below); anything else is refused before the forward pass.
#include "commands.h"
#include "progress_bar.h"
#include "simpli/model/network/loader.h"
#include "stop_signals.h"

#include "simpli/error.h"
#include "simpli/model/generator/mli_builder.h"
#include "simpli/model/io/image.h"
#include "simpli/model/io/staged_folder.h"
#include "simpli/model/metrics/image_quality.h"
#include "simpli/model/mli/files.h"
#include "simpli/model/scene/scene.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace simpli::app {

namespace {

struct InferOptions {
  std::string scene, weights, config, layers = "all", device, out;
  std::vector<int> views, renderViews;
  int corrections = -1;
  int64_t initRandom = -1; ///< >= 0: random weights with this seed
};

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

/// MLIBuildOptions::dropEmptyBelow for --layers: "all" keeps every surface, "auto" drops those
/// with nothing visible after 8-bit export, N checks that the network has N surfaces.
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

/// What `simpli infer` writes into DIR besides the JPEG MLI: the lossless MLI, rendered views,
/// the random weights.
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

int cancelled(const std::string& out) {
  const int sig = stopSignal();
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

int runInfer(const InferOptions& o) {
  namespace fs = std::filesystem;
  const auto start = Clock::now();
  // Before the device is opened (stop_signals.h), and until the output is committed: a signal
  // cancels the forward pass or the write, and never kills the command or its helpers.
  StopSignals signals;
  if (!o.device.empty()) {
    const auto [platform, device] = ocl::Device::parseSelector(o.device, "--device");
    ocl::Device::select(platform, device);
  }
  if (o.corrections < -1)
    fail("--corrections ", o.corrections, ": must be >= 0 (or -1 for all)");
  if (o.out.empty())
    fail("--out: an output folder is required");
  // Before the long work: an --out that cannot be written or must not be replaced fails now.
  const io::ReplaceCheck replaceable = [](const fs::path& folder) {
    return mli::mliReplaceRefusal(folder.string(), inferOutputExtras());
  };
  io::checkReplaceable(o.out, replaceable, "--out");
  io::checkOutputLocation(o.out, "--out", /*createParents=*/true);

  // Scene and source views.
  auto t0 = Clock::now();
  const scene::Scene scene = scene::readScene(o.scene);
  std::vector<int> views = o.views;
  if (views.empty())
    for (std::size_t i = 0; i < scene.size(); ++i)
      views.push_back(static_cast<int>(i));
  checkViewIndices(views, scene.size(), "--views");
  checkViewIndices(o.renderViews, scene.size(), "--render-views");
  const double readMs = msSince(t0);

  // Network.
  generator::MLIBuilder builder;
  generator::NetworkSource source;
  source.config = o.config;
  source.weights = o.weights;
  if (o.initRandom >= 0)
    source.randomSeed = static_cast<uint64_t>(o.initRandom);
  const network::LoadedNetwork& loaded = builder.network(source);
  network::SimpliNetwork& network = *loaded.network;
  const network::NetworkConfig& config = network.config();
  if (o.corrections > config.mliCorrections())
    fail("--corrections ", o.corrections, ": config '", config.name, "' has ",
         config.mliCorrections(), " corrections");
  generator::MLIBuildOptions options;
  options.views = views;
  options.corrections = o.corrections;
  options.keepOutput = true; // for --render-views
  options.dropEmptyBelow = layersThreshold(o.layers, config);

  const int H = scene.height(), W = scene.width();
  std::printf("scene      %s (%s, %zu views of %d x %d)\n", o.scene.c_str(), toString(scene.format),
              scene.size(), W, H);
  std::string list;
  for (int v : views)
    list += (list.empty() ? "" : ",") + std::to_string(v);
  std::printf("sources    %zu views: %s\n", views.size(), list.c_str());
  std::printf("network    config %s (%s), %lld parameters\n", config.name.c_str(),
              loaded.configSource.c_str(), static_cast<long long>(network.parameters().count()));
  std::printf("weights    %s\n", loaded.weightsDescription.c_str());
  std::printf("device     %s\n", ocl::Device::current().info().deviceName.c_str());

  // Forward pass and the MLI.
  ocl::BufferPool& pool = ocl::Device::current().pool();
  pool.resetPeak();
  const std::size_t liveBefore = pool.stats().liveBytes;
  t0 = Clock::now();
  generator::MLIBuild build;
  {
    std::fflush(stdout);
    ProgressBar bar("forward", 1);
    options.progress = [&bar](const std::string& stage, int done, int total) {
      // The bar counts stages; `total` is known once the pass starts.
      bar.setTotal(total);
      bar.update(done, stage);
      return stopSignal() == 0;
    };
    try {
      build = builder.build(scene, options);
    } catch (const generator::GeneratorCancelled&) {
      bar.finish();
      return cancelled(o.out);
    }
    bar.finish();
  }
  const generator::GeneratorOutput& output = *build.output;
  const generator::GeneratorInput& input = build.input;
  const double forwardMs = msSince(t0);
  // One pass per process: hand the buffers the pool parked for reuse back to the device.
  pool.trim();
  std::printf("stages (ms):");
  for (const auto& [name, ms] : output.stageMs)
    std::printf(" %s %.1f", name.c_str(), ms);
  std::printf("\nforward    %.1f ms, peak device memory %.1f MiB\n", forwardMs,
              (pool.stats().peakBytes - std::min(liveBefore, pool.stats().peakBytes)) / 1048576.0);

  // Everything goes into one staging folder that replaces --out at the end.
  t0 = Clock::now();
  const mli::MLI& mli = build.mli;
  const fs::path outDir(o.out);
  if (outDir.has_parent_path())
    fs::create_directories(outDir.parent_path());
  io::StagedFolder staged(o.out, replaceable, {"--out"});
  const fs::path& tmp = staged.path();
  mli::writeMLIFiles(tmp.string(), mli, mli::MLIFormat::Jpeg);
  fs::create_directory(tmp / "lossless");
  mli::writeMLIFiles((tmp / "lossless").string(), mli, mli::MLIFormat::Lossless);
  const std::string lossless = (outDir / "lossless").string();
  const int surfaces = static_cast<int>(output.rgba.size(0));
  std::printf("MLI        %d of %d %s (%d x %d) -> %s (jpeg), %s (lossless); %.1f ms\n",
              mli.numLayers(), surfaces, config.mpiOnly ? "planes" : "layers", mli.width(),
              mli.height(), o.out.c_str(), lossless.c_str(), msSince(t0));
  if (o.initRandom >= 0) {
    // So that the same random network can be loaded again (tests, benchmarks).
    network.parameters().save(
        (tmp / "random_weights.safetensors").string(),
        {{"config", network::toJson(config)}, {"seed", std::to_string(o.initRandom)}});
    std::printf("weights    saved to %s\n", (outDir / "random_weights.safetensors").c_str());
  }

  // Rendered views.
  for (int k : o.renderViews) {
    t0 = Clock::now();
    const scene::SceneView& view = scene.views[static_cast<std::size_t>(k)];
    raster::RenderedLayers r;
    {
      ocl::NoGradGuard noGrad;
      r = generator::renderNovelView(output, input.reference, view.camera);
    }
    const io::Image image = toImage(r.colour);
    char name[64];
    std::snprintf(name, sizeof name, "render_%03d.png", k);
    io::writeImagePng(image, (tmp / name).string());
    const bool source = std::find(views.begin(), views.end(), k) != views.end();
    const metrics::ImageQuality q = metrics::evaluateImageQuality(
        metrics::metricImageFromImage(image), metrics::metricImageFromImage(view.image));
    std::printf("view %-5d %s PSNR %.2f dB SSIM %.4f (%s, 90%% central crop); %.1f ms\n", k,
                (outDir / name).c_str(), q.psnr, q.ssim, source ? "source view" : "held out",
                msSince(t0));
  }
  std::fflush(stdout);
  if (stopSignal() != 0)
    return cancelled(o.out); // the staging folder goes with `staged`
  staged.commit();
  std::printf("total      %.1f ms (scene read %.1f ms)\n", msSince(start), readMs);
  return 0;
}

} // namespace

void addInferCommand(CLI::App& app) {
  auto o = std::make_shared<InferOptions>();
  auto* cmd = app.add_subcommand(
      "infer", "Build the multi-layer image (MLI) of a scene with the SIMPLI network");
  cmd->add_option("scene", o->scene, "Scene folder (LLFF, COLMAP or RealEstate10K)")->required();
  cmd->add_option("--out", o->out,
                  "Output folder: the MLI in JPEG form, its lossless form in OUT/lossless, "
                  "rendered views; written as a whole, and an existing one is replaced only if "
                  "it holds nothing but an earlier simpli infer output")
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
                  "all (default), auto (drop layers with nothing visible) or N (check that the "
                  "network has N layers)");
  cmd->add_option("--corrections", o->corrections,
                  "MLI correction steps to run (default: all of the config's)");
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

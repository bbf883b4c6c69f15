// `simpli eval DATA --weights W[,W2,...] --config C`: PSNR / SSIM of novel views with the
// paper's protocol (central 90 % crop), mean +- std over R repeated samples, next to the
// nearest-source-view baseline on the same samples. Several networks are scored on the same
// samples, with each one's time to build the surfaces and its paired difference to the first.
// `--protocol rff` is the paper's Real Forward-Facing protocol; `--out DIR` keeps the evidence
// (views.csv and one comparison picture per view of the first sample). A --weights entry
// `baseline:plane-sweep` is the non-learned plane-sweep stereo yardstick
// (baselines/plane_sweep_stereo.h), scored on the same samples as the networks.
#include "commands.h"
#include "progress_bar.h"
#include "reference_margin_option.h"

#include "simpli/error.h"
#include "simpli/model/baselines/plane_sweep_stereo.h"
#include "simpli/model/io/files.h"
#include "simpli/model/io/staged_folder.h"
#include "simpli/model/metrics/comparison_grid.h"
#include "simpli/model/network/loader.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/eval.h"
#include "simpli/ocl/device.h"
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace simpli::app {

namespace {

struct EvalCliOptions {
  std::vector<std::string> weights;
  std::string data, config, size, device, dtype = "f32", protocol = "none", out;
  int repeats = 1, views = 4, novel = 4, window = 0, scenes = 1, corrections = -1, factor = 0;
  double inputScale = 1.0;
  /// One for every network, or one per --weights entry (the same weights with two margins is a
  /// paired comparison of the margins).
  std::vector<double> referenceMargins{scene::recommendedReferenceMargin};
  int64_t seed = 0;
  // Which of the protocol's settings the user gave explicitly (those win over the protocol).
  bool givenSize = false, givenViews = false, givenNovel = false, givenRepeats = false,
       givenWindow = false;
};

// The paper's Real Forward-Facing protocol (Table 1): 512x384 images, sources and novel views
// drawn without replacement from all frames of the scene, 5 sources and 8 novel views, 20
// repeats; the central 90 % crop is evaluate()'s default.
void applyProtocol(EvalCliOptions& o) {
  if (o.protocol == "none")
    return;
  if (o.protocol != "rff")
    fail("--protocol '", o.protocol, "': expected rff or none");
  if (!o.givenSize)
    o.size = "512x384";
  if (!o.givenViews)
    o.views = 5;
  if (!o.givenNovel)
    o.novel = 8;
  if (!o.givenRepeats)
    o.repeats = 20;
  if (!o.givenWindow)
    o.window = 0;
}

// The --weights entry that names the plane-sweep stereo baseline instead of a weights file.
constexpr const char* kPlaneSweepBaseline = "baseline:plane-sweep";

bool isBaseline(const std::string& weights) {
  return weights.rfind("baseline:", 0) == 0;
}

std::string csvQuote(const std::string& s) {
  std::string q = "\"";
  for (char c : s)
    q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string frameList(const std::vector<int>& frames) {
  std::string s;
  for (int f : frames)
    s += (s.empty() ? "" : " ") + std::to_string(f);
  return s;
}

// --out: a folder the user named; created when missing. Only our own file names are written.
void prepareOutFolder(const std::string& out) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec))
    fail("--out '", out, "' exists and is not a folder");
  fs::create_directories(out, ec);
  if (ec)
    fail("--out '", out, "': cannot create the folder: ", ec.message());
}

// One row per scored view and network: the frames, the network's and the baseline's scores.
void writeViewsCsv(const std::string& path, const std::vector<std::string>& weights,
                   const std::vector<double>& margins,
                   const std::vector<training::EvalResult>& results) {
  std::ostringstream csv;
  csv << "network,weights,scene,sample,target_frame,source_frames,nearest_frame,psnr,ssim,"
         "nearest_psnr,nearest_ssim,reference_margin\n";
  csv.precision(6);
  for (size_t n = 0; n < results.size(); ++n) {
    const training::EvalResult& r = results[n];
    for (size_t v = 0; v < r.views.size(); ++v) {
      const training::EvalView& w = r.views[v];
      csv << n + 1 << ',' << csvQuote(weights[n]) << ',' << w.scene << ',' << w.sample << ','
          << w.targetFrame << ',' << frameList(w.sourceFrames) << ',' << w.nearestFrame << ','
          << std::fixed << r.model[v].psnr << ',' << r.model[v].ssim << ',' << r.baseline[v].psnr
          << ',' << r.baseline[v].ssim << std::defaultfloat << ',' << margins[n] << '\n';
    }
  }
  const std::string text = csv.str();
  io::writeFileAtomically(path, text.data(), text.size());
}

void runEval(EvalCliOptions o) {
  applyProtocol(o);
  if (o.factor < 0)
    fail("--factor ", o.factor, ": must be >= 0");
  if (o.repeats < 1)
    fail("--repeats ", o.repeats, ": must be >= 1");
  if (o.views < 1)
    fail("--views ", o.views, ": must be >= 1");
  if (o.novel < 1)
    fail("--novel ", o.novel, ": must be >= 1");
  if (o.window < 0)
    fail("--window ", o.window, ": must be >= 0");
  if (o.corrections < -1)
    fail("--corrections ", o.corrections, ": must be >= 0 (or -1 for all)");
  if (o.scenes < 1)
    fail("--scenes ", o.scenes, ": must be >= 1");
  generator::checkInputScale(o.inputScale, "--input-scale");
  for (double m : o.referenceMargins)
    checkReferenceMargin(m);
  if (o.referenceMargins.size() == 1)
    o.referenceMargins.resize(o.weights.size(), o.referenceMargins[0]);
  if (o.referenceMargins.size() != o.weights.size())
    fail("--reference-margin: ", o.referenceMargins.size(), " values for ", o.weights.size(),
         " networks (give one for all, or one per --weights entry)");
  if (o.seed < 0)
    fail("--seed ", o.seed, ": must be >= 0");
  if (o.dtype != "f32" && o.dtype != "f64")
    fail("--dtype '", o.dtype, "': expected f32 or f64");
  if (!o.device.empty()) {
    const auto [p, d] = ocl::Device::parseSelector(o.device, "--device");
    ocl::Device::select(p, d);
  }
  if (!o.out.empty())
    io::checkOutputLocation(o.out, "--out", /*createParents=*/true);
  training::DataOptions data;
  if (!o.size.empty())
    training::parseWidthHeight(o.size, "--size", data.width, data.height);
  data.imagesFactor = o.factor;
  auto source = training::openTrainingData(o.data, data);
  if (!o.out.empty())
    prepareOutFolder(o.out);
  // Every network is loaded (and its config checked) before the first one is scored.
  std::vector<std::unique_ptr<network::SimpliNetwork>> networks;
  for (const std::string& weights : o.weights) {
    if (isBaseline(weights)) {
      if (weights != kPlaneSweepBaseline)
        fail("--weights '", weights, "': unknown baseline (expected ", kPlaneSweepBaseline, ")");
      networks.push_back(nullptr);
      continue;
    }
    network::NetworkConfig config;
    if (!o.config.empty()) {
      config = training::resolveNetworkOrTrainingConfig(o.config);
    } else {
      const std::optional<network::NetworkConfig> fromWeights = network::configFromWeights(weights);
      if (!fromWeights)
        fail("--config is required: ", weights, " carries no \"network_config\" metadata");
      config = *fromWeights;
    }
    networks.push_back(std::make_unique<network::SimpliNetwork>(
        config, o.dtype == "f64" ? ocl::Dtype::F64 : ocl::Dtype::F32));
    networks.back()->parameters().load(weights);
  }
  training::EvalOptions e;
  e.repeats = o.repeats;
  e.views = o.views;
  e.novelViews = o.novel;
  e.window = o.window;
  e.scenes = o.scenes;
  e.seed = uint64_t(o.seed);
  e.corrections = o.corrections;
  e.inputScale = o.inputScale;
  const uint64_t scenes = source->sceneCount() > 0 ? source->sceneCount() : uint64_t(o.scenes);
  const int64_t perNetwork = int64_t(scenes) * o.repeats;
  ProgressBar bar("eval", perNetwork * int64_t(networks.size()));
  std::vector<training::EvalResult> results;
  for (size_t i = 0; i < networks.size(); ++i) {
    // The first sample of every scene as pictures: ground truth | render | error | nearest.
    auto picture = [&](const training::EvalViewImages& v) {
      if (o.out.empty() || v.view.sample != 0)
        return;
      const io::Image error = metrics::errorMap(v.render, v.truth);
      char name[96];
      std::snprintf(name, sizeof name, "net%zu_scene%llu_view%03d.png", i + 1,
                    static_cast<unsigned long long>(v.view.scene), v.view.targetFrame);
      io::writeImagePng(metrics::sideBySide({&v.truth, &v.render, &error, &v.nearest}),
                        (std::filesystem::path(o.out) / name).string());
    };
    e.referenceMargin = o.referenceMargins[i];
    auto progress = [&](int done, int) { bar.update(int64_t(i) * perNetwork + done); };
    if (networks[i]) {
      results.push_back(training::evaluate(*networks[i], *source, e, progress, picture));
    } else {
      const baselines::PlaneSweepStereoOptions stereo;
      results.push_back(training::evaluate(
          [&](const generator::GeneratorInput& in) {
            return baselines::planeSweepStereo(in, stereo);
          },
          o.dtype == "f64" ? ocl::Dtype::F64 : ocl::Dtype::F32, *source, e, progress, picture));
    }
  }
  bar.finish();
  if (!o.out.empty())
    writeViewsCsv((std::filesystem::path(o.out) / "views.csv").string(), o.weights,
                  o.referenceMargins, results);

  const training::EvalResult& first = results[0];
  const scene::Scene& scene0 = source->scene(0);
  std::printf("evaluated %zu novel views (%s%s; %dx%d; %d sources, %d repeats, seed %lld; "
              "central 90%% crop%s)\n",
              first.model.size(), source->describe().c_str(),
              scene0.imagesDir.empty() ? "" : (", images from " + scene0.imagesDir).c_str(),
              scene0.width(), scene0.height(), o.views, o.repeats, static_cast<long long>(o.seed),
              o.protocol == "rff" ? "; protocol rff" : "");
  if (o.inputScale != 1.0)
    std::printf("  sources resized to %dx%d before the network (--input-scale %g); the MLI is "
                "rendered into the novel views at %dx%d\n",
                generator::scaledSize(scene0.width(), o.inputScale),
                generator::scaledSize(scene0.height(), o.inputScale), o.inputScale, scene0.width(),
                scene0.height());
  const bool several = networks.size() > 1;
  auto label = [&](size_t i) { return several ? "model " + std::to_string(i + 1) : "model"; };
  for (size_t i = 0; i < networks.size(); ++i) {
    if (!networks[i]) {
      const baselines::PlaneSweepStereoOptions stereo;
      std::printf(
          "  %-22s %s (no network: one opaque surface from %d planes, RGB variance over "
          "%d px windows; reference margin %g; building it %.0f +- %.0f ms per sample)\n",
          label(i).c_str(), o.weights[i].c_str(), stereo.planes,
          baselines::windowPixels(stereo, generator::scaledSize(scene0.width(), o.inputScale)),
          o.referenceMargins[i], results[i].build.mean, results[i].build.std);
      continue;
    }
    const network::NetworkConfig& c = networks[i]->config();
    std::printf("  %-22s %s (config %s, %d %s; reference margin %g; building them %.0f +- %.0f "
                "ms per sample)\n",
                label(i).c_str(), o.weights[i].c_str(), c.name.c_str(), c.surfaces(),
                c.mpiOnly ? "planes" : "layers", o.referenceMargins[i], results[i].build.mean,
                results[i].build.std);
  }
  auto line = [](const std::string& name, const metrics::MeanStd& psnr,
                 const metrics::MeanStd& ssim) {
    std::printf("  %-22s PSNR %6.2f +- %.2f dB   SSIM %.4f +- %.4f\n", name.c_str(), psnr.mean,
                psnr.std, ssim.mean, ssim.std);
  };
  for (size_t i = 0; i < networks.size(); ++i)
    line(label(i), results[i].modelPsnr, results[i].modelSsim);
  line("nearest source view", first.baselinePsnr, first.baselineSsim);
  if (!o.out.empty())
    std::printf("  wrote %s/views.csv and one picture per view of the first sample "
                "(ground truth | render | error x4 | nearest source view)\n",
                o.out.c_str());
  // Paired differences: the same target views, so the per-view spread of the network's
  // quality cancels out.
  for (size_t i = 1; i < networks.size(); ++i) {
    std::vector<double> dp, ds;
    for (size_t v = 0; v < first.model.size(); ++v) {
      dp.push_back(results[i].model[v].psnr - first.model[v].psnr);
      ds.push_back(results[i].model[v].ssim - first.model[v].ssim);
    }
    const metrics::MeanStd p = metrics::meanAndStd(dp), q = metrics::meanAndStd(ds);
    std::printf("  %-22s PSNR %+6.2f +- %.2f dB   SSIM %+.4f +- %.4f (paired over %zu views)\n",
                (label(i) + " - model 1").c_str(), p.mean, p.std, q.mean, q.std, dp.size());
  }
}

} // namespace

void addEvalCommand(CLI::App& app) {
  auto opts = std::make_shared<EvalCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "eval", "PSNR / SSIM of novel views (paper protocol) against the nearest-source-view "
              "baseline");
  cmd->add_option("data", opts->data,
                  "A scene folder, a folder of scene folders, or synthetic[:SEED]")
      ->required();
  cmd->add_option("--weights", opts->weights,
                  "Network weights (safetensors); several (comma separated) are scored on the "
                  "same samples; baseline:plane-sweep is classical plane-sweep stereo (no "
                  "network), a yardstick for what a network has learnt")
      ->required()
      ->delimiter(',');
  cmd->add_option("--config", opts->config,
                  "Network or training config: a name (official-4l, tiny-prior, a recipe in "
                  "model/configs/training) or a JSON file (default: the weights' "
                  "\"network_config\" metadata, which `simpli train` writes)");
  cmd->add_option("--protocol", opts->protocol,
                  "rff: the paper's Real Forward-Facing protocol (512x384, 5 sources and 8 novel "
                  "views from all frames, 20 repeats); options given explicitly win")
      ->capture_default_str();
  cmd->add_option("--repeats", opts->repeats, "Samples per scene")->capture_default_str();
  cmd->add_option("--views", opts->views, "Source views per sample")->capture_default_str();
  cmd->add_option("--novel", opts->novel, "Novel (held-out) views per sample")
      ->capture_default_str();
  cmd->add_option("--window", opts->window, "Frame window the views come from (0 = all)")
      ->capture_default_str();
  cmd->add_option("--factor", opts->factor,
                  "Read the LLFF / NeRF image folder images_N (default: the images_* folder "
                  "closest to --size, else images/)")
      ->capture_default_str();
  cmd->add_option("--out", opts->out,
                  "Folder for views.csv and comparison pictures (created when missing; files "
                  "of those names are replaced, nothing else is touched)");
  cmd->add_option("--scenes", opts->scenes, "Scenes to draw from synthetic data")
      ->capture_default_str();
  cmd->add_option("--seed", opts->seed, "Sampling seed")->capture_default_str();
  cmd->add_option("--input-scale", opts->inputScale,
                  "Resize the sources by this factor (0, 2] before the network; the MLI is "
                  "rendered into the novel views at their size")
      ->capture_default_str();
  cmd->add_option("--reference-margin", opts->referenceMargins,
                  std::string(kReferenceMarginHelp) +
                      "; one value, or one per --weights entry (paired: --weights W,W "
                      "--reference-margin 0,0.06)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--corrections", opts->corrections, "MLI corrections to run (-1 = all)")
      ->capture_default_str();
  cmd->add_option("--size", opts->size, "Resize the images to WIDTHxHEIGHT (multiples of 16)");
  cmd->add_option("--dtype", opts->dtype, "f32 or f64")->capture_default_str();
  cmd->add_option("--device", opts->device, "OpenCL device p:d (see `simpli devices`)");
  cmd->callback([opts, cmd] {
    EvalCliOptions o = *opts;
    o.givenSize = cmd->count("--size") > 0;
    o.givenViews = cmd->count("--views") > 0;
    o.givenNovel = cmd->count("--novel") > 0;
    o.givenRepeats = cmd->count("--repeats") > 0;
    o.givenWindow = cmd->count("--window") > 0;
    runEval(std::move(o));
  });
}

} // namespace simpli::app

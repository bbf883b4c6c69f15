// `simpli bench trade SCENE --out DIR`: the trade between build time, render speed, size and
// quality, measured one axis at a time from a default point (not the cartesian product):
//
//   layers       every network given (--weights; their configs' layer counts), and `auto`
//                (generator/layer_choice.h: the fewest layers within 0.2 dB on the sources)
//   planes       P at inference: the default network with other plane counts its weights fit
//                (the depth decoder has ceil(P / L) outputs per layer, so P must keep that)
//   corrections  MLI correction steps 0 .. the config's
//   scale        the source images (and so the MLI) at a fraction of the scene's resolution
//   dtype        float32 / float64 network
//   tolerance    the adaptive display mesh's tolerance (pixels, mli/adaptive_mesh.h)
//
// Samples: the paper's protocol as `simpli eval` draws it (training::forEachEvalSample: V
// sources and N held-out novel views drawn from the scene's frames, R repeats), the same samples
// at every point. Per point and sample, the forward pass (after one untimed warm-up pass) gives
// the MLI (every layer; with `auto`, the chosen ones, the choice included in the build time);
// then
//   bytes      of its JPEG form, lossless form (mli/files.h) and GLB with the adaptive mesh
//              (mli/glb.h)
//   psnr/ssim  of the MLI (float, per-texel rasterizer) rendered into the held-out views at the
//              scene's resolution, central 90 % crop (what `simpli eval` scores)
//   mesh_*     the shipped form: the MLI read back from its JPEG form, as adaptive meshes at the
//              tolerance, rendered by the OpenCL adaptive renderer (raster/render_adaptive.h)
//              into the same views; render_fps is that renderer's (median over 3 frames per
//              view, after one warm-up frame) on the current OpenCL device
// Everything is the mean over the samples. Writes DIR/trade.csv (one row per point) and
// DIR/trade.png (mesh PSNR against build time, render fps and JPEG bytes; the Pareto front of
// each dashed). Measures, never asserts.
#include "simpli/error.h"
#include "simpli/model/generator/generator.h"
#include "simpli/model/generator/layer_choice.h"
#include "simpli/model/io/files.h"
#include "simpli/model/io/image.h"
#include "simpli/model/io/staged_folder.h"
#include "simpli/model/metrics/image_quality.h"
#include "simpli/model/metrics/line_plot.h"
#include "simpli/model/mli/files.h"
#include "simpli/model/mli/glb.h"
#include "simpli/model/network/loader.h"
#include "simpli/model/raster/render_adaptive.h"
#include "simpli/model/raster/render_mli.h"
#include "simpli/model/training/data.h"
#include "simpli/model/training/eval.h"
#include "simpli/model/training/trainer.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace simpli::app {

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

struct TradeOptions {
  std::string scene, out, size, device;
  std::vector<std::string> weights;
  bool quick = false;
  int views = 4, novel = 4, repeats = 2;
  int64_t seed = 0;
  std::vector<int> planes, corrections; ///< empty: every value the default network allows
  std::vector<double> scales{0.5, 0.75, 1.0};
  std::vector<std::string> dtypes{"f32", "f64"};
  std::vector<double> tolerances{0.1, 0.25, 1.0, 4.0};
  double tolerance = 1.0; ///< the default point's
  double layerMarginDb = 0.2;
};

/// One point of the sweep.
struct Point {
  std::string axis, value;
  std::size_t network = 0; ///< index into --weights
  int planes = 0, corrections = 0;
  double scale = 1.0;
  std::string dtype = "f32";
  double tolerance = 1.0;
  bool autoLayers = false;
};

/// What a point measured (means over the samples).
struct Row {
  Point point;
  std::string config;
  int layers = 0;
  double layersKept = 0;
  int width = 0, height = 0;
  double buildMs = 0, renderFps = 0, triangles = 0;
  double jpegBytes = 0, losslessBytes = 0, glbBytes = 0;
  double psnr = 0, ssim = 0, meshPsnr = 0, meshSsim = 0;
  bool paretoBuild = false, paretoFps = false, paretoBytes = false;
};

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// ---- networks and forward passes -------------------------------------------------------

struct NetworkSpec {
  std::string weights;
  network::NetworkConfig config;
};

class Networks {
public:
  explicit Networks(std::vector<NetworkSpec> specs) : specs_(std::move(specs)) {}
  const NetworkSpec& spec(std::size_t i) const { return specs_[i]; }
  std::size_t size() const { return specs_.size(); }
  /// Network i with P planes in `dtype`, loaded once. Throws simpli::Error when the weights do
  /// not fit that P.
  network::SimpliNetwork& get(std::size_t i, int planes, const std::string& dtype) {
    const auto key = std::make_tuple(i, planes, dtype);
    auto it = cache_.find(key);
    if (it != cache_.end())
      return *it->second;
    network::NetworkConfig config = specs_[i].config;
    config.numPlanes = planes;
    config.validate("config '" + config.name + "' with " + std::to_string(planes) + " planes");
    auto net = std::make_unique<network::SimpliNetwork>(config, dtype == "f64" ? ocl::Dtype::F64
                                                                               : ocl::Dtype::F32);
    net->parameters().load(specs_[i].weights);
    return *cache_.emplace(key, std::move(net)).first->second;
  }

private:
  std::vector<NetworkSpec> specs_;
  std::map<std::tuple<std::size_t, int, std::string>, std::unique_ptr<network::SimpliNetwork>>
      cache_;
};

/// The plane counts network `spec`'s weights fit: its own P and every other P in [L + 1, 3 P]
/// that keeps ceil(P / L) (the depth decoder's outputs) and makes a valid config.
std::vector<int> fittingPlaneCounts(const network::NetworkConfig& c) {
  std::vector<int> out;
  for (int p = c.numLayers + 1; p <= 3 * c.numPlanes; ++p) {
    network::NetworkConfig t = c;
    t.numPlanes = p;
    if (!c.mpiOnly && t.groupSize() != c.groupSize())
      continue;
    try {
      t.validate("planes");
    } catch (const Error&) {
      continue;
    }
    out.push_back(p);
  }
  return out;
}

/// One forward pass's result for one sample.
struct Built {
  mli::MLI mli;
  double forwardMs = 0;
};

std::vector<Built> buildAll(network::SimpliNetwork& net,
                            const std::vector<training::TrainingSample>& samples, const Point& p) {
  ocl::NoGradGuard noGrad;
  generator::Generator generator(net);
  generator::GeneratorOptions go;
  go.corrections = p.corrections;
  std::vector<Built> out;
  for (std::size_t s = 0; s < samples.size(); ++s) {
    const training::TrainingSample& sample = samples[s];
    const generator::GeneratorInput in =
        training::sampleInput(sample, p.scale, net.parameters().dtype());
    if (s == 0) { // untimed: PoCL compiles kernels and the pool fills on first use
      generator.forward(in, go);
      ocl::Device::current().finish();
    }
    const auto t0 = Clock::now();
    const generator::GeneratorOutput output = generator.forward(in, go);
    ocl::Device::current().finish();
    Built b;
    b.forwardMs = msSince(t0);
    b.mli = generator::toMLI(output, in.reference);
    out.push_back(std::move(b));
  }
  ocl::Device::current().pool().trim();
  return out;
}

// ---- measuring one representation --------------------------------------------------------

std::uintmax_t folderBytes(const std::filesystem::path& folder) {
  std::uintmax_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(folder))
    if (e.is_regular_file())
      n += e.file_size();
  return n;
}

struct Measured {
  double jpegBytes = 0, losslessBytes = 0, glbBytes = 0, triangles = 0;
  double psnr = 0, ssim = 0, meshPsnr = 0, meshSsim = 0, renderMs = 0;
};

Measured measure(const mli::MLI& mli, const training::TrainingSample& sample, double tolerance,
                 const std::filesystem::path& tmp) {
  namespace fs = std::filesystem;
  Measured m;
  fs::remove_all(tmp);
  fs::create_directories(tmp / "jpeg");
  fs::create_directories(tmp / "lossless");
  mli::writeMLIFiles((tmp / "jpeg").string(), mli, mli::MLIFormat::Jpeg);
  mli::writeMLIFiles((tmp / "lossless").string(), mli, mli::MLIFormat::Lossless);
  m.jpegBytes = static_cast<double>(folderBytes(tmp / "jpeg"));
  m.losslessBytes = static_cast<double>(folderBytes(tmp / "lossless"));
  mli::AdaptiveMeshOptions mesh;
  mesh.tolerancePixels = tolerance;
  mli::GlbOptions glb;
  glb.layerMesh = mli::adaptiveGlbMesh(mesh);
  m.glbBytes = static_cast<double>(mli::encodeGlb(mli, glb).size());

  const metrics::ImageQuality q =
      generator::meanQualityOfMLI(mli, sample.targetCameras, sample.targets);
  m.psnr = q.psnr;
  m.ssim = q.ssim;

  // The shipped form: JPEG read back, adaptive meshes, the OpenCL adaptive renderer.
  ocl::NoGradGuard noGrad;
  const raster::AdaptiveRenderer renderer(
      raster::buildAdaptiveMLI(mli::readMLI((tmp / "jpeg").string()), mesh));
  m.triangles = static_cast<double>(renderer.adaptive().numTriangles());
  (void)renderer.render(sample.targetCameras[0]).colour.toVectorF32(); // warm-up
  std::vector<double> ms;
  const double n = static_cast<double>(sample.targets.size());
  for (std::size_t t = 0; t < sample.targets.size(); ++t) {
    // Three timed frames per view (the median over all of them is reported): a loaded machine
    // makes single frames noisy.
    for (int k = 0; k < 2; ++k) {
      const auto t0 = Clock::now();
      (void)renderer.render(sample.targetCameras[t]).colour.toVectorF32();
      ms.push_back(msSince(t0));
    }
    const auto t0 = Clock::now();
    const raster::AdaptiveRender r = renderer.render(sample.targetCameras[t]);
    const metrics::MetricImage image = generator::metricImageFromColour(r.colour);
    ms.push_back(msSince(t0));
    const metrics::ImageQuality mq =
        metrics::evaluateImageQuality(image, metrics::metricImageFromImage(sample.targets[t]));
    m.meshPsnr += mq.psnr / n;
    m.meshSsim += mq.ssim / n;
  }
  std::sort(ms.begin(), ms.end());
  m.renderMs = ms[ms.size() / 2];
  fs::remove_all(tmp);
  return m;
}

// ---- Pareto fronts, CSV, plot --------------------------------------------------------------

/// Marks the rows no other row beats in both quality (mesh PSNR, higher) and `cost` (lower).
void markPareto(std::vector<Row>& rows, double (*cost)(const Row&), bool Row::*flag) {
  for (Row& r : rows) {
    r.*flag = true;
    for (const Row& o : rows)
      if (&o != &r && o.meshPsnr >= r.meshPsnr && cost(o) <= cost(r) &&
          (o.meshPsnr > r.meshPsnr || cost(o) < cost(r))) {
        r.*flag = false;
        break;
      }
  }
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos)
    return s;
  std::string q = "\"";
  for (char c : s)
    q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

const char* kCsvHeader = "axis,value,weights,config,layers,layers_kept,planes,corrections,scale,"
                         "width,height,dtype,tolerance,build_ms,render_fps,triangles,jpeg_bytes,"
                         "lossless_bytes,glb_bytes,psnr,ssim,mesh_psnr,mesh_ssim,pareto_build,"
                         "pareto_fps,pareto_bytes";

void writeCsv(const std::string& path, const std::vector<Row>& rows, const Networks& nets) {
  std::ostringstream csv;
  csv << kCsvHeader << '\n';
  csv.precision(6);
  for (const Row& r : rows) {
    const Point& p = r.point;
    csv << p.axis << ',' << csvField(p.value) << ',' << csvField(nets.spec(p.network).weights)
        << ',' << csvField(r.config) << ',' << r.layers << ',' << r.layersKept << ',' << p.planes
        << ',' << p.corrections << ',' << p.scale << ',' << r.width << ',' << r.height << ','
        << p.dtype << ',' << p.tolerance << ',' << r.buildMs << ',' << r.renderFps << ','
        << r.triangles << ',' << r.jpegBytes << ',' << r.losslessBytes << ',' << r.glbBytes << ','
        << r.psnr << ',' << r.ssim << ',' << r.meshPsnr << ',' << r.meshSsim << ','
        << int(r.paretoBuild) << ',' << int(r.paretoFps) << ',' << int(r.paretoBytes) << '\n';
  }
  const std::string text = csv.str();
  io::writeFileAtomically(path, text.data(), text.size());
}

void writePlot(const std::string& path, const std::vector<Row>& rows) {
  static const std::vector<std::pair<std::string, std::array<float, 3>>> kAxes = {
      {"default", {0.0f, 0.0f, 0.0f}},   {"layers", {0.85f, 0.1f, 0.1f}},
      {"planes", {0.1f, 0.45f, 0.85f}},  {"corrections", {0.1f, 0.6f, 0.2f}},
      {"scale", {0.8f, 0.5f, 0.0f}},     {"dtype", {0.55f, 0.2f, 0.7f}},
      {"tolerance", {0.0f, 0.6f, 0.65f}}};
  struct Panel {
    const char* title;
    const char* xLabel;
    double (*x)(const Row&);
    bool Row::*front;
    bool ascending; ///< the front drawn by increasing x
  };
  const Panel panels[] = {{"QUALITY AGAINST BUILD TIME", "BUILD MS (FORWARD PASS)",
                           [](const Row& r) { return r.buildMs; }, &Row::paretoBuild, true},
                          {"QUALITY AGAINST RENDER SPEED", "RENDER FPS (OPENCL ADAPTIVE)",
                           [](const Row& r) { return r.renderFps; }, &Row::paretoFps, true},
                          {"QUALITY AGAINST SIZE", "JPEG FORM KIB",
                           [](const Row& r) { return r.jpegBytes / 1024.0; }, &Row::paretoBytes,
                           true}};
  std::vector<metrics::PlotPanel> out;
  for (const Panel& panel : panels) {
    const bool legend = out.empty(); // the first panel has the legend, the others none
    metrics::PlotPanel p;
    p.title = panel.title;
    p.xLabel = panel.xLabel;
    p.yLabel = "MESH PSNR DB";
    for (const auto& [axis, colour] : kAxes) {
      metrics::PlotSeries s;
      s.name = legend ? axis : "";
      s.colour = colour;
      s.markers = true;
      for (const Row& r : rows)
        if (r.point.axis == axis) { // points only: a non-finite point between them is a gap
          s.x.insert(s.x.end(), {panel.x(r), NAN});
          s.y.insert(s.y.end(), {r.meshPsnr, NAN});
        }
      if (!s.x.empty())
        p.series.push_back(std::move(s));
    }
    metrics::PlotSeries front;
    front.name = "pareto front";
    front.colour = {0.4f, 0.4f, 0.4f};
    front.dashed = true;
    std::vector<const Row*> f;
    for (const Row& r : rows)
      if (r.*panel.front)
        f.push_back(&r);
    std::sort(f.begin(), f.end(),
              [&](const Row* a, const Row* b) { return panel.x(*a) < panel.x(*b); });
    for (const Row* r : f) {
      front.x.push_back(panel.x(*r));
      front.y.push_back(r->meshPsnr);
    }
    // Room: an undrawn series (two points with a gap, no markers) widens the axes, to the
    // right and up in the first panel so that the legend (top right) covers no point.
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (const Row& r : rows)
      if (std::isfinite(panel.x(r)) && std::isfinite(r.meshPsnr)) {
        x0 = std::min(x0, panel.x(r));
        x1 = std::max(x1, panel.x(r));
        y0 = std::min(y0, r.meshPsnr);
        y1 = std::max(y1, r.meshPsnr);
      }
    if (x0 <= x1) {
      const double dx = std::max(x1 - x0, 1e-9), dy = std::max(y1 - y0, 1e-9);
      metrics::PlotSeries room;
      room.colour = {1.0f, 1.0f, 1.0f};
      room.x = {x0 - 0.05 * dx, NAN, x1 + (legend ? 0.6 : 0.05) * dx};
      room.y = {y0 - 0.05 * dy, NAN, y1 + 0.05 * dy};
      p.series.push_back(std::move(room));
    }
    front.name = legend ? front.name : "";
    p.series.push_back(std::move(front));
    out.push_back(std::move(p));
  }
  io::writeImagePng(metrics::renderPlot(out, 720, 300), path);
}

// ---- the sweep -----------------------------------------------------------------------------

void validate(const TradeOptions& o) {
  if (o.views < 1)
    fail("--views ", o.views, ": must be >= 1");
  if (o.novel < 1)
    fail("--novel ", o.novel, ": must be >= 1");
  if (o.repeats < 1)
    fail("--repeats ", o.repeats, ": must be >= 1");
  if (o.seed < 0)
    fail("--seed ", o.seed, ": must be >= 0");
  if (o.scales.empty())
    fail("--scales: give at least one scale");
  for (double s : o.scales)
    if (!(s > 0 && s <= 2))
      fail("--scales ", s, ": each scale must be in (0, 2]");
  if (o.dtypes.empty())
    fail("--dtypes: give f32, f64 or both");
  for (const std::string& d : o.dtypes)
    if (d != "f32" && d != "f64")
      fail("--dtypes '", d, "': expected f32 or f64");
  for (double t : o.tolerances)
    if (!(t >= 0) || !std::isfinite(t))
      fail("--tolerances ", t, ": each tolerance must be finite and >= 0");
  if (!(o.tolerance >= 0) || !std::isfinite(o.tolerance))
    fail("--tolerance ", o.tolerance, ": must be finite and >= 0");
  for (int c : o.corrections)
    if (c < 0)
      fail("--corrections ", c, ": each count must be >= 0");
  for (int p : o.planes)
    if (p < 2)
      fail("--planes ", p, ": each plane count must be >= 2");
}

std::vector<NetworkSpec> networkSpecs(const TradeOptions& o) {
  std::vector<std::string> files = o.weights;
  if (files.empty())
    files.push_back(network::defaultWeightsPath());
  std::vector<NetworkSpec> specs;
  for (const std::string& w : files) {
    if (!std::filesystem::is_regular_file(w))
      fail("--weights '", w, "': no such file");
    const std::optional<network::NetworkConfig> config = network::configFromWeights(w);
    if (!config)
      fail("--weights '", w, "' carries no \"network_config\" / \"config\" metadata");
    specs.push_back({w, *config});
  }
  return specs;
}

std::vector<Point> sweepPoints(const TradeOptions& o, const Networks& nets) {
  const network::NetworkConfig& c = nets.spec(0).config;
  Point d;
  d.axis = "default";
  d.value = "default";
  d.planes = c.numPlanes;
  d.corrections = c.mliCorrections();
  d.scale = 1.0;
  d.dtype = "f32";
  d.tolerance = o.tolerance;
  std::vector<Point> points{d};
  auto add = [&](const std::string& axis, const std::string& value, auto change) {
    Point p = d;
    p.axis = axis;
    p.value = value;
    change(p);
    points.push_back(p);
  };
  for (std::size_t i = 1; i < nets.size(); ++i)
    add("layers", std::to_string(nets.spec(i).config.surfaces()), [&](Point& p) {
      p.network = i;
      p.planes = nets.spec(i).config.numPlanes;
      p.corrections = nets.spec(i).config.mliCorrections();
    });
  add("layers", "auto", [](Point& p) { p.autoLayers = true; });
  for (int planes : o.planes.empty() ? fittingPlaneCounts(c) : o.planes)
    if (planes != d.planes)
      add("planes", std::to_string(planes), [&](Point& p) { p.planes = planes; });
  std::vector<int> corrections = o.corrections;
  if (corrections.empty())
    for (int k = 0; k <= c.mliCorrections(); ++k)
      corrections.push_back(k);
  for (int k : corrections) {
    if (k > c.mliCorrections())
      fail("--corrections ", k, ": config '", c.name, "' has ", c.mliCorrections(), " corrections");
    if (k != d.corrections)
      add("corrections", std::to_string(k), [&](Point& p) { p.corrections = k; });
  }
  for (double s : o.scales)
    if (s != 1.0)
      add("scale", formatNumber(s), [&](Point& p) { p.scale = s; });
  for (const std::string& t : o.dtypes)
    if (t != "f32")
      add("dtype", t, [&](Point& p) { p.dtype = t; });
  for (double t : o.tolerances)
    if (t != d.tolerance)
      add("tolerance", formatNumber(t), [&](Point& p) { p.tolerance = t; });
  return points;
}

void runTrade(TradeOptions o) {
  if (o.quick) {
    o.repeats = 1;
    o.novel = std::min(o.novel, 2);
    o.scales = {0.5, 1.0};
    o.tolerances = {o.tolerance, 2.0};
  }
  validate(o);
  if (!o.device.empty()) {
    const auto [p, d] = ocl::Device::parseSelector(o.device, "--device");
    ocl::Device::select(p, d);
  }
  io::checkOutputLocation(o.out, "--out", /*createParents=*/true);
  {
    std::error_code ec;
    if (std::filesystem::exists(o.out, ec) && !std::filesystem::is_directory(o.out, ec))
      fail("--out '", o.out, "' exists and is not a folder");
  }
  Networks nets(networkSpecs(o));
  for (int planes : o.planes) { // a named error now rather than after the first points
    network::NetworkConfig t = nets.spec(0).config;
    t.numPlanes = planes;
    if (!t.mpiOnly && t.groupSize() != nets.spec(0).config.groupSize())
      fail("--planes ", planes, ": the weights of config '", t.name, "' fit ",
           nets.spec(0).config.groupSize(), " planes per layer group (ceil(P / ", t.numLayers,
           ")); P = ", planes, " needs ", t.groupSize());
    t.validate("--planes " + std::to_string(planes));
  }
  const std::vector<Point> points = sweepPoints(o, nets);

  training::DataOptions data;
  if (!o.size.empty())
    training::parseWidthHeight(o.size, "--size", data.width, data.height);
  auto source = training::openTrainingData(o.scene, data);
  training::EvalOptions e;
  e.views = o.views;
  e.novelViews = o.novel;
  e.repeats = o.repeats;
  e.seed = uint64_t(o.seed);
  std::vector<training::TrainingSample> samples;
  training::forEachEvalSample(
      *source, e, [&](const training::TrainingSample& s, uint64_t, int) { samples.push_back(s); });
  std::filesystem::create_directories(o.out);
  const std::filesystem::path tmp = std::filesystem::path(o.out) / ".trade-tmp";

  const scene::Scene& scene0 = source->scene(0);
  std::printf("bench trade: %s (%d x %d; %zu sample(s) of %d sources and %zu held-out views, "
              "seed %lld); %zu points, one axis at a time from the default (%s, %d planes, %d "
              "corrections, scale 1, f32, tolerance %g px); device %s\n",
              source->describe().c_str(), scene0.width(), scene0.height(), samples.size(), o.views,
              samples[0].targets.size(), static_cast<long long>(o.seed), points.size(),
              nets.spec(0).config.name.c_str(), nets.spec(0).config.numPlanes,
              nets.spec(0).config.mliCorrections(), o.tolerance,
              ocl::Device::current().info().deviceName.c_str());
  std::printf("%-12s %-6s %6s %6s %9s %9s %8s %9s %9s %9s %7s %6s %7s %6s\n", "axis", "value",
              "layers", "size", "build ms", "fps", "tris", "JPEG KiB", "lossl KiB", "GLB KiB",
              "PSNR", "SSIM", "meshPSNR", "mSSIM");
  std::fflush(stdout);

  std::map<std::tuple<std::size_t, int, int, double, std::string>, std::vector<Built>> builds;
  std::vector<Row> rows;
  for (const Point& p : points) {
    const auto key = std::make_tuple(p.network, p.planes, p.corrections, p.scale, p.dtype);
    auto it = builds.find(key);
    if (it == builds.end()) {
      try {
        it =
            builds.emplace(key, buildAll(nets.get(p.network, p.planes, p.dtype), samples, p)).first;
      } catch (const Error& error) {
        if (p.axis == "default")
          throw;
        // E.g. a plane count whose config is valid but whose weights do not load.
        std::printf("%-12s %-6s skipped: %s\n", p.axis.c_str(), p.value.c_str(), error.what());
        continue;
      }
    }
    Row r;
    r.point = p;
    const network::NetworkConfig& config = nets.spec(p.network).config;
    r.config = config.name;
    r.layers = config.surfaces();
    const double n = static_cast<double>(samples.size());
    for (std::size_t s = 0; s < samples.size(); ++s) {
      const Built& b = it->second[s];
      const mli::MLI* mli = &b.mli;
      double ms = b.forwardMs;
      std::optional<generator::LayerChoice> choice;
      if (p.autoLayers) {
        const auto t0 = Clock::now();
        generator::LayerChoiceOptions lc;
        lc.maxLossDb = o.layerMarginDb;
        choice =
            generator::chooseLayers(b.mli, samples[s].sourceCameras, samples[s].cleanSources, lc);
        ms += msSince(t0);
        mli = &choice->mli;
        std::string kept;
        for (int k : choice->kept)
          kept += (kept.empty() ? "" : ",") + std::to_string(k);
        std::printf("  layers auto, sample %zu: kept %zu of %d layers (%s; farthest = 0), "
                    "source-view PSNR %.2f dB against %.2f dB with all (margin %.2g dB)\n",
                    s, choice->kept.size(), b.mli.numLayers(), kept.c_str(), choice->chosenPsnr,
                    choice->fullPsnr, o.layerMarginDb);
      }
      const Measured m = measure(*mli, samples[s], p.tolerance, tmp);
      r.width = mli->width();
      r.height = mli->height();
      r.layersKept += mli->numLayers() / n;
      r.buildMs += ms / n;
      r.renderFps += 1000.0 / m.renderMs / n;
      r.triangles += m.triangles / n;
      r.jpegBytes += m.jpegBytes / n;
      r.losslessBytes += m.losslessBytes / n;
      r.glbBytes += m.glbBytes / n;
      r.psnr += m.psnr / n;
      r.ssim += m.ssim / n;
      r.meshPsnr += m.meshPsnr / n;
      r.meshSsim += m.meshSsim / n;
    }
    char size[32];
    std::snprintf(size, sizeof size, "%dx%d", r.width, r.height);
    std::printf("%-12s %-6s %6.3g %6s %9.1f %9.2f %8.0f %9.1f %9.1f %9.1f %7.2f %6.4f %7.2f "
                "%6.4f\n",
                p.axis.c_str(), p.value.c_str(), r.layersKept, size, r.buildMs, r.renderFps,
                r.triangles, r.jpegBytes / 1024, r.losslessBytes / 1024, r.glbBytes / 1024, r.psnr,
                r.ssim, r.meshPsnr, r.meshSsim);
    std::fflush(stdout);
    rows.push_back(std::move(r));
  }
  markPareto(
      rows, [](const Row& r) { return r.buildMs; }, &Row::paretoBuild);
  markPareto(
      rows, [](const Row& r) { return -r.renderFps; }, &Row::paretoFps);
  markPareto(
      rows, [](const Row& r) { return r.jpegBytes; }, &Row::paretoBytes);
  const std::string csv = (std::filesystem::path(o.out) / "trade.csv").string();
  const std::string png = (std::filesystem::path(o.out) / "trade.png").string();
  writeCsv(csv, rows, nets);
  writePlot(png, rows);
  std::printf("PSNR / SSIM: the float MLI, per-texel rasterizer; meshPSNR / mSSIM: the JPEG form "
              "read back as adaptive meshes (OpenCL adaptive renderer, whose fps is shown); all "
              "on the held-out views at the scene's size, central 90%% crop, mean over samples\n");
  std::printf("Pareto front (mesh PSNR against): build time");
  for (const Row& r : rows)
    if (r.paretoBuild)
      std::printf(" %s=%s", r.point.axis.c_str(), r.point.value.c_str());
  std::printf("; fps");
  for (const Row& r : rows)
    if (r.paretoFps)
      std::printf(" %s=%s", r.point.axis.c_str(), r.point.value.c_str());
  std::printf("; bytes");
  for (const Row& r : rows)
    if (r.paretoBytes)
      std::printf(" %s=%s", r.point.axis.c_str(), r.point.value.c_str());
  std::printf("\nwrote %s and %s\n", csv.c_str(), png.c_str());
}

} // namespace

void addBenchTradeCommand(CLI::App& bench) {
  auto o = std::make_shared<TradeOptions>();
  auto* cmd = bench.add_subcommand(
      "trade", "Sweep layers, planes, corrections, resolution, dtype and mesh tolerance one at a "
               "time: build time, render fps, bytes and held-out PSNR / SSIM (CSV and plot)");
  cmd->add_option("scene", o->scene, "A scene folder (or synthetic[:SEED])")->required();
  cmd->add_option("--out", o->out, "Folder for trade.csv and trade.png (created when missing)")
      ->required();
  cmd->add_option("--weights", o->weights,
                  "Networks for the layers axis, comma separated; the first is the default point's "
                  "(default: model/weights/default.safetensors)")
      ->delimiter(',');
  cmd->add_flag("--quick", o->quick,
                "1 sample, 2 held-out views, scales 0.5 and 1, tolerances --tolerance and 2 (a "
                "few minutes on the bundled scenes)");
  cmd->add_option("--views", o->views, "Source views per sample")->capture_default_str();
  cmd->add_option("--novel", o->novel, "Held-out views per sample")->capture_default_str();
  cmd->add_option("--repeats", o->repeats, "Samples")->capture_default_str();
  cmd->add_option("--seed", o->seed, "Sampling seed")->capture_default_str();
  cmd->add_option("--size", o->size, "Resize the scene's images to WIDTHxHEIGHT (multiples of 16)");
  cmd->add_option("--planes", o->planes,
                  "Plane counts (default: every count the default network's weights fit)")
      ->delimiter(',');
  cmd->add_option("--corrections", o->corrections, "Correction counts (default: 0 .. the config's)")
      ->delimiter(',');
  cmd->add_option("--scales", o->scales, "Input resolution scales in (0, 2]")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--dtypes", o->dtypes, "f32, f64")->delimiter(',')->capture_default_str();
  cmd->add_option("--tolerances", o->tolerances, "Adaptive mesh tolerances (pixels)")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--tolerance", o->tolerance, "The default point's mesh tolerance (pixels)")
      ->capture_default_str();
  cmd->add_option("--device", o->device, "OpenCL device p:d (see `simpli devices`)");
  cmd->callback([o] { runTrade(*o); });
}

} // namespace simpli::app

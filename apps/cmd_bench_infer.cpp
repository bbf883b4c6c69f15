// `simpli bench infer`: times the SIMPLI generator's forward pass (building one MLI) per stage,
// with random weights on random images seen by a forward-facing rig of V cameras, and reports
// the peak device memory the pass allocated (buffer-pool live bytes above those held before
// the pass; buffers parked in the pool for reuse are reported separately and released after
// every view count). One untimed warm-up pass per view count compiles the kernels and fills the
// buffer pool; the reported times are medians over --repeat passes. Measures, never asserts.
// Beside its own time it prints the ratio to the reference implementation (PyTorch on the CPU):
// --reference DIR times the user's checkout of the reference sources in the same run
// (scripts/time_reference.py: same size and view count, random weights, its CUDA-only renderer
// stubbed), --reference-ms takes times measured earlier; without either it says it has none. The
// GEMM backend and the OpenBLAS kernel are printed too (`bench infer` re-executes itself without
// OPENBLAS_CORETYPE / OPENBLAS_L2_SIZE like `bench ops`, see cmd_bench.cpp).
#include "simpli/model/network/loader.h"

#include "simpli/error.h"
#include "simpli/model/generator/generator.h"
#include "simpli/model/io/image_size.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/gemm_backend.h"
#include <CLI/CLI.hpp>

#include <sys/resource.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace simpli::app {

namespace {

struct BenchInferOptions {
  std::string config = "official-4l";
  std::string size = "512x384";
  std::vector<int> views{4, 8};
  int repeat = 1;
  int corrections = -1;
  std::string device;
  std::vector<double> referenceMs; // one per view count, or empty
  std::string referenceDir;        // a checkout of the reference sources, or empty
};

std::string shellQuoted(const std::string& s) {
  std::string q = "'";
  for (char c : s)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// Times the reference generator with scripts/time_reference.py (PyTorch on the CPU, with the
/// OpenBLAS variables already removed from this process's environment) and returns its median
/// forward time in ms; fails with the script's reason when it cannot.
double timeReference(const std::string& dir, const std::string& config, int W, int H, int V,
                     int repeat) {
  const std::string script = std::string(SIMPLI_SOURCE_DIR) + "/scripts/time_reference.py";
  const std::string command = "/usr/bin/python3 " + shellQuoted(script) + " --reference " +
                              shellQuoted(dir) + " --size " + std::to_string(W) + "x" +
                              std::to_string(H) + " --views " + std::to_string(V) + " --repeat " +
                              std::to_string(repeat) + " --config " + shellQuoted(config) + " 2>&1";
  std::printf("  timing the reference (%s) ...\n", dir.c_str());
  std::fflush(stdout);
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe)
    fail("--reference ", dir, ": cannot run ", script);
  std::string output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe))
    output += buffer;
  const int status = pclose(pipe);
  // The script's last line: "reference_ms <median> ..." when it ran, else its reason
  // ("reference not timed: ...") or the exception that stopped it.
  output.erase(output.find_last_not_of('\n') + 1); // npos + 1 = 0: no output at all
  const std::string last = output.substr(output.rfind('\n') + 1);
  const double ms =
      last.rfind("reference_ms ", 0) == 0 ? std::strtod(last.c_str() + 13, nullptr) : -1;
  if (status != 0 || !(ms > 0))
    fail("--reference ", dir, ": the reference was not timed (", script, ": ",
         last.empty() ? std::string("no output") : last, ")");
  return ms;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// V cameras on a circle of radius 0.05 around the origin, slightly rotated, looking along +z.
generator::GeneratorInput rigInput(int V, int H, int W, uint64_t seed) {
  generator::GeneratorInput input;
  for (int v = 0; v < V; ++v) {
    const double phase = 2.0 * M_PI * v / V;
    scene::Camera c;
    c.R = (Eigen::AngleAxisd(0.01 * std::sin(phase), Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(0.01 * std::cos(phase), Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
    c.t = Eigen::Vector3d(0.05 * std::cos(phase), 0.05 * std::sin(phase), 0.0);
    c.fx = 1.0;
    c.fy = double(W) / H;
    c.width = W;
    c.height = H;
    input.sources.push_back(c);
  }
  input.reference = scene::referenceCamera(input.sources);
  input.images = ocl::Tensor::uniform({V, 3, H, W}, -1.0, 1.0, seed);
  return input;
}

void runBenchInfer(const BenchInferOptions& o) {
  if (!o.device.empty()) {
    const auto [platform, device] = ocl::Device::parseSelector(o.device, "--device");
    ocl::Device::select(platform, device);
  }
  // The generator's own requirement (multiples of 8), checked before any work.
  const io::ImageSize size = io::parseImageSize(o.size, "--size", {8, 8192, 8});
  const int W = size.width, H = size.height;
  if (o.repeat < 1)
    fail("--repeat must be at least 1, got ", o.repeat);
  if (o.views.empty())
    fail("--views: at least one view count is needed");
  for (int v : o.views)
    if (v < 1 || v > 64)
      fail("--views ", v, ": view counts must be in 1..64");
  // The reference's config of the same network (its own files, relative to the checkout).
  const std::string referenceConfig =
      o.config == "official-4l"   ? "pretrained/model4_layers/tblock4.yaml"
      : o.config == "official-8l" ? "pretrained/model8_layers/tblock8.yaml"
                                  : "";
  if (!o.referenceDir.empty() && referenceConfig.empty())
    fail("--reference: the reference has only the official networks; --config ", o.config,
         " has no counterpart (use official-4l or official-8l)");
  if (!o.referenceDir.empty() && !o.referenceMs.empty())
    fail("--reference and --reference-ms: give one of them (a checkout to time, or times)");
  if (!o.referenceDir.empty() &&
      !std::filesystem::is_regular_file(std::filesystem::path(o.referenceDir) / "lib" / "networks" /
                                        "generators" / "gen_simpli.py"))
    fail("--reference ", o.referenceDir,
         ": not a checkout of the reference sources (SamsungLabs/MLI: no "
         "lib/networks/generators/gen_simpli.py)");
  if (!o.referenceMs.empty() && o.referenceMs.size() != o.views.size())
    fail("--reference-ms: ", o.referenceMs.size(), " time(s) for ", o.views.size(),
         " view count(s); give one per view count");

  network::SimpliNetwork network(network::resolveNetworkConfig(o.config), ocl::Dtype::F32, 0);
  const generator::Generator generator(network);
  ocl::BufferPool& pool = ocl::Device::current().pool();
  std::printf("bench infer: config %s (%lld parameters, random weights), %d x %d (H x W), "
              "device %s, median of %d\n",
              network.config().name.c_str(), static_cast<long long>(network.parameters().count()),
              H, W, ocl::Device::current().info().deviceName.c_str(), o.repeat);
  std::printf("gemm backend: %s\n", ocl::gemmBackendSummary().c_str());
  ocl::NoGradGuard noGrad;
  for (std::size_t vi = 0; vi < o.views.size(); ++vi) {
    const int V = o.views[vi];
    // The reference first: a checkout that cannot run fails before the long pass.
    const double referenceMs =
        !o.referenceDir.empty() ? timeReference(o.referenceDir, referenceConfig, W, H, V, o.repeat)
        : o.referenceMs.empty() ? 0.0
                                : o.referenceMs[vi];
    const generator::GeneratorInput input = rigInput(V, H, W, 1234 + V);
    generator::GeneratorOptions options;
    options.corrections = o.corrections;
    options.timeStages = true;
    generator.forward(input, options); // warm-up: kernel compilation, buffer pool
    std::vector<std::string> names;
    std::map<std::string, std::vector<double>> times;
    std::vector<double> totals;
    std::size_t peak = 0;
    for (int r = 0; r < o.repeat; ++r) {
      pool.resetPeak();
      const std::size_t before = pool.stats().liveBytes;
      const auto t0 = std::chrono::steady_clock::now();
      const generator::GeneratorOutput out = generator.forward(input, options);
      totals.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      peak = std::max(peak, pool.stats().peakBytes - std::min(before, pool.stats().peakBytes));
      for (const auto& [name, ms] : out.stageMs) {
        if (r == 0)
          names.push_back(name);
        times[name].push_back(ms);
      }
    }
    std::printf("V = %d: forward %.1f ms, peak device memory %.1f MiB (buffer pool: %.1f MiB "
                "parked for reuse)\n",
                V, median(totals), peak / 1048576.0, pool.stats().cachedBytes / 1048576.0);
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    std::printf("  peak process memory (max RSS so far) %.1f MiB\n", usage.ru_maxrss / 1024.0);
    if (referenceMs <= 0)
      std::printf("  reference (PyTorch CPU): not measured here (pass --reference DIR, a "
                  "checkout of the reference sources, or --reference-ms for %dx%d, V = %d)\n",
                  W, H, V);
    else
      std::printf("  reference (PyTorch CPU%s) %.1f ms: simpli / reference = %.2f\n",
                  o.referenceDir.empty() ? ", given" : ", this run", referenceMs,
                  median(totals) / referenceMs);
    for (const std::string& name : names)
      std::printf("  %-18s %10.1f ms\n", name.c_str(), median(times[name]));
    pool.trim(); // hand the parked buffers back before the next (larger) view count
  }
}

} // namespace

void addBenchInferCommand(CLI::App& bench) {
  auto o = std::make_shared<BenchInferOptions>();
  auto* cmd = bench.add_subcommand(
      "infer", "Time the generator's forward pass per stage and its peak device memory");
  cmd->add_option("--config", o->config,
                  "Network config (official-4l, official-8l, a name in model/configs or a .json)");
  cmd->add_option("--size", o->size,
                  "Image size WIDTHxHEIGHT (default 512x384, the reference's 384 x 512)");
  cmd->add_option("--views", o->views, "Source view counts to run (comma separated)")
      ->delimiter(',');
  cmd->add_option("--repeat", o->repeat, "Timed passes per view count (median reported)");
  cmd->add_option("--corrections", o->corrections, "MLI corrections to run (default all)");
  cmd->add_option("--device", o->device, "OpenCL device as platform:device (see simpli devices)");
  cmd->add_option("--reference", o->referenceDir,
                  "A checkout of the reference sources (SamsungLabs/MLI): time its generator "
                  "with PyTorch on the CPU in this run (scripts/time_reference.py)");
  cmd->add_option("--reference-ms", o->referenceMs,
                  "The reference's forward time per view count (ms, comma separated), for the "
                  "ratio")
      ->delimiter(',');
  cmd->callback([o] { runBenchInfer(*o); });
}

} // namespace simpli::app

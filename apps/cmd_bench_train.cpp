// `simpli bench train`: the time of one training step (issue 10: the step is what a CPU training
// budget buys). Runs --warmup untimed steps (PoCL compiles kernels on first use), then --steps
// timed steps of a real run (the config's data, sampler, losses and optimizer) in a temporary
// run folder, printing ms/step (mean +- std, min), and then one more step with the profiler on
// (every device call finished and timed; slower, so not part of the mean) as a breakdown by
// kernel and by engine area. Measures, never asserts; the load average is printed beside the
// times because the machine may be shared. Runs with OpenBLAS's native kernel (cmd_bench.cpp).
#include <CLI/CLI.hpp>

#include "simpli/error.h"
#include "simpli/model/training/trainer.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/gemm_backend.h"
#include "simpli/ocl/profiler.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace simpli::app {

namespace {

struct BenchTrainOptions {
  std::string config = "tiny-world";
  std::string data = "synthetic:0";
  std::string size;
  int steps = 5, warmup = 1;
  std::string device;
  std::string baseline; ///< "composed": also time the composed view aggregation
  int kernels = 20;     ///< rows of the per-kernel table
};

std::string loadAverage() {
  std::ifstream f("/proc/loadavg");
  std::string one;
  return f >> one ? one : std::string("?");
}

// A fresh folder under the system temporary folder, removed with its contents at the end.
class TempRun {
public:
  TempRun() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("simpli-bench-train-" + std::to_string(rd()) + std::to_string(rd()));
  }
  ~TempRun() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string str() const { return path_.string(); }

private:
  std::filesystem::path path_;
};

// "attention.attention_backward_key" -> "attention"; "clblast.Gemm NT ..." -> "gemm (CLBlast)",
// "host.Gemm NT ..." -> "gemm (host BLAS)".
std::string area(const std::string& kernel) {
  const std::string program = kernel.substr(0, kernel.find('.'));
  if (program == "clblast")
    return "gemm (CLBlast)";
  if (program == "host")
    return "gemm (host BLAS)";
  if (program.rfind("gemm", 0) == 0)
    return "gemm (own kernels)";
  return program;
}

struct Summary {
  double mean = 0, std = 0, min = 0;
};

Summary summarise(const std::vector<double>& ms) {
  Summary r;
  for (double v : ms)
    r.mean += v / ms.size();
  for (double v : ms)
    r.std += (v - r.mean) * (v - r.mean) / std::max<std::size_t>(1, ms.size() - 1);
  r.std = std::sqrt(r.std);
  r.min = *std::min_element(ms.begin(), ms.end());
  return r;
}

void runBenchTrain(const BenchTrainOptions& o) {
  if (o.steps < 1)
    fail("--steps ", o.steps, ": must be >= 1");
  if (o.warmup < 0)
    fail("--warmup ", o.warmup, ": must be >= 0");
  if (o.kernels < 1)
    fail("--kernels ", o.kernels, ": must be >= 1");
  if (!o.baseline.empty() && o.baseline != "composed")
    fail("--baseline '", o.baseline,
         "': the one baseline is 'composed' (the view aggregation as "
         "composed ops instead of the fused kernels)");
  if (!o.device.empty()) {
    const auto [p, d] = ocl::Device::parseSelector(o.device, "--device");
    ocl::Device::select(p, d);
  }
  const training::TrainingConfig config = training::resolveTrainingConfig(o.config);
  TempRun run;
  training::TrainerOptions t;
  t.data = {{o.data}};
  t.runDir = run.str();
  t.checkpointEvery = 1 << 30; // no checkpoints: only steps are timed
  t.dataOptions.configSource = "training config '" + o.config + "'";
  if (!o.size.empty())
    training::parseWidthHeight(o.size, "--size", t.dataOptions.width, t.dataOptions.height);
  training::Trainer trainer(&config, t);
  // The baseline trains the same network on the same samples (same seed) with the view
  // aggregation as composed ops; its steps alternate with the measured ones, so both see the
  // same machine load.
  std::unique_ptr<TempRun> baselineRun;
  std::unique_ptr<training::Trainer> baseline;
  if (!o.baseline.empty()) {
    baselineRun = std::make_unique<TempRun>();
    training::TrainerOptions b = t;
    b.runDir = baselineRun->str();
    b.fusedAggregation = false;
    baseline = std::make_unique<training::Trainer>(&config, b);
  }
  const ocl::DeviceInfo& dev = ocl::Device::current().info();
  std::printf("simpli bench train: config %s (%s), data %s, device %s; load average %s\n",
              o.config.c_str(), config.network.name.c_str(), o.data.c_str(), dev.deviceName.c_str(),
              loadAverage().c_str());
  // Host GEMMs are part of the step: say which OpenBLAS kernel ran them (the process drops
  // OPENBLAS_CORETYPE / OPENBLAS_L2_SIZE first, like bench ops).
  std::printf("gemm backend: %s\n", ocl::gemmBackendSummary().c_str());
  for (int i = 0; i < o.warmup; ++i) {
    std::printf("warm-up step %d: %.0f ms", i + 1, trainer.trainStep().ms);
    if (baseline)
      std::printf(", baseline %.0f ms", baseline->trainStep().ms);
    std::printf("\n");
  }
  // Device allocations during the timed steps: each new buffer costs page faults (the pages
  // are zeroed by the kernel on first touch), which the pool exists to avoid.
  const ocl::PoolStats poolBefore = ocl::Device::current().pool().stats();
  std::vector<double> ms, baseMs;
  for (int i = 0; i < o.steps; ++i) {
    ms.push_back(trainer.trainStep().ms);
    std::printf("step %d: %.0f ms", i + 1, ms.back());
    if (baseline) {
      baseMs.push_back(baseline->trainStep().ms);
      std::printf(", baseline (%s aggregation) %.0f ms, ratio %.2f", o.baseline.c_str(),
                  baseMs.back(), ms.back() / baseMs.back());
    }
    std::printf("\n");
  }
  const Summary step = summarise(ms);
  std::printf("train step: %.0f +- %.0f ms (min %.0f) over %zu steps; load average %s\n", step.mean,
              step.std, step.min, ms.size(), loadAverage().c_str());
  const ocl::PoolStats& pool = ocl::Device::current().pool().stats();
  std::printf("buffer pool over the timed steps: %zu new buffers, %zu reuses, %zu evictions; "
              "%.0f MiB parked\n",
              pool.allocations - poolBefore.allocations, pool.reuses - poolBefore.reuses,
              pool.evictions - poolBefore.evictions, pool.cachedBytes / 1048576.0);
  if (baseline) {
    const Summary base = summarise(baseMs);
    std::printf("baseline (%s aggregation): %.0f +- %.0f ms (min %.0f); ratio of the means %.2f "
                "(%.2fx faster)\n",
                o.baseline.c_str(), base.mean, base.std, base.min, step.mean / base.mean,
                base.mean / step.mean);
    baseline.reset();
  }

  // The breakdown: one profiled step (every device call finished and timed).
  ocl::Profiler::reset();
  ocl::Profiler::setEnabled(true);
  const double profiledMs = trainer.trainStep().ms;
  ocl::Profiler::setEnabled(false);
  const std::vector<ocl::ProfileEntry> entries = ocl::Profiler::entries();
  double device = 0;
  std::map<std::string, double> areas;
  for (const ocl::ProfileEntry& e : entries) {
    device += e.ms;
    areas[area(e.name)] += e.ms;
  }
  std::vector<std::pair<std::string, double>> byArea(areas.begin(), areas.end());
  std::sort(byArea.begin(), byArea.end(), [](auto& a, auto& b) { return a.second > b.second; });
  std::printf("profiled step: %.0f ms, of which device calls %.0f ms (%.0f %%), host %.0f ms\n",
              profiledMs, device, 100 * device / profiledMs, profiledMs - device);
  std::printf("%-28s %10s %7s\n", "area", "ms", "%");
  for (const auto& [name, v] : byArea)
    std::printf("%-28s %10.1f %6.1f\n", name.c_str(), v, 100 * v / device);
  std::printf("%s", ocl::Profiler::report(o.kernels).c_str());
}

} // namespace

void addBenchTrainCommand(CLI::App& bench) {
  auto o = std::make_shared<BenchTrainOptions>();
  auto* cmd = bench.add_subcommand(
      "train", "Time one training step (ms/step) and break a profiled step down by kernel");
  cmd->add_option("--config", o->config,
                  "Training config (a name in model/configs/training or a .json)")
      ->capture_default_str();
  cmd->add_option("--data", o->data, "Training data (as simpli train)")->capture_default_str();
  cmd->add_option("--size", o->size, "Resize the images to WIDTHxHEIGHT (default: the config's)");
  cmd->add_option("--steps", o->steps, "Timed steps")->capture_default_str();
  cmd->add_option("--warmup", o->warmup, "Untimed steps first (kernel compiles)")
      ->capture_default_str();
  cmd->add_option("--device", o->device, "OpenCL device as platform:device (see simpli devices)");
  cmd->add_option("--baseline", o->baseline,
                  "Also time, step by step on the same samples, a baseline: 'composed' = the "
                  "view aggregation as composed ops (the step before the fused kernels)");
  cmd->add_option("--kernels", o->kernels, "Rows of the profiled step's per-kernel table")
      ->capture_default_str();
  cmd->callback([o] { runBenchTrain(*o); });
}

} // namespace simpli::app

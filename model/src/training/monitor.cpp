// The training run's progress pictures and validation (training/monitor.h).
#include "simpli/model/training/monitor.h"

#include "simpli/error.h"
#include "simpli/model/io/safetensors.h"
#include "simpli/model/metrics/comparison_grid.h"
#include "simpli/model/metrics/line_plot.h"
#include "simpli/model/training/checkpoint.h"
#include "simpli/model/training/eval.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <tuple>

namespace simpli::training {
namespace {
namespace fs = std::filesystem;

const std::vector<std::string>& valColumns() {
  static const std::vector<std::string> c{"step", "psnr", "ssim", "nearest_psnr", "nearest_ssim"};
  return c;
}

// Trailing mean over `window` values (fewer at the start), skipping non-finite ones.
std::vector<double> movingAverage(const std::vector<double>& v, size_t window) {
  std::vector<double> out(v.size(), std::nan(""));
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    if (std::isfinite(v[i])) {
      sum += v[i];
      ++n;
    }
    if (i >= window && std::isfinite(v[i - window])) {
      sum -= v[i - window];
      --n;
    }
    if (n > 0)
      out[i] = sum / double(n);
  }
  return out;
}

// The score of the weights in best.safetensors: the val.csv row of their step (none when the
// file is missing, unreadable or of a step the kept rows do not have, e.g. after a resume from
// an earlier checkpoint; the next validation then becomes the best).
std::unique_ptr<ValidationScore> keptBest(const std::string& runDir,
                                          const std::vector<std::vector<double>>& rows) {
  const std::string path = TrainingMonitor::bestWeightsPath(runDir);
  if (!fs::exists(path))
    return nullptr;
  int64_t step = -1;
  try {
    const io::SafeTensorsReader reader(path);
    const std::map<std::string, std::string> meta = reader.metadata();
    const auto it = meta.find("step");
    if (it != meta.end())
      step = std::stoll(it->second);
  } catch (const std::exception&) {
    return nullptr; // a damaged file: replaced by the next validation
  }
  for (const std::vector<double>& r : rows)
    if (r.size() >= 5 && static_cast<int64_t>(r[0]) == step) {
      auto b = std::make_unique<ValidationScore>();
      *b = {step, r[1], r[2], r[3], r[4], true};
      return b;
    }
  return nullptr;
}

int columnIndex(const std::vector<std::string>& header, const std::string& name) {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name)
      return int(i);
  return -1;
}
} // namespace

TrainingMonitor::TrainingMonitor(std::string runDir, ValidationOptions options)
    : runDir_(std::move(runDir)), options_(std::move(options)) {
  if (options_.scene.empty())
    return;
  if (options_.every < 1)
    fail("validation every ", options_.every, " steps: must be >= 1");
  DataOptions d;
  d.width = options_.width;
  d.height = options_.height;
  data_ = openTrainingData(options_.scene, d);
  const scene::Scene& s = data_->scene(0);
  if (int(s.size()) < options_.views + 1)
    fail("validation scene ", options_.scene, " has ", s.size(), " views; ", options_.views,
         " sources and a novel view need at least ", options_.views + 1);
}

void TrainingMonitor::begin(int64_t resumeStep, double referenceMargin) {
  referenceMargin_ = referenceMargin;
  lastValidated_ = -1;
  if (!data_)
    return;
  const std::string path = (fs::path(runDir_) / "val.csv").string();
  log_ = std::make_unique<TrainLog>(path, valColumns(), resumeStep);
  // The schedule counts from the last validation kept (a run stopped between two validations
  // resumes on the same schedule); with none, the first checkpoint validates.
  best_.reset();
  if (resumeStep < 0)
    return;
  const std::vector<std::vector<double>> rows = TrainLog::read(path);
  for (const std::vector<double>& row : rows)
    if (!row.empty())
      lastValidated_ = static_cast<int64_t>(row[0]);
  best_ = keptBest(runDir_, rows);
}

std::string TrainingMonitor::bestWeightsPath(const std::string& runDir) {
  return (fs::path(runDir) / "best.safetensors").string();
}

TrainingMonitor::~TrainingMonitor() = default;

std::unique_ptr<ValidationScore> TrainingMonitor::update(network::SimpliNetwork& network,
                                                         int64_t step, bool force) {
  std::unique_ptr<ValidationScore> score;
  if (log_ && (force || lastValidated_ < 0 || step - lastValidated_ >= options_.every)) {
    EvalOptions e;
    e.repeats = options_.repeats;
    e.views = options_.views;
    e.novelViews = options_.novelViews;
    e.seed = options_.seed;
    e.referenceMargin = referenceMargin_;
    e.warmUp = false; // build time is not measured here
    io::Image grid;
    const EvalResult r = evaluate(network, *data_, e, {}, [&](const EvalViewImages& v) {
      if (!grid.empty())
        return;
      const io::Image error = metrics::errorMap(v.render, v.truth);
      grid = metrics::sideBySide({&v.truth, &v.render, &error, &v.nearest});
    });
    score = std::make_unique<ValidationScore>();
    *score = {step, r.modelPsnr.mean, r.modelSsim.mean, r.baselinePsnr.mean, r.baselineSsim.mean};
    log_->append({double(step), score->psnr, score->ssim, score->nearestPsnr, score->nearestSsim});
    const fs::path dir = fs::path(runDir_) / "validation";
    fs::create_directories(dir);
    char name[32];
    std::snprintf(name, sizeof name, "step_%08lld.png", static_cast<long long>(step));
    io::writeImagePng(grid, (dir / name).string());
    lastValidated_ = step;
    if (!best_ || score->psnr > best_->psnr) {
      network.parameters().save(bestWeightsPath(runDir_),
                                weightsMetadata(step, network::toJson(network.config())));
      score->best = true;
      best_ = std::make_unique<ValidationScore>(*score);
    }
  }
  drawProgress(runDir_);
  return score;
}

void TrainingMonitor::drawProgress(const std::string& runDir) {
  const fs::path run(runDir);
  std::vector<metrics::PlotPanel> panels;
  std::vector<std::string> header;
  const std::vector<std::vector<double>> rows = TrainLog::read((run / "log.csv").string(), &header);
  const int totalCol = columnIndex(header, "total");
  metrics::PlotPanel loss;
  loss.title = "training loss";
  loss.xLabel = "step";
  loss.yLabel = "loss";
  loss.logY = true;
  if (totalCol >= 0) {
    metrics::PlotSeries raw{"per step", {}, {}, {0.72f, 0.78f, 0.9f}};
    for (const std::vector<double>& r : rows) {
      raw.x.push_back(r[0]);
      raw.y.push_back(r[size_t(totalCol)]);
    }
    const size_t window = std::max<size_t>(5, rows.size() / 20);
    metrics::PlotSeries mean{"mean of " + std::to_string(window),
                             raw.x,
                             movingAverage(raw.y, window),
                             {0.05f, 0.2f, 0.6f}};
    loss.series = {raw, mean};
  }
  panels.push_back(loss);
  const fs::path val = run / "val.csv";
  if (fs::exists(val)) {
    const std::vector<std::vector<double>> v = TrainLog::read(val.string());
    // PSNR and SSIM can move apart (sharper layers with misplaced edges: SSIM up, PSNR down),
    // so both are shown. val.csv columns: step, psnr, ssim, nearest_psnr, nearest_ssim.
    for (const auto& [title, label, column] :
         {std::tuple{"validation psnr (fixed views)", "psnr db", 1},
          std::tuple{"validation ssim (fixed views)", "ssim", 2}}) {
      metrics::PlotPanel p;
      p.title = title;
      p.xLabel = "step";
      p.yLabel = label;
      metrics::PlotSeries model{"network", {}, {}, {0.8f, 0.15f, 0.1f}, true};
      metrics::PlotSeries nearest{"nearest view", {}, {}, {0.3f, 0.3f, 0.3f}, false, true};
      for (const std::vector<double>& r : v) {
        model.x.push_back(r[0]);
        model.y.push_back(r[size_t(column)]);
        nearest.x.push_back(r[0]);
        nearest.y.push_back(r[size_t(column) + 2]);
      }
      p.series = {model, nearest};
      panels.push_back(p);
    }
  }
  io::writeImagePng(metrics::renderPlot(panels), (run / "progress.png").string());
}

} // namespace simpli::training

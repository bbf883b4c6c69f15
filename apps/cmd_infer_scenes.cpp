// `simpli infer SCENES_DIR --out OUT` (infer.h): every scene folder of SCENES_DIR into
// OUT/<scene> by the one-scene rules (staged, never replacing a folder simpli did not write),
// the scenes sorted by name and dealt round robin over the ranks of the job (parallel::world():
// `mpiexec -n K`; one rank without a launcher). Each rank loads the network once. A scene that
// fails (not a scene, bad views for it, an output that must not be replaced) is reported and the
// others go on; SIGINT / SIGTERM cancel the scene in flight and the rest of that rank's share.
// Rank 0 gathers every rank's rows and prints one table and the throughput. Exit code, the same
// on every rank: 128 + signal when a rank was stopped, else 1 when a scene failed, else 0.
#include "infer.h"
#include "stop_signals.h"

#include "simpli/error.h"
#include "simpli/model/io/staged_folder.h"
#include "simpli/model/parallel/communicator.h"
#include "simpli/ocl/device.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace simpli::app {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// One scene's line of the report.
struct SceneRow {
  std::size_t index = 0; ///< in the sorted list
  int rank = 0;
  std::string status; ///< "ok", "failed", "cancelled"
  int layers = 0, width = 0, height = 0;
  double seconds = 0;
  std::string detail; ///< the output folder, or why it failed
};

// Rows travel to rank 0 as text: tab-separated fields, one row per line.
std::string oneLine(std::string text) {
  std::replace(text.begin(), text.end(), '\t', ' ');
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

std::string encode(const std::vector<SceneRow>& rows) {
  std::ostringstream out;
  for (const SceneRow& r : rows)
    out << r.index << '\t' << r.rank << '\t' << r.status << '\t' << r.layers << '\t' << r.width
        << '\t' << r.height << '\t' << r.seconds << '\t' << oneLine(r.detail) << '\n';
  return out.str();
}

std::vector<SceneRow> decode(const std::string& text) {
  std::vector<SceneRow> rows;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    SceneRow r;
    std::string field;
    std::getline(fields, field, '\t');
    r.index = std::stoul(field);
    fields >> r.rank >> r.status >> r.layers >> r.width >> r.height >> r.seconds;
    fields.get(); // the tab before the detail
    std::getline(fields, r.detail);
    rows.push_back(std::move(r));
  }
  return rows;
}

/// OUT must not lie in SCENES_DIR: its folders would be read as scenes by the next run.
void checkOutsideScenes(const std::string& out, const std::string& scenes) {
  std::error_code ec;
  const fs::path o = fs::weakly_canonical(out, ec), s = fs::weakly_canonical(scenes, ec);
  const auto [end, rest] = std::mismatch(s.begin(), s.end(), o.begin(), o.end());
  if (end == s.end())
    fail("--out ", out, " lies inside the folder of scenes ", scenes,
         " (its folders would be read as scenes); choose a folder outside it");
}

SceneRow inferOne(const InferOptions& o, const scene::SceneFolder& s, InferNetwork& net) {
  SceneRow row;
  const auto t0 = Clock::now();
  const std::string out = (fs::path(o.out) / s.name).string();
  if (!s.problem.empty()) {
    row.status = "failed";
    row.detail = s.problem;
    return row;
  }
  if (stopSignal() != 0) {
    row.status = "cancelled";
    row.detail = "not started: stop requested";
    return row;
  }
  try {
    const SceneInference r = inferScene(o, s.path, out, net, /*verbose=*/false);
    row.status = r.exitCode == 0 ? "ok" : "cancelled";
    row.layers = r.layers;
    row.width = r.width;
    row.height = r.height;
    row.detail = r.exitCode == 0 ? out : "cancelled by a signal, nothing written";
  } catch (const Error& e) {
    row.status = "failed";
    row.detail = e.what();
  }
  row.seconds = secondsSince(t0);
  return row;
}

void printTable(const std::vector<SceneRow>& rows, const std::vector<scene::SceneFolder>& scenes) {
  std::size_t width = 5;
  for (const scene::SceneFolder& s : scenes)
    width = std::max(width, s.name.size());
  const int w = int(width);
  std::printf("%-*s  rank  status     layers  size       time s  output / error\n", w, "scene");
  for (const SceneRow& r : rows) {
    char size[32] = "";
    if (r.status == "ok")
      std::snprintf(size, sizeof size, "%d x %d", r.width, r.height);
    const std::string layers = r.status == "ok" ? std::to_string(r.layers) : "";
    std::printf("%-*s  %4d  %-9s  %6s  %-9s  %6.1f  %s\n", w, scenes[r.index].name.c_str(), r.rank,
                r.status.c_str(), layers.c_str(), size, r.seconds, r.detail.c_str());
  }
}

} // namespace

int inferScenes(const InferOptions& o, const std::vector<scene::SceneFolder>& scenes) {
  parallel::Communicator& comm = parallel::world();
  const auto start = Clock::now();
  checkOutsideScenes(o.out, o.scene);
  io::checkOutputLocation(o.out, "--out", /*createParents=*/true);
  std::error_code ec;
  fs::create_directories(o.out, ec); // every rank: the folder holding the scenes' folders
  if (!fs::is_directory(o.out))
    fail("--out ", o.out, ": cannot create the folder: ", ec.message());

  // One network per rank, loaded once; an error here is the same for every scene.
  InferNetwork net;
  loadInferNetwork(o, net);
  const double loadSeconds = secondsSince(start);
  if (comm.isRoot()) {
    std::printf("scenes     %zu under %s, dealt round robin by name over %d rank(s)\n",
                scenes.size(), o.scene.c_str(), comm.size());
    std::printf("network    config %s (%s)\n", net.loaded->network->config().name.c_str(),
                net.loaded->configSource.c_str());
    std::printf("weights    %s\n", net.loaded->weightsDescription.c_str());
    std::printf("device     %s (rank 0)\n", ocl::Device::current().info().deviceName.c_str());
    std::fflush(stdout);
  }

  const auto loop = Clock::now();
  std::vector<SceneRow> mine;
  for (const std::size_t i : parallel::roundRobinShare(scenes.size(), comm.rank(), comm.size())) {
    SceneRow row = inferOne(o, scenes[i], net);
    row.index = i;
    row.rank = comm.rank();
    std::fprintf(stderr, "rank %d: %s %s (%.1f s)\n", comm.rank(), scenes[i].name.c_str(),
                 row.status.c_str(), row.seconds);
    mine.push_back(std::move(row));
  }
  const double busySeconds = secondsSince(loop);

  // The report: every rank's rows on rank 0, and the exit code agreed by all.
  std::vector<double> counts{0, 0, 0, busySeconds}; // failed, SIGINT, SIGTERM, busy seconds
  for (const SceneRow& r : mine)
    counts[0] += r.status == "failed" ? 1 : 0;
  counts[1] = stopSignal() == SIGINT ? 1 : 0;
  counts[2] = stopSignal() == SIGTERM ? 1 : 0;
  const std::vector<std::string> texts = comm.gather(encode(mine));
  comm.allreduceSum(counts);
  const int code = counts[2] > 0 ? 128 + SIGTERM : counts[1] > 0 ? 128 + SIGINT : counts[0] > 0;
  if (!comm.isRoot())
    return code;
  std::vector<SceneRow> rows;
  for (const std::string& t : texts)
    for (SceneRow& r : decode(t))
      rows.push_back(std::move(r));
  std::sort(rows.begin(), rows.end(),
            [](const SceneRow& a, const SceneRow& b) { return a.index < b.index; });
  printTable(rows, scenes);
  const auto written =
      std::count_if(rows.begin(), rows.end(), [](const SceneRow& r) { return r.status == "ok"; });
  const double wall = secondsSince(loop);
  std::printf("%zu scenes on %d rank(s): %ld written, %.0f failed, %ld cancelled; %.1f s "
              "(network load %.1f s before), %.2f scenes/min, ranks busy %.0f%% of the time\n",
              rows.size(), comm.size(), long(written), counts[0],
              long(rows.size()) - long(written) - long(counts[0]), wall, loadSeconds,
              wall > 0 ? written * 60.0 / wall : 0.0,
              wall > 0 ? 100.0 * counts[3] / (comm.size() * wall) : 0.0);
  std::fflush(stdout);
  return code;
}

} // namespace simpli::app

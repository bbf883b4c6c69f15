#include "simpli/model/training/snapshots.h"

#include "simpli/error.h"
#include "simpli/model/network/config.h"
#include "simpli/model/training/checkpoint.h"

#include <cstdio>
#include <filesystem>
#include <utility>

namespace simpli::training {

namespace fs = std::filesystem;

WeightSnapshots::WeightSnapshots(std::string runDir, int64_t every, int64_t startStep)
    : runDir_(std::move(runDir)), every_(every) {
  if (every < 0)
    fail("keep-weights-every ", every, ": must be >= 0 (0 = keep none)");
  lastMultiple_ = every > 0 ? startStep / every : 0;
}

std::string WeightSnapshots::path(const std::string& runDir, int64_t step) {
  char name[40];
  std::snprintf(name, sizeof name, "step_%08lld.safetensors", static_cast<long long>(step));
  return (fs::path(runDir) / "kept" / name).string();
}

bool WeightSnapshots::due(int64_t step) const {
  return every_ > 0 && step / every_ > lastMultiple_;
}

std::string WeightSnapshots::keep(const network::SimpliNetwork& network, int64_t step) {
  const std::string file = path(runDir_, step);
  fs::create_directories(fs::path(file).parent_path());
  network.parameters().save(file, weightsMetadata(step, network::toJson(network.config())));
  lastMultiple_ = every_ > 0 ? step / every_ : lastMultiple_;
  return file;
}

} // namespace simpli::training

// Atomic training checkpoints (training/checkpoint.h).
#include "simpli/model/training/checkpoint.h"

#include "io/json_text.h"
#include "simpli/error.h"
#include "simpli/model/io/files.h"
#include "simpli/model/io/safetensors.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <vector>

namespace simpli::training {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr const char* kFormat = "simpli-train-checkpoint";
constexpr int kVersion = 1;

// Step number of a "step_NNNNNNNN" folder name, -1 for anything else.
int64_t stepOfName(const std::string& name) {
  if (name.size() != 13 || name.rfind("step_", 0) != 0 ||
      name.find_first_not_of("0123456789", 5) != std::string::npos)
    return -1;
  return std::stoll(name.substr(5));
}

class FileCounter {
public:
  explicit FileCounter(int failAfter) : failAfter_(failAfter) {}
  void wrote(const std::string& file) {
    ++count_;
    if (failAfter_ >= 0 && count_ >= failAfter_)
      fail("writeCheckpoint: simulated failure after writing ", file);
  }

private:
  int failAfter_;
  int count_ = 0;
};

} // namespace

std::map<std::string, std::string> weightsMetadata(int64_t step,
                                                   const std::string& networkConfigJson) {
  std::map<std::string, std::string> meta{{"format", "simpli-weights"},
                                          {"step", std::to_string(step)}};
  if (!networkConfigJson.empty())
    meta["network_config"] = networkConfigJson;
  return meta;
}

std::string checkpointDir(const std::string& runDir, int64_t step) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%08lld", static_cast<long long>(step));
  return (fs::path(runDir) / "checkpoints" / name).string();
}

std::string writeCheckpoint(const std::string& runDir, const network::ParameterStore& store,
                            const CheckpointData& data, const CheckpointWriteOptions& options) {
  if (data.step < 0 || data.step > 99999999)
    fail("writeCheckpoint: step ", data.step, " out of range 0 .. 99999999");
  const fs::path root = fs::path(runDir) / "checkpoints";
  std::error_code ec;
  fs::create_directories(root, ec);
  if (ec)
    fail("writeCheckpoint: cannot create '", root.string(), "': ", ec.message());
  const fs::path final = checkpointDir(runDir, data.step);
  const fs::path tmp =
      root / (".tmp-" + final.filename().string() + "-" + std::to_string(::getpid()));
  fs::remove_all(tmp, ec);
  fs::create_directory(tmp, ec);
  if (ec)
    fail("writeCheckpoint: cannot create '", tmp.string(), "': ", ec.message());
  FileCounter counter(options.failAfterFiles);

  std::string networkConfig;
  if (!data.configJson.empty()) {
    const json config = json::parse(data.configJson);
    if (config.is_object() && config.contains("network") && config["network"].is_object())
      networkConfig = config["network"].dump(2);
  }
  const std::map<std::string, std::string> meta = weightsMetadata(data.step, networkConfig);
  const std::string weights = (tmp / "weights.safetensors").string();
  store.save(weights, meta);
  counter.wrote(weights);

  // Adam moments, keyed by parameter name (store order = optimiser order).
  const std::vector<std::string>& names = store.names();
  if (!data.adam.params.empty() && data.adam.params.size() != names.size())
    fail("writeCheckpoint: optimiser state has ", data.adam.params.size(),
         " parameters, the network ", names.size());
  std::map<std::string, io::SafeTensorEntry> moments;
  json paramSteps = json::object();
  for (size_t i = 0; i < data.adam.params.size(); ++i) {
    const ocl::Adam::ParamState& p = data.adam.params[i];
    paramSteps[names[i]] = p.step;
    if (p.m.empty())
      continue;
    io::HostTensor<double> m{{int64_t(p.m.size())}, p.m}, v{{int64_t(p.v.size())}, p.v};
    moments["m." + names[i]] = io::makeEntry(m);
    moments["v." + names[i]] = io::makeEntry(v);
  }
  const std::string optim = (tmp / "optimizer.safetensors").string();
  io::writeSafeTensors(optim, moments, {{"format", "simpli-adam"}});
  counter.wrote(optim);

  std::map<std::string, io::SafeTensorEntry> average;
  for (const auto& [name, values] : data.average)
    average[name] = io::makeEntry(values);
  const std::string averagePath = (tmp / "weights_ema.safetensors").string();
  if (!average.empty()) {
    io::writeSafeTensors(averagePath, average, meta);
    counter.wrote(averagePath);
  }

  json state;
  state["format"] = kFormat;
  state["version"] = kVersion;
  state["step"] = data.step;
  state["lr_step"] = data.step; // ExponentialLR is stepped once per optimiser step
  {
    TrainRandom r;
    r.setState(data.random);
    state["random"] = r.stateString();
  }
  if (!data.streams.empty()) {
    if (data.streams[0] != data.random)
      fail("writeCheckpoint: sample stream 0 differs from the sampler state");
    json streams = json::array();
    for (const TrainRandom::State& s : data.streams) {
      TrainRandom r;
      r.setState(s);
      streams.push_back(r.stateString());
    }
    state["sample_streams"] = streams;
  }
  state["adam_steps"] = data.adam.steps;
  state["param_steps"] = paramSteps;
  state["config"] = data.configJson.empty() ? json() : json::parse(data.configJson);
  const std::string text = state.dump(2) + "\n";
  const std::string statePath = (tmp / "state.json").string();
  io::writeFileAtomically(statePath, text.data(), text.size());
  counter.wrote(statePath);

  // Commit: a previous checkpoint of the same step (a re-run) is moved aside first.
  if (fs::exists(final)) {
    const fs::path old = root / (".old-" + final.filename().string());
    fs::remove_all(old, ec);
    fs::rename(final, old, ec);
    if (ec)
      fail("writeCheckpoint: cannot move '", final.string(), "' aside: ", ec.message());
  }
  fs::rename(tmp, final, ec);
  if (ec)
    fail("writeCheckpoint: cannot rename '", tmp.string(), "' to '", final.string(),
         "': ", ec.message());

  // The run's current weights, for `simpli infer --weights RUN/weights.safetensors`.
  store.save((fs::path(runDir) / "weights.safetensors").string(), meta);
  if (!average.empty())
    io::writeSafeTensors((fs::path(runDir) / "weights_ema.safetensors").string(), average, meta);

  // Clean up: temporaries of failed writes and checkpoints beyond `keep`.
  std::vector<std::pair<int64_t, fs::path>> complete;
  for (const fs::directory_entry& e : fs::directory_iterator(root)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(".tmp-", 0) == 0 || name.rfind(".old-", 0) == 0)
      fs::remove_all(e.path(), ec);
    else if (int64_t s = stepOfName(name); s >= 0)
      complete.emplace_back(s, e.path());
  }
  std::sort(complete.begin(), complete.end());
  // A folder is renamed out of the step_* namespace before its files go: a process killed while
  // removing it leaves a `.old-` temporary, never a step folder that lacks files.
  const size_t keep = size_t(std::max(1, options.keep));
  for (size_t i = 0; i + keep < complete.size(); ++i) {
    const fs::path old = root / (".old-" + complete[i].second.filename().string());
    fs::remove_all(old, ec);
    fs::rename(complete[i].second, old, ec);
    if (!ec)
      fs::remove_all(old, ec);
  }
  return final.string();
}

std::optional<std::string> latestCheckpoint(const std::string& runDir) {
  const fs::path root = fs::path(runDir) / "checkpoints";
  std::error_code ec;
  if (!fs::is_directory(root, ec))
    return std::nullopt;
  int64_t best = -1;
  fs::path bestPath;
  for (const fs::directory_entry& e : fs::directory_iterator(root)) {
    const int64_t s = stepOfName(e.path().filename().string());
    if (s > best && fs::exists(e.path() / "state.json")) {
      best = s;
      bestPath = e.path();
    }
  }
  if (best < 0)
    return std::nullopt;
  return bestPath.string();
}

CheckpointData readCheckpoint(const std::string& dir, network::ParameterStore& store) {
  const fs::path root(dir);
  const std::string statePath = (root / "state.json").string();
  const std::vector<unsigned char> bytes = io::readFileBytes(statePath, "checkpoint state");
  const json state = io::parseJson(std::string(bytes.begin(), bytes.end()), statePath);
  auto field = [&](const char* key) -> const json& {
    if (!state.is_object() || !state.contains(key))
      fail(statePath, ": missing field \"", key, "\"");
    return state[key];
  };
  if (field("format") != kFormat)
    fail(statePath, ": field \"format\" is ", io::jsonExcerpt(field("format")), ", expected \"",
         kFormat, "\"");
  if (field("version") != kVersion)
    fail(statePath, ": field \"version\" is ", io::jsonExcerpt(field("version")), ", expected ",
         kVersion);
  CheckpointData data;
  if (!field("step").is_number_integer() || field("step").get<int64_t>() < 0)
    fail(statePath, ": field \"step\" is ", io::jsonExcerpt(field("step")),
         ", expected an integer >= 0");
  data.step = field("step").get<int64_t>();
  if (!field("random").is_string())
    fail(statePath, ": field \"random\" is not a string");
  data.random = TrainRandom::parseState(field("random").get<std::string>(), statePath);
  if (state.contains("sample_streams")) {
    const json& streams = state["sample_streams"];
    if (!streams.is_array() || streams.empty())
      fail(statePath, ": field \"sample_streams\" is not a non-empty array");
    for (const json& s : streams) {
      if (!s.is_string())
        fail(statePath, ": field \"sample_streams\" holds ", s.dump(), ", expected a string");
      data.streams.push_back(TrainRandom::parseState(s.get<std::string>(), statePath));
    }
    if (data.streams[0] != data.random)
      fail(statePath, ": field \"sample_streams\"[0] differs from field \"random\"");
  }
  if (!field("adam_steps").is_number_integer())
    fail(statePath, ": field \"adam_steps\" is not an integer");
  data.adam.steps = field("adam_steps").get<int64_t>();
  data.configJson = field("config").is_null() ? "" : field("config").dump(2) + "\n";
  const json& paramSteps = field("param_steps");
  if (!paramSteps.is_object())
    fail(statePath, ": field \"param_steps\" is not an object");

  store.load((root / "weights.safetensors").string());

  const std::string optimPath = (root / "optimizer.safetensors").string();
  const io::SafeTensorsReader optim(optimPath);
  for (const std::string& name : store.names()) {
    ocl::Adam::ParamState p;
    if (!paramSteps.contains(name) || !paramSteps[name].is_number_integer())
      fail(statePath, ": field \"param_steps\" has no step count for parameter '", name, "'");
    p.step = paramSteps[name].get<int64_t>();
    const int64_t numel = store.get(name).numel();
    for (const char* which : {"m.", "v."}) {
      const std::string key = which + name;
      if (!optim.contains(key)) {
        if (p.step > 0)
          fail(optimPath, ": missing key '", key, "' (parameter stepped ", p.step, " times)");
        continue;
      }
      io::HostTensor<double> t = optim.readF64(key);
      if (t.numel() != numel)
        fail(optimPath, ": key '", key, "' has ", t.numel(), " values; the parameter has ", numel);
      (which[0] == 'm' ? p.m : p.v) = std::move(t.data);
    }
    data.adam.params.push_back(std::move(p));
  }

  const fs::path averagePath = root / "weights_ema.safetensors";
  if (fs::exists(averagePath)) {
    const io::SafeTensorsReader average(averagePath.string());
    for (const std::string& key : average.keys())
      data.average[key] = average.readF64(key);
  }
  return data;
}

} // namespace simpli::training

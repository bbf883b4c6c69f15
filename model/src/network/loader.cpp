#include "simpli/model/network/loader.h"

#include "simpli/error.h"

#include "simpli/model/io/safetensors.h"

#include <cstdlib>

#include <filesystem>

namespace simpli::network {

std::string networkConfigDir() {
  if (const char* dir = std::getenv("SIMPLI_CONFIG_DIR"); dir && *dir)
    return dir;
  return std::string(SIMPLI_SOURCE_DIR) + "/model/configs";
}

std::string defaultWeightsPath() {
  if (const char* file = std::getenv("SIMPLI_DEFAULT_WEIGHTS"); file && *file)
    return file;
  return std::string(SIMPLI_SOURCE_DIR) + "/model/weights/default.safetensors";
}

NetworkConfig resolveNetworkConfig(const std::string& nameOrPath) {
  if (nameOrPath == "official-4l")
    return officialConfig(4);
  if (nameOrPath == "official-8l")
    return officialConfig(8);
  const bool isPath =
      nameOrPath.find('/') != std::string::npos ||
      (nameOrPath.size() > 5 && nameOrPath.substr(nameOrPath.size() - 5) == ".json");
  const std::string path = isPath ? nameOrPath : networkConfigDir() + "/" + nameOrPath + ".json";
  if (!std::filesystem::exists(path))
    fail("network config '", nameOrPath, "': ", path,
         " does not exist (built in: official-4l, official-8l; others in ", networkConfigDir(),
         ")");
  return loadNetworkConfig(path);
}

std::optional<NetworkConfig> configFromWeights(const std::string& weightsPath) {
  const io::SafeTensorsReader reader(weightsPath);
  for (const char* key : {"network_config", "config"}) {
    const auto it = reader.metadata().find(key);
    if (it == reader.metadata().end())
      continue;
    const std::string& text = it->second;
    const std::size_t first = text.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && text[first] == '{')
      return parseNetworkConfig(text, weightsPath + " metadata \"" + key + "\"");
    return resolveNetworkConfig(text);
  }
  return std::nullopt;
}

LoadedNetwork loadNetwork(const std::string& configName, const std::string& weightsPath,
                          std::optional<uint64_t> randomSeed, ocl::Dtype dtype) {
  LoadedNetwork out;
  if (randomSeed) {
    if (!weightsPath.empty())
      fail("a weights file (", weightsPath, ") and random initialisation exclude each other");
    const std::string name = configName.empty() ? "official-4l" : configName;
    out.network = std::make_unique<SimpliNetwork>(resolveNetworkConfig(name), dtype, *randomSeed);
    out.configSource = name;
    out.weightsDescription = "random (seed " + std::to_string(*randomSeed) + ")";
    return out;
  }
  const std::string weights = weightsPath.empty() ? defaultWeightsPath() : weightsPath;
  if (!std::filesystem::exists(weights)) {
    if (weightsPath.empty())
      fail("no weights given and the default weights ", weights,
           " are missing: train a network with `simpli train` and pass its weights.safetensors "
           "as the weights (--weights / WeightsFile), convert an official checkpoint with "
           "scripts/convert_reference_checkpoint.py, or initialise randomly (--init-random SEED, "
           "testing only)");
    fail("weights file ", weights, " does not exist");
  }
  NetworkConfig config;
  if (!configName.empty()) {
    config = resolveNetworkConfig(configName);
    out.configSource = configName;
  } else if (auto stored = configFromWeights(weights)) {
    config = *stored;
    out.configSource = weights + " metadata";
  } else {
    fail("weights file ", weights,
         " has no \"config\" metadata: name a config (--config / Config, e.g. official-4l)");
  }
  out.network = std::make_unique<SimpliNetwork>(config, dtype);
  const LoadReport report = out.network->parameters().load(weights);
  out.weightsDescription = weights + " (" + std::to_string(report.loaded) + " tensors";
  if (!report.unexpected.empty())
    out.weightsDescription += ", " + std::to_string(report.unexpected.size()) +
                              " unused keys, e.g. " + report.unexpected.front();
  out.weightsDescription += ")";
  return out;
}

} // namespace simpli::network

#pragma once
// Building a SIMPLI network from a config name or file and a weights file: what `simpli
// infer`, `simpli eval`, `simpli bench infer` and the VTK filters share.
//
// Shipped configs live in model/configs and the default weights in
// model/weights/default.safetensors of the source tree; the environment variables
// SIMPLI_CONFIG_DIR and SIMPLI_DEFAULT_WEIGHTS point elsewhere (an installed copy).
#include "simpli/model/network/network.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace simpli::network {

/// The folder of the shipped network configs.
std::string networkConfigDir();
/// The default weights file.
std::string defaultWeightsPath();

/// A config by name ("official-4l" and "official-8l" are built in; other names are
/// <networkConfigDir()>/<name>.json) or by the path of a JSON file (anything ending in .json
/// or containing a '/'). Throws simpli::Error naming the config when it is unknown.
NetworkConfig resolveNetworkConfig(const std::string& nameOrPath);

/// The network config stored in a weights file's metadata ("network_config" or "config":
/// the config's JSON text, or a config name), if any.
std::optional<NetworkConfig> configFromWeights(const std::string& weightsPath);

struct LoadedNetwork {
  std::unique_ptr<SimpliNetwork> network;
  std::string weightsDescription; ///< "<file> (N tensors)" or "random (seed S)"
  std::string configSource;       ///< where the config came from
};

/// Weights from `weightsPath` (empty: the default weights) or, with `randomSeed`, freshly
/// initialised parameters; the config from `configName` (empty: the weights' metadata; for
/// random weights "official-4l"). Throws simpli::Error naming the missing file and how to get
/// weights when there are none.
LoadedNetwork loadNetwork(const std::string& configName, const std::string& weightsPath,
                          std::optional<uint64_t> randomSeed, ocl::Dtype dtype = ocl::Dtype::F32);

} // namespace simpli::network

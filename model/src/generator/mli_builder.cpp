#include "simpli/model/generator/mli_builder.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace simpli::generator {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Modification time of `path` as text ("" when it cannot be read), so that a weights file
// rewritten by a training run is loaded again.
std::string modificationTime(const std::string& path) {
  std::error_code ec;
  const auto t = std::filesystem::last_write_time(path, ec);
  return ec ? std::string() : std::to_string(t.time_since_epoch().count());
}

std::string currentDevice() {
  const ocl::DeviceInfo& info = ocl::Device::current().info();
  return std::to_string(info.platformIndex) + ":" + std::to_string(info.deviceIndex);
}

std::string networkKey(const NetworkSource& source) {
  const std::string weights =
      source.weights.empty() ? network::defaultWeightsPath() : source.weights;
  return source.weights + "\n" + modificationTime(weights) + "\n" + source.config + "\n" +
         (source.randomSeed ? std::to_string(*source.randomSeed) : std::string("-")) + "\n" +
         currentDevice();
}

// Everything besides the pixels that the forward pass depends on, exactly (17 digits).
std::string forwardKey(const std::string& networkKey, int corrections,
                       const GeneratorInput& input) {
  std::ostringstream os;
  os << std::setprecision(17) << networkKey << "\n"
     << corrections << " " << input.minDepth << " " << input.maxDepth;
  std::vector<scene::Camera> cameras = input.sources;
  cameras.push_back(input.reference);
  for (const scene::Camera& c : cameras) {
    os << "\n"
       << c.width << " " << c.height << " " << c.fx << " " << c.fy << " " << c.cx << " " << c.cy;
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k)
        os << " " << c.R(r, k);
      os << " " << c.t(r);
    }
  }
  return os.str();
}

// The source views' pixels, in input order.
std::vector<float> sourcePixels(const scene::Scene& scene, const std::vector<int>& views) {
  std::vector<float> pixels;
  for (int v : views) {
    const std::vector<float>& data = scene.views[static_cast<std::size_t>(v)].image.data;
    pixels.insert(pixels.end(), data.begin(), data.end());
  }
  return pixels;
}

} // namespace

const network::LoadedNetwork& MLIBuilder::network(const NetworkSource& source) {
  const std::string key = networkKey(source);
  if (loaded_.network && key == networkKey_)
    return loaded_;
  release();
  loaded_ = network::loadNetwork(source.config, source.weights, source.randomSeed);
  networkKey_ = key;
  return loaded_;
}

MLIBuild MLIBuilder::build(const scene::Scene& scene, const MLIBuildOptions& options) {
  if (!loaded_.network)
    fail("MLIBuilder::build: no network (call network() first)");
  network::SimpliNetwork& net = *loaded_.network;
  MLIBuild result;
  result.views = sceneInputViews(scene, options.views);
  SceneInputOptions inputOptions;
  inputOptions.views = result.views;
  inputOptions.depthRange = options.depthRange;
  inputOptions.inputScale = options.inputScale;
  inputOptions.referenceMargin = options.referenceMargin;
  result.input = sceneInput(scene, inputOptions);

  const int corrections =
      options.corrections < 0 ? net.config().mliCorrections() : options.corrections;
  const std::string key = forwardKey(networkKey_, corrections, result.input) + "\n" +
                          std::to_string(options.dropEmptyBelow);
  std::vector<float> pixels = sourcePixels(scene, result.views);
  if (!options.keepOutput && lastMLI_ && key == lastKey_ && pixels == lastPixels_) {
    result.mli = *lastMLI_;
    result.reused = true;
    result.stageMs.emplace_back("forward_reused", 0.0);
    return result;
  }
  lastMLI_.reset();
  lastKey_.clear();
  lastPixels_.clear();

  GeneratorOptions generatorOptions;
  generatorOptions.corrections = options.corrections;
  generatorOptions.timeStages = true;
  generatorOptions.progress = options.progress;
  GeneratorOutput output;
  {
    ocl::NoGradGuard noGrad;
    output = Generator(net).forward(result.input, generatorOptions);
  }
  result.stageMs = output.stageMs;
  const auto t0 = Clock::now();
  result.mli = toMLI(output, result.input.reference, options.dropEmptyBelow);
  result.stageMs.emplace_back("to_mli", msSince(t0));
  if (options.keepOutput)
    result.output = std::move(output);
  lastMLI_ = result.mli;
  lastKey_ = key;
  lastPixels_ = std::move(pixels);
  return result;
}

void MLIBuilder::release() {
  loaded_ = network::LoadedNetwork{};
  networkKey_.clear();
  lastMLI_.reset();
  lastKey_.clear();
  lastPixels_.clear();
}

} // namespace simpli::generator

#include "vtkSIMPLIBuildMLI.h"

#include "SIMPLIDevice.h"
#include "SIMPLIMLIToVTK.h"
#include "SIMPLISceneToVTK.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"

#include "simpli/error.h"
#include "simpli/model/generator/generator.h"
#include "simpli/model/generator/scene_input.h"
#include "simpli/model/mli/mli.h"
#include "simpli/model/network/loader.h"
#include "simpli/model/scene/scene.h"
#include "simpli/ocl/autograd.h"

#include <chrono>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkSIMPLIBuildMLI);

// The cached network and what it was loaded from; the last forward pass's MLI and what it was
// computed from (so that changing only how the layers become meshes does not rerun it).
class vtkSIMPLIBuildMLI::vtkInternals {
public:
  std::unique_ptr<simpli::network::SimpliNetwork> Network;
  std::string Key; ///< weights, their modification time, config, seed and device
  std::string WeightsDescription;
  int DeviceUser = 0;

  std::optional<simpli::mli::MLI> LastMLI;
  std::string LastForwardKey;    ///< Key, corrections, depth range, cameras
  std::vector<float> LastPixels; ///< the source images
  void ForgetForward() {
    this->LastMLI.reset();
    this->LastForwardKey.clear();
    this->LastPixels.clear();
  }
};

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

std::string str(const char* s) {
  return s ? std::string(s) : std::string();
}

// "0,2,5" (commas and/or spaces) -> {0, 2, 5}; range checks happen against the scene.
std::vector<int> parseViewList(const std::string& text) {
  std::vector<int> views;
  std::size_t i = 0;
  while (i < text.size()) {
    const std::size_t end = text.find_first_of(", \t", i);
    const std::string item = text.substr(i, end == std::string::npos ? end : end - i);
    i = end == std::string::npos ? text.size() : end + 1;
    if (item.empty())
      continue;
    std::size_t used = 0;
    long value = -1;
    try {
      value = std::stol(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || value < 0 || value > 1000000)
      simpli::fail("SourceViews '", text, "': '", item,
                   "' is not a view index (expected comma-separated 0-based indices such as "
                   "0,2,5, or empty for every view)");
    views.push_back(static_cast<int>(value));
  }
  return views;
}

// Modification time of `path` as text ("" when it cannot be read), so that a weights file
// rewritten by a training run is loaded again.
std::string modificationTime(const std::string& path) {
  std::error_code ec;
  const auto t = std::filesystem::last_write_time(path, ec);
  return ec ? std::string() : std::to_string(t.time_since_epoch().count());
}

// Everything besides the pixels that the forward pass depends on, exactly (17 digits).
std::string forwardKey(const std::string& networkKey, int corrections,
                       const simpli::generator::GeneratorInput& input) {
  std::ostringstream os;
  os << std::setprecision(17) << networkKey << "\n"
     << corrections << " " << input.minDepth << " " << input.maxDepth;
  std::vector<simpli::scene::Camera> cameras = input.sources;
  cameras.push_back(input.reference);
  for (const simpli::scene::Camera& c : cameras) {
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
std::vector<float> sourcePixels(const simpli::scene::Scene& scene, const std::vector<int>& views) {
  std::vector<float> pixels;
  for (int v : views) {
    const std::vector<float>& data = scene.views[static_cast<std::size_t>(v)].image.data;
    pixels.insert(pixels.end(), data.begin(), data.end());
  }
  return pixels;
}

vtkSmartPointer<vtkStringArray> stringValue(const char* name, const std::string& value) {
  auto a = vtkSmartPointer<vtkStringArray>::New();
  a->SetName(name);
  a->InsertNextValue(value);
  return a;
}

vtkSmartPointer<vtkIntArray> intValue(const char* name, int value) {
  auto a = vtkSmartPointer<vtkIntArray>::New();
  a->SetName(name);
  a->InsertNextValue(value);
  return a;
}

} // namespace

vtkSIMPLIBuildMLI::vtkSIMPLIBuildMLI() : Internals(new vtkInternals) {
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
  vtkInternals* internals = this->Internals;
  internals->DeviceUser = simpli::vtkdevice::registerDeviceUser([internals] {
    internals->Network.reset();
    internals->Key.clear();
  });
}

vtkSIMPLIBuildMLI::~vtkSIMPLIBuildMLI() {
  simpli::vtkdevice::unregisterDeviceUser(this->Internals->DeviceUser);
  delete this->Internals;
  this->SetSceneFileName(nullptr);
  this->SetWeightsFile(nullptr);
  this->SetConfig(nullptr);
  this->SetSourceViews(nullptr);
  this->SetDevice(nullptr);
}

void vtkSIMPLIBuildMLI::ReleaseNetwork() {
  this->Internals->Network.reset();
  this->Internals->Key.clear();
  this->Internals->ForgetForward();
}

int vtkSIMPLIBuildMLI::FillInputPortInformation(int port, vtkInformation* info) {
  if (port != 0)
    return 0;
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPartitionedDataSetCollection");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkSIMPLIBuildMLI::RequestData(vtkInformation* vtkNotUsed(request),
                                   vtkInformationVector** inputVector,
                                   vtkInformationVector* outputVector) {
  vtkPartitionedDataSetCollection* output = vtkPartitionedDataSetCollection::GetData(outputVector);
  if (!output) {
    vtkErrorMacro(<< "No vtkPartitionedDataSetCollection output to fill");
    return 0;
  }
  output->Initialize();
  std::vector<std::pair<std::string, double>> stages;

  try {
    const std::vector<int> requestedViews = parseViewList(str(this->SourceViews));

    // --- the scene ----------------------------------------------------------------------------
    this->UpdateProgress(0.0);
    auto t0 = Clock::now();
    auto* sceneInput = inputVector[0]->GetNumberOfInformationObjects() > 0
                           ? vtkPartitionedDataSetCollection::GetData(inputVector[0], 0)
                           : nullptr;
    simpli::scene::Scene scene;
    if (sceneInput) {
      scene = simpli::vtkscene::vtkToScene(sceneInput, "Build MLI: input scene");
    } else {
      if (str(this->SceneFileName).empty())
        simpli::fail("no scene: connect a scene (SIMPLI Scene Reader) to the input or set "
                     "SceneFileName to a scene folder");
      try {
        scene = simpli::scene::readScene(this->SceneFileName);
      } catch (const simpli::Error& e) {
        simpli::fail("SceneFileName '", this->SceneFileName, "': ", e.what());
      }
    }
    stages.emplace_back("read_scene", msSince(t0));
    std::vector<int> views;
    try {
      views = simpli::generator::sceneInputViews(scene, requestedViews);
    } catch (const simpli::Error& e) {
      simpli::fail("SourceViews '", str(this->SourceViews), "': ", e.what());
    }
    this->UpdateProgress(0.1);
    if (this->GetAbortExecute())
      return 1; // aborted: empty output, no error

    // --- the network (cached) -------------------------------------------------------------------
    t0 = Clock::now();
    simpli::vtkdevice::selectDevice(str(this->Device), "Device");
    const std::string weights = str(this->WeightsFile);
    const std::string key =
        weights + "\n" +
        modificationTime(weights.empty() ? simpli::network::defaultWeightsPath() : weights) + "\n" +
        str(this->Config) + "\n" + std::to_string(this->RandomSeed) + "\n" +
        simpli::vtkdevice::currentDevice();
    vtkInternals& in = *this->Internals;
    if (!in.Network || in.Key != key) {
      in.Network.reset();
      in.Key.clear();
      simpli::network::LoadedNetwork loaded;
      try {
        loaded = simpli::network::loadNetwork(
            str(this->Config), weights,
            this->RandomSeed >= 0 ? std::optional<uint64_t>(this->RandomSeed) : std::nullopt);
      } catch (const simpli::Error& e) {
        simpli::fail("network (WeightsFile '", weights, "', Config '", str(this->Config),
                     "'): ", e.what());
      }
      in.Network = std::move(loaded.network);
      in.WeightsDescription = loaded.weightsDescription;
      in.Key = key;
    }
    stages.emplace_back("load_network", msSince(t0));
    simpli::network::SimpliNetwork& network = *in.Network;
    const simpli::network::NetworkConfig& config = network.config();
    if (this->NumberOfPlanes != 0 && this->NumberOfPlanes != config.numPlanes)
      simpli::fail("NumberOfPlanes ", this->NumberOfPlanes, ": the network (config '", config.name,
                   "') was built for ", config.numPlanes,
                   " planes (the plane count is part of the trained network); use 0 or ",
                   config.numPlanes);
    if (this->CorrectionSteps > config.mliCorrections())
      simpli::fail("CorrectionSteps ", this->CorrectionSteps, ": config '", config.name, "' has ",
                   config.mliCorrections(), " MLI corrections (use -1 for all, or 0..",
                   config.mliCorrections(), ")");
    this->UpdateProgress(0.2);
    if (this->GetAbortExecute())
      return 1;

    // --- the forward pass ----------------------------------------------------------------------
    simpli::generator::SceneInputOptions inputOptions;
    inputOptions.views = views;
    inputOptions.depthRange = this->DepthRange == DEPTH_RANGE_SCENE
                                  ? simpli::generator::DepthRangeSource::Scene
                                  : simpli::generator::DepthRangeSource::Config;
    const simpli::generator::GeneratorInput input =
        simpli::generator::sceneInput(scene, inputOptions);

    const int corrections =
        this->CorrectionSteps < 0 ? config.mliCorrections() : this->CorrectionSteps;
    const std::string fwdKey = forwardKey(in.Key, corrections, input);
    std::vector<float> pixels = sourcePixels(scene, views);
    if (in.LastMLI && in.LastForwardKey == fwdKey && in.LastPixels == pixels) {
      // Same network, sources and settings: only the mesh options changed.
      stages.emplace_back("forward_reused", 0.0);
    } else {
      in.ForgetForward();
      simpli::generator::GeneratorOptions options;
      options.corrections = this->CorrectionSteps;
      options.timeStages = true;
      // Progress and abort after every stage of the pass: 0.2 .. 0.85 of the work.
      options.progress = [this](const std::string&, int done, int total) {
        this->UpdateProgress(0.2 + 0.65 * done / total);
        return !this->GetAbortExecute();
      };
      simpli::generator::GeneratorOutput generated;
      try {
        simpli::ocl::NoGradGuard noGrad;
        generated = simpli::generator::Generator(network).forward(input, options);
      } catch (const simpli::generator::GeneratorCancelled&) {
        vtkDebugMacro(<< "Aborted during the forward pass");
        return 1;
      }
      for (const auto& stage : generated.stageMs)
        stages.push_back(stage);
      t0 = Clock::now();
      in.LastMLI = simpli::generator::toMLI(generated, input.reference);
      stages.emplace_back("to_mli", msSince(t0));
      in.LastForwardKey = fwdKey;
      in.LastPixels = std::move(pixels);
    }
    this->UpdateProgress(0.85);
    if (this->GetAbortExecute())
      return 1;

    // --- the meshes -----------------------------------------------------------------------------
    const simpli::mli::MLI& mli = *in.LastMLI;
    simpli::vtkmli::LayerOptions layerOptions;
    layerOptions.dropTransparentTriangles = this->DropTransparentTriangles;
    layerOptions.alphaThreshold = this->EmptyLayerThreshold;
    // "auto" layers; an MLI whose every layer is empty keeps them all (never an empty output).
    layerOptions.skipEmptyLayers =
        this->DropEmptyLayers &&
        simpli::mli::emptyLayers(mli, static_cast<float>(this->EmptyLayerThreshold)).size() <
            mli.layers.size();
    t0 = Clock::now();
    const bool complete =
        simpli::vtkmli::mliToCollection(mli, layerOptions, output, [this](double f) {
          this->UpdateProgress(0.9 + 0.1 * f);
          return !this->GetAbortExecute();
        });
    if (!complete)
      return 1;
    stages.emplace_back("meshes", msSince(t0));

    vtkFieldData* fd = output->GetFieldData();
    auto names = vtkSmartPointer<vtkStringArray>::New();
    names->SetName("StageNames");
    auto times = vtkSmartPointer<vtkDoubleArray>::New();
    times->SetName("StageTimes");
    for (const auto& [name, ms] : stages) {
      names->InsertNextValue(name);
      times->InsertNextValue(ms);
    }
    fd->AddArray(names);
    fd->AddArray(times);
    auto viewArray = vtkSmartPointer<vtkIntArray>::New();
    viewArray->SetName("SourceViews");
    for (int v : views)
      viewArray->InsertNextValue(v);
    fd->AddArray(viewArray);
    fd->AddArray(intValue("NumberOfPlanes", config.numPlanes));
    fd->AddArray(stringValue("NetworkConfig", config.name));
    fd->AddArray(stringValue("NetworkWeights", in.WeightsDescription));
    this->UpdateProgress(1.0);
    return 1;
  } catch (const simpli::Error& e) {
    vtkErrorMacro(<< "SIMPLI Build MLI: " << e.what());
  } catch (const std::exception& e) {
    vtkErrorMacro(<< "SIMPLI Build MLI: unexpected failure: " << e.what());
  }
  output->Initialize();
  return 0;
}

void vtkSIMPLIBuildMLI::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  auto s = [](const char* v) { return v ? v : "(none)"; };
  os << indent << "SceneFileName: " << s(this->SceneFileName) << "\n";
  os << indent << "WeightsFile: " << (this->WeightsFile ? this->WeightsFile : "(default)") << "\n";
  os << indent << "Config: " << (this->Config ? this->Config : "(from the weights)") << "\n";
  os << indent << "DropEmptyLayers: " << this->DropEmptyLayers << "\n";
  os << indent << "EmptyLayerThreshold: " << this->EmptyLayerThreshold << "\n";
  os << indent << "DropTransparentTriangles: " << this->DropTransparentTriangles << "\n";
  os << indent << "NumberOfPlanes: " << this->NumberOfPlanes << "\n";
  os << indent << "CorrectionSteps: " << this->CorrectionSteps << "\n";
  os << indent << "SourceViews: " << (this->SourceViews ? this->SourceViews : "(all)") << "\n";
  os << indent << "DepthRange: " << (this->DepthRange == DEPTH_RANGE_SCENE ? "Scene" : "Config")
     << "\n";
  os << indent << "Device: " << (this->Device ? this->Device : "(current)") << "\n";
  os << indent << "RandomSeed: " << this->RandomSeed << "\n";
  os << indent << "NetworkLoaded: " << (this->Internals->Network ? 1 : 0) << "\n";
}

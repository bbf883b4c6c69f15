#include "vtkSIMPLIBuildMLI.h"

#include "SIMPLIFilter.h"
#include "SIMPLIMLIToVTK.h"
#include "SIMPLISceneToVTK.h"

#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>

#include "simpli/error.h"
#include "simpli/model/generator/mli_builder.h"
#include "simpli/model/mli/mli.h"
#include "simpli/model/network/loader.h"
#include "simpli/model/parallel/communicator.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/scene/scene.h"

#include <chrono>
#include <exception>
#include <string>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkSIMPLIBuildMLI);

// The model side, generator::MLIBuilder (the cached network and the last forward pass), and the
// steps of RequestData that read the filter's properties (a nested class sees them).
class vtkSIMPLIBuildMLI::vtkInternals {
public:
  simpli::generator::MLIBuilder Builder;
  int DeviceUser = 0;

  /// The input scene, or the one in SceneFileName when nothing is connected.
  static simpli::scene::Scene ReadScene(vtkSIMPLIBuildMLI* self, vtkInformationVector* input);
  /// The network of WeightsFile / Config / RandomSeed on Device (cached), checked against
  /// NumberOfPlanes and CorrectionSteps.
  const simpli::network::LoadedNetwork& LoadNetwork(vtkSIMPLIBuildMLI* self);
  /// The MLI as layer meshes per DropEmptyLayers, EmptyLayerThreshold, DropTransparentTriangles,
  /// MeshMode, MeshTolerance;
  /// false when aborted.
  static bool FillLayers(vtkSIMPLIBuildMLI* self, const simpli::mli::MLI& mli,
                         vtkPartitionedDataSetCollection* output,
                         const simpli::vtkfilter::Progress& progress);
};

namespace {

using Clock = std::chrono::steady_clock;
using simpli::vtkfilter::str;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
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

// Stage names and times, the source views and the network as field data of `out`.
void addBuildFieldData(vtkFieldData* fd, const std::vector<std::pair<std::string, double>>& stages,
                       const std::vector<int>& views, const simpli::network::NetworkConfig& config,
                       const std::string& weights) {
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
  fd->AddArray(stringValue("NetworkWeights", weights));
}

} // namespace

vtkSIMPLIBuildMLI::vtkSIMPLIBuildMLI() : Internals(new vtkInternals) {
  this->SetNumberOfInputPorts(1);
  this->SetNumberOfOutputPorts(1);
  vtkInternals* internals = this->Internals;
  internals->DeviceUser =
      simpli::vtkfilter::registerDeviceUser([internals] { internals->Builder.release(); });
}

vtkSIMPLIBuildMLI::~vtkSIMPLIBuildMLI() {
  simpli::vtkfilter::unregisterDeviceUser(this->Internals->DeviceUser);
  delete this->Internals;
  this->SetSceneFileName(nullptr);
  this->SetWeightsFile(nullptr);
  this->SetConfig(nullptr);
  this->SetSourceViews(nullptr);
  this->SetDevice(nullptr);
}

void vtkSIMPLIBuildMLI::ReleaseNetwork() {
  this->Internals->Builder.release();
}

int vtkSIMPLIBuildMLI::FillInputPortInformation(int port, vtkInformation* info) {
  if (port != 0)
    return 0;
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPartitionedDataSetCollection");
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

simpli::scene::Scene vtkSIMPLIBuildMLI::vtkInternals::ReadScene(vtkSIMPLIBuildMLI* self,
                                                                vtkInformationVector* input) {
  auto* collection = input->GetNumberOfInformationObjects() > 0
                         ? vtkPartitionedDataSetCollection::GetData(input, 0)
                         : nullptr;
  if (collection)
    return simpli::vtkscene::vtkToScene(collection, "Build MLI: input scene");
  if (str(self->SceneFileName).empty())
    simpli::fail("no scene: connect a scene (SIMPLI Scene Reader) to the input or set "
                 "SceneFileName to a scene folder");
  try {
    return simpli::scene::readScene(self->SceneFileName);
  } catch (const simpli::Error& e) {
    simpli::fail("SceneFileName '", self->SceneFileName, "': ", e.what());
  }
}

const simpli::network::LoadedNetwork&
vtkSIMPLIBuildMLI::vtkInternals::LoadNetwork(vtkSIMPLIBuildMLI* self) {
  simpli::vtkfilter::selectDevice(str(self->Device), "Device");
  simpli::generator::NetworkSource source;
  source.config = str(self->Config);
  source.weights = str(self->WeightsFile);
  if (self->RandomSeed >= 0)
    source.randomSeed = static_cast<uint64_t>(self->RandomSeed);
  try {
    const simpli::network::LoadedNetwork& loaded = this->Builder.network(source);
    const simpli::network::NetworkConfig& config = loaded.network->config();
    if (self->NumberOfPlanes != 0 && self->NumberOfPlanes != config.numPlanes)
      simpli::fail("NumberOfPlanes ", self->NumberOfPlanes, ": the network (config '", config.name,
                   "') was built for ", config.numPlanes,
                   " planes (the plane count is part of the trained network); use 0 or ",
                   config.numPlanes);
    if (self->CorrectionSteps > config.mliCorrections())
      simpli::fail("CorrectionSteps ", self->CorrectionSteps, ": config '", config.name, "' has ",
                   config.mliCorrections(), " MLI corrections (use -1 for all, or 0..",
                   config.mliCorrections(), ")");
    return loaded;
  } catch (const simpli::Error& e) {
    if (this->Builder.hasNetwork())
      throw; // loaded; a property does not fit it
    simpli::fail("network (WeightsFile '", source.weights, "', Config '", source.config,
                 "'): ", e.what());
  }
}

int vtkSIMPLIBuildMLI::RequestInformation(vtkInformation* vtkNotUsed(request),
                                          vtkInformationVector** vtkNotUsed(inputVector),
                                          vtkInformationVector* outputVector) {
  // Every piece is asked for (BuildPiece decides which one builds), not only piece 0.
  outputVector->GetInformationObject(0)->Set(vtkAlgorithm::CAN_HANDLE_PIECE_REQUEST(), 1);
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
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  using SDDP = vtkStreamingDemandDrivenPipeline;
  const int piece =
      outInfo->Has(SDDP::UPDATE_PIECE_NUMBER()) ? outInfo->Get(SDDP::UPDATE_PIECE_NUMBER()) : 0;
  const int pieces = outInfo->Has(SDDP::UPDATE_NUMBER_OF_PIECES())
                         ? outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES())
                         : 1;
  if (this->BuildPiece >= 0 && pieces > 1 && piece >= 0 && piece < pieces &&
      !simpli::parallel::ownsItem(static_cast<std::size_t>(this->BuildPiece), piece, pieces))
    return 1; // another piece builds the MLI
  using simpli::vtkfilter::Progress;
  return simpli::vtkfilter::runRequest(
      this, "SIMPLI Build MLI",
      [&](const Progress& progress) {
        const std::vector<int> requestedViews = parseViewList(str(this->SourceViews));
        std::vector<std::pair<std::string, double>> stages;
        progress(0.0);
        auto t0 = Clock::now();
        const simpli::scene::Scene scene = vtkInternals::ReadScene(this, inputVector[0]);
        stages.emplace_back("read_scene", msSince(t0));
        simpli::generator::MLIBuildOptions options;
        try {
          options.views = simpli::generator::sceneInputViews(scene, requestedViews);
        } catch (const simpli::Error& e) {
          simpli::fail("SourceViews '", str(this->SourceViews), "': ", e.what());
        }
        if (!progress(0.1))
          return; // aborted: empty output, no error

        t0 = Clock::now();
        const simpli::network::LoadedNetwork& loaded = this->Internals->LoadNetwork(this);
        stages.emplace_back("load_network", msSince(t0));
        if (!progress(0.2))
          return;

        options.depthRange = this->DepthRange == DEPTH_RANGE_SCENE
                                 ? simpli::generator::DepthRangeSource::Scene
                                 : simpli::generator::DepthRangeSource::Config;
        options.corrections = this->CorrectionSteps;
        options.inputScale = this->InputScale;
        static_assert(simpli::scene::maxReferenceMargin == 0.5, "ReferenceMargin's clamp");
        static_assert(simpli::scene::recommendedReferenceMargin == 0.06,
                      "ReferenceMargin's default (the header and the ParaView XML say 0.06)");
        options.referenceMargin = this->ReferenceMargin;
        const Progress pass = progress.range(0.2, 0.85);
        options.progress = [&pass](const std::string&, int done, int total) {
          return pass(static_cast<double>(done) / total);
        };
        simpli::generator::MLIBuild build;
        try {
          build = this->Internals->Builder.build(scene, options);
        } catch (const simpli::generator::GeneratorCancelled&) {
          vtkDebugMacro(<< "Aborted during the forward pass");
          return;
        }
        stages.insert(stages.end(), build.stageMs.begin(), build.stageMs.end());
        if (!progress(0.85))
          return;

        t0 = Clock::now();
        if (!vtkInternals::FillLayers(this, build.mli, output, progress.range(0.9, 1.0)))
          return;
        stages.emplace_back("meshes", msSince(t0));
        addBuildFieldData(output->GetFieldData(), stages, build.views, loaded.network->config(),
                          loaded.weightsDescription);
        output->GetFieldData()->AddArray(intValue("BuildPiece", piece));
        progress(1.0);
      },
      [output] { output->Initialize(); });
}

bool vtkSIMPLIBuildMLI::vtkInternals::FillLayers(vtkSIMPLIBuildMLI* self,
                                                 const simpli::mli::MLI& mli,
                                                 vtkPartitionedDataSetCollection* output,
                                                 const simpli::vtkfilter::Progress& progress) {
  simpli::vtkmli::LayerOptions layerOptions;
  layerOptions.dropTransparentTriangles = self->DropTransparentTriangles;
  layerOptions.alphaThreshold = self->EmptyLayerThreshold;
  layerOptions.meshMode = self->MeshMode == MESH_ADAPTIVE ? simpli::vtkmli::MeshMode::Adaptive
                                                          : simpli::vtkmli::MeshMode::PerTexel;
  layerOptions.meshTolerance = self->MeshTolerance;
  // "auto" layers; an MLI whose every layer is empty keeps them all (never an empty output).
  layerOptions.skipEmptyLayers =
      self->DropEmptyLayers &&
      simpli::mli::emptyLayers(mli, static_cast<float>(self->EmptyLayerThreshold)).size() <
          mli.layers.size();
  return simpli::vtkmli::mliToCollection(mli, layerOptions, output, progress);
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
  os << indent << "MeshMode: " << (this->MeshMode == MESH_ADAPTIVE ? "Adaptive" : "PerTexel")
     << "\n";
  os << indent << "MeshTolerance: " << this->MeshTolerance << "\n";
  os << indent << "NumberOfPlanes: " << this->NumberOfPlanes << "\n";
  os << indent << "CorrectionSteps: " << this->CorrectionSteps << "\n";
  os << indent << "InputScale: " << this->InputScale << "\n";
  os << indent << "ReferenceMargin: " << this->ReferenceMargin << "\n";
  os << indent << "SourceViews: " << (this->SourceViews ? this->SourceViews : "(all)") << "\n";
  os << indent << "DepthRange: " << (this->DepthRange == DEPTH_RANGE_SCENE ? "Scene" : "Config")
     << "\n";
  os << indent << "Device: " << (this->Device ? this->Device : "(current)") << "\n";
  os << indent << "RandomSeed: " << this->RandomSeed << "\n";
  os << indent << "BuildPiece: " << this->BuildPiece << "\n";
  os << indent << "NetworkLoaded: " << (this->Internals->Builder.hasNetwork() ? 1 : 0) << "\n";
}

#include "vtkSIMPLITrain.h"

#include "SIMPLIFilter.h"

#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkMath.h>
#include <vtkObjectFactory.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

#include "simpli/error.h"
#include "simpli/model/network/loader.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/data.h"
#include "simpli/model/training/trainer.h"

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSIMPLITrain);

namespace {

using simpli::vtkfilter::str;

vtkSmartPointer<vtkDoubleArray> doubleColumn(const std::string& name) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name.c_str());
  return a;
}

vtkSmartPointer<vtkIntArray> intValue(const char* name, long long value) {
  auto a = vtkSmartPointer<vtkIntArray>::New();
  a->SetName(name);
  a->InsertNextValue(static_cast<int>(value));
  return a;
}

// The output table: one row per training step (step, loss terms, total, lr, grad norm, time,
// skipped).
struct LossTable {
  vtkSmartPointer<vtkIntArray> step = vtkSmartPointer<vtkIntArray>::New();
  std::vector<vtkSmartPointer<vtkDoubleArray>> terms;
  vtkSmartPointer<vtkDoubleArray> total = doubleColumn("total"), lr = doubleColumn("lr"),
                                  gradNorm = doubleColumn("grad_norm"),
                                  ms = doubleColumn("step_ms");
  vtkSmartPointer<vtkIntArray> skipped = vtkSmartPointer<vtkIntArray>::New();

  LossTable() {
    step->SetName("step");
    skipped->SetName("skipped");
    for (const std::string& name : simpli::training::lossTermNames())
      terms.push_back(doubleColumn(name));
  }
  void append(const simpli::training::StepReport& r) {
    step->InsertNextValue(static_cast<int>(r.step));
    for (std::size_t i = 0; i < terms.size(); ++i)
      terms[i]->InsertNextValue(i < r.terms.size() ? r.terms[i].second : vtkMath::Nan());
    total->InsertNextValue(r.total);
    lr->InsertNextValue(r.lr);
    gradNorm->InsertNextValue(r.gradNorm);
    ms->InsertNextValue(r.ms);
    skipped->InsertNextValue(r.skipped ? 1 : 0);
  }
  void addTo(vtkTable* table) const {
    table->AddColumn(step);
    for (const auto& column : terms)
      table->AddColumn(column);
    table->AddColumn(total);
    table->AddColumn(lr);
    table->AddColumn(gradNorm);
    table->AddColumn(ms);
    table->AddColumn(skipped);
  }
};

// The training config of the Config property (null: a resumed run uses its own).
std::unique_ptr<simpli::training::TrainingConfig> configOf(const char* config, bool resume) {
  if (str(config).empty()) {
    if (!resume)
      simpli::fail("Config is not set: a new run needs a training config or a network config "
                   "(e.g. tiny); only a resumed run (Resume) uses its own config.json");
    return nullptr;
  }
  try {
    return std::make_unique<simpli::training::TrainingConfig>(
        simpli::training::resolveTrainingConfig(config));
  } catch (const simpli::Error& e) {
    const std::string what = e.what();
    // Messages from resolveConfig already name the property.
    if (what.rfind("Config '", 0) == 0)
      throw;
    simpli::fail("Config '", config, "': ", what);
  }
}

} // namespace

vtkSIMPLITrain::vtkSIMPLITrain() {
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

vtkSIMPLITrain::~vtkSIMPLITrain() {
  this->SetDataPath(nullptr);
  this->SetConfig(nullptr);
  this->SetRunDirectory(nullptr);
  this->SetVGGWeightsFile(nullptr);
  this->SetDevice(nullptr);
}

int vtkSIMPLITrain::RequestData(vtkInformation* vtkNotUsed(request),
                                vtkInformationVector** vtkNotUsed(inputVector),
                                vtkInformationVector* outputVector) {
  vtkTable* output = vtkTable::GetData(outputVector);
  if (!output) {
    vtkErrorMacro(<< "No vtkTable output to fill");
    return 0;
  }
  output->Initialize();
  // In parallel (pvbatch on K ranks, piece = rank) one run folder takes one trainer: piece 0
  // trains, the others leave an empty table (data-parallel training is mpiexec simpli train).
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) &&
      outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER()) > 0)
    return 1;
  const std::string what = "SIMPLI Train (RunDirectory '" + str(this->RunDirectory) + "')";
  return simpli::vtkfilter::runRequest(
      this, what,
      [&](const simpli::vtkfilter::Progress& progress) {
        if (str(this->DataPath).empty())
          simpli::fail(
              "DataPath is not set (a scene folder, a folder of scenes, or synthetic[:seed])");
        if (str(this->RunDirectory).empty())
          simpli::fail(
              "RunDirectory is not set (the run folder: new or empty, or the run to resume)");
        if (this->CheckpointEvery == 0)
          simpli::fail("CheckpointEvery 0: must be >= 1 (or -1 for the config's)");
        if ((this->ImageSize[0] > 0) != (this->ImageSize[1] > 0) || this->ImageSize[0] < 0 ||
            this->ImageSize[1] < 0)
          simpli::fail("ImageSize (", this->ImageSize[0], ", ", this->ImageSize[1],
                       "): give both width and height (> 0), or (0, 0) to keep the images' size");
        const std::unique_ptr<simpli::training::TrainingConfig> config =
            configOf(this->Config, this->Resume);
        simpli::vtkfilter::selectDevice(str(this->Device), "Device");

        LossTable table;
        auto messages = vtkSmartPointer<vtkStringArray>::New();
        messages->SetName("Messages");
        simpli::training::TrainerOptions options;
        options.data = {{this->DataPath}};
        options.runDir = this->RunDirectory;
        options.resume = this->Resume;
        options.steps = this->Steps;
        options.checkpointEvery = this->CheckpointEvery;
        options.vggPath = str(this->VGGWeightsFile);
        options.dataOptions.width = this->ImageSize[0];
        options.dataOptions.height = this->ImageSize[1];
        if (this->Seed >= 0)
          options.seed = static_cast<uint64_t>(this->Seed);
        // Polled between steps: the trainer then writes a checkpoint and returns.
        options.stopRequested = [&progress] { return progress.aborted(); };
        options.message = [this, messages](const std::string& line) {
          messages->InsertNextValue(line);
          vtkDebugMacro(<< line);
        };
        int64_t totalSteps = 1;
        options.onStep = [&](const simpli::training::StepReport& r) {
          table.append(r);
          progress(static_cast<double>(r.step) / static_cast<double>(totalSteps));
        };

        progress(0.0);
        simpli::training::Trainer trainer(config.get(), options);
        totalSteps = std::max<int64_t>(1, trainer.totalSteps());
        const simpli::training::Trainer::RunResult result = trainer.run();

        table.addTo(output);
        vtkFieldData* fd = output->GetFieldData();
        auto runDir = vtkSmartPointer<vtkStringArray>::New();
        runDir->SetName("RunDirectory");
        runDir->InsertNextValue(this->RunDirectory);
        fd->AddArray(runDir);
        fd->AddArray(messages);
        fd->AddArray(intValue("FinalStep", result.steps));
        fd->AddArray(intValue("TotalSteps", trainer.totalSteps()));
        fd->AddArray(intValue("Interrupted", result.interrupted ? 1 : 0));
        if (!result.interrupted)
          progress(1.0);
      },
      [output] { output->Initialize(); });
}

void vtkSIMPLITrain::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  auto s = [](const char* v) { return v ? v : "(none)"; };
  os << indent << "DataPath: " << s(this->DataPath) << "\n";
  os << indent << "Config: " << s(this->Config) << "\n";
  os << indent << "RunDirectory: " << s(this->RunDirectory) << "\n";
  os << indent << "Steps: " << this->Steps << "\n";
  os << indent << "CheckpointEvery: " << this->CheckpointEvery << "\n";
  os << indent << "Resume: " << this->Resume << "\n";
  os << indent << "VGGWeightsFile: " << s(this->VGGWeightsFile) << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "ImageSize: " << this->ImageSize[0] << " " << this->ImageSize[1] << "\n";
  os << indent << "Device: " << (this->Device ? this->Device : "(current)") << "\n";
}

// vtkSIMPLITrain: a few steps of the tiny config on datasets_small/synthetic/scene_00 (images
// resized small so that a step is quick), the loss table, the run folder, abort with a
// checkpoint that a resumed run reads, and bad input.
#include "vtkSIMPLITrain.h"

#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "mli_vtk_test_util.h"
#include "simpli/model/network/network.h"
#include "simpli/model/training/checkpoint.h"
#include "simpli/model/training/config.h"
#include "simpli/model/training/log.h"

namespace simpli::vtktest {
namespace {

const std::string kScene = std::string(SIMPLI_DATA_DIR) + "/synthetic/scene_00";

// Tiny config, scene_00 at 48 x 32 (W x H: multiples of 16), 3 steps.
void configure(vtkSIMPLITrain* t, const std::string& runDir) {
  t->SetDataPath(kScene.c_str());
  t->SetConfig("tiny");
  t->SetRunDirectory(runDir.c_str());
  t->SetSteps(3);
  t->SetCheckpointEvery(10);
  t->SetSeed(5);
  t->SetImageSize(48, 32);
}

vtkTable* tableOf(vtkAlgorithm* t) {
  return vtkTable::SafeDownCast(t->GetOutputDataObject(0));
}

double fieldValue(vtkTable* table, const char* name) {
  vtkDataArray* a = table->GetFieldData()->GetArray(name);
  return a ? a->GetComponent(0, 0) : NAN;
}

TEST(Train, ThreeStepsGiveATableAndACheckpoint) {
  TempDir tmp;
  const std::string run = tmp / "run";
  vtkNew<vtkSIMPLITrain> t;
  configure(t, run);
  vtkNew<ErrorRecorder> errors;
  ASSERT_EQ(runWithErrors(t, errors), 1) << errors->all();
  vtkTable* table = tableOf(t);
  ASSERT_EQ(table->GetNumberOfRows(), 3);
  const std::vector<std::string>& terms = training::lossTermNames();
  ASSERT_EQ(table->GetNumberOfColumns(), vtkIdType(terms.size() + 6));
  vtkDataArray* step = vtkDataArray::SafeDownCast(table->GetColumnByName("step"));
  ASSERT_NE(step, nullptr);
  for (vtkIdType r = 0; r < 3; ++r)
    EXPECT_EQ(step->GetComponent(r, 0), r + 1);
  for (const char* name : {"total", "lr", "grad_norm", "step_ms", "l1"}) {
    vtkDataArray* c = vtkDataArray::SafeDownCast(table->GetColumnByName(name));
    ASSERT_NE(c, nullptr) << name;
    for (vtkIdType r = 0; r < 3; ++r)
      EXPECT_TRUE(std::isfinite(c->GetComponent(r, 0))) << name << " row " << r;
  }
  EXPECT_GT(vtkDataArray::SafeDownCast(table->GetColumnByName("total"))->GetComponent(0, 0), 0.0);
  for (const std::string& term : terms)
    EXPECT_NE(table->GetColumnByName(term.c_str()), nullptr) << term;
  EXPECT_EQ(fieldValue(table, "FinalStep"), 3);
  EXPECT_EQ(fieldValue(table, "TotalSteps"), 3);
  EXPECT_EQ(fieldValue(table, "Interrupted"), 0);

  // The run folder: the final checkpoint, the weights, the log with the same rows.
  const auto latest = training::latestCheckpoint(run);
  ASSERT_TRUE(latest.has_value());
  EXPECT_EQ(fs::path(*latest).filename(), "step_00000003");
  EXPECT_TRUE(fs::exists(fs::path(run) / "weights.safetensors"));
  std::vector<std::string> header;
  const auto rows = training::TrainLog::read((fs::path(run) / "log.csv").string(), &header);
  ASSERT_EQ(rows.size(), 3u);
  // (log.csv leaves out the terms that are off and not in the reference: find "total".)
  const auto total = std::find(header.begin(), header.end(), "total");
  ASSERT_NE(total, header.end());
  vtkDataArray* totals = vtkDataArray::SafeDownCast(table->GetColumnByName("total"));
  EXPECT_EQ(rows[2][size_t(total - header.begin())], totals->GetComponent(2, 0));

  // Running again into the same folder without Resume is an error naming the folder...
  t->Modified();
  ASSERT_EQ(runWithErrors(t, errors), 0);
  EXPECT_TRUE(errors->has({"SIMPLI Train", run})) << errors->all();
  // ...with Resume and more steps it continues from step 3.
  t->ResumeOn();
  t->SetSteps(4);
  ASSERT_EQ(runWithErrors(t, errors), 1) << errors->all();
  ASSERT_EQ(tableOf(t)->GetNumberOfRows(), 1);
  EXPECT_EQ(vtkDataArray::SafeDownCast(tableOf(t)->GetColumnByName("step"))->GetComponent(0, 0), 4);
}

// Piece 1 of 2 (another pvbatch rank) does not train: an empty table, no run folder.
TEST(Train, OnlyPieceZeroTrains) {
  TempDir tmp;
  const std::string run = tmp / "run";
  vtkNew<vtkSIMPLITrain> t;
  configure(t, run);
  t->SetSteps(1);
  t->UpdatePiece(1, 2, 0);
  EXPECT_EQ(tableOf(t)->GetNumberOfRows(), 0);
  EXPECT_FALSE(fs::exists(run));
  t->UpdatePiece(0, 2, 0);
  EXPECT_EQ(tableOf(t)->GetNumberOfRows(), 1);
  EXPECT_TRUE(fs::exists(fs::path(run) / "weights.safetensors"));
}

class AbortAfterFirstStep : public vtkCommand {
public:
  static AbortAfterFirstStep* New() { return new AbortAfterFirstStep; }
  void Execute(vtkObject* caller, unsigned long, void* data) override {
    const double p = *static_cast<double*>(data);
    if (p > 0.0 && p < 1.0)
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
  }
};

TEST(Train, AbortAfterTheFirstStepLeavesAReadableCheckpoint) {
  TempDir tmp;
  const std::string run = tmp / "run";
  vtkNew<vtkSIMPLITrain> t;
  configure(t, run);
  t->SetSteps(5);
  vtkNew<AbortAfterFirstStep> abort; // progress 1/5 after step 1
  t->AddObserver(vtkCommand::ProgressEvent, abort);
  vtkNew<ErrorRecorder> errors;
  ASSERT_EQ(runWithErrors(t, errors), 1) << errors->all();
  vtkTable* table = tableOf(t);
  EXPECT_EQ(table->GetNumberOfRows(), 1);
  EXPECT_EQ(fieldValue(table, "Interrupted"), 1);
  EXPECT_EQ(fieldValue(table, "FinalStep"), 1);

  const auto latest = training::latestCheckpoint(run);
  ASSERT_TRUE(latest.has_value());
  EXPECT_EQ(fs::path(*latest).filename(), "step_00000001");
  // Readable: a network of the run's config loads it completely.
  const training::TrainingConfig config =
      training::loadTrainingConfig((fs::path(run) / "config.json").string());
  network::SimpliNetwork network(config.network);
  const training::CheckpointData data = training::readCheckpoint(*latest, network.parameters());
  EXPECT_EQ(data.step, 1);
  // No temporaries left behind.
  for (const std::string& name : listDir(fs::path(run) / "checkpoints"))
    EXPECT_EQ(name.rfind(".tmp", 0), std::string::npos) << name;
}

TEST(Train, ANetworkConfigFileTrainsWithTheDefaultSettings) {
  TempDir tmp;
  vtkNew<vtkSIMPLITrain> t;
  configure(t, tmp / "run");
  // A network config (not a training config): the default training settings around it.
  const std::string network = std::string(SIMPLI_SOURCE_DIR) + "/model/configs/tiny.json";
  t->SetConfig(network.c_str());
  t->SetSteps(1);
  vtkNew<ErrorRecorder> errors;
  ASSERT_EQ(runWithErrors(t, errors), 1) << errors->all();
  EXPECT_EQ(tableOf(t)->GetNumberOfRows(), 1);
  const training::TrainingConfig saved =
      training::loadTrainingConfig((fs::path(tmp.path()) / "run" / "config.json").string());
  EXPECT_EQ(saved.network.name, "tiny");
  EXPECT_EQ(saved.optimizer.lr,
            training::TrainingConfig().optimizer.lr); // not tiny's training 1e-3
}

TEST(Train, BadInputFailsWithAClearMessage) {
  TempDir tmp;
  vtkNew<vtkSIMPLITrain> t;
  configure(t, tmp / "run");
  vtkNew<ErrorRecorder> errors;

  t->SetDataPath((kScene + "/no_such").c_str());
  EXPECT_EQ(runWithErrors(t, errors), 0);
  EXPECT_TRUE(errors->has({"no_such"})) << errors->all();
  EXPECT_EQ(tableOf(t)->GetNumberOfRows(), 0);
  t->SetDataPath(nullptr);
  EXPECT_EQ(runWithErrors(t, errors), 0);
  EXPECT_TRUE(errors->has({"DataPath is not set"})) << errors->all();
  t->SetDataPath(kScene.c_str());

  t->SetConfig("no_such_config");
  EXPECT_EQ(runWithErrors(t, errors), 0);
  EXPECT_TRUE(errors->has({"Config 'no_such_config'"})) << errors->all();
  const std::string bad = tmp / "bad.json";
  writeText(bad, R"({"network": "official-4l", "steps": -4})");
  t->SetConfig(bad.c_str());
  EXPECT_EQ(runWithErrors(t, errors), 0);
  EXPECT_TRUE(errors->has({"Config '" + bad + "'", "steps"})) << errors->all();
  t->SetConfig(nullptr);
  EXPECT_EQ(runWithErrors(t, errors), 0);
  EXPECT_TRUE(errors->has({"Config is not set"})) << errors->all();
  t->SetConfig("tiny");

  t->SetRunDirectory(nullptr);
  EXPECT_EQ(runWithErrors(t, errors), 0);
  EXPECT_TRUE(errors->has({"RunDirectory is not set"})) << errors->all();
  t->SetRunDirectory((tmp / "run2").c_str());
  t->SetImageSize(64, 0);
  EXPECT_EQ(runWithErrors(t, errors), 0);
  EXPECT_TRUE(errors->has({"ImageSize (64, 0)"})) << errors->all();
  EXPECT_FALSE(fs::exists(tmp / "run2")) << "a failed request must not create the run";
}

} // namespace
} // namespace simpli::vtktest

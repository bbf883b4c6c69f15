/**
 * @class   vtkSIMPLITrain
 * @brief   trains a SIMPLI network (simpli/model/training/trainer.h); outputs the loss log
 *
 * A source: RequestData runs the trainer (as `simpli train` does) and returns one table row
 * per step done in this update.
 *
 * Properties:
 *   - DataPath: a scene folder, a folder of scene folders, or "synthetic[:seed]" (procedural
 *     scenes generated in memory).
 *   - Config: a training config JSON file (see simpli/model/training/train_config.h), or a
 *     network config (a name such as "tiny" / "official-4l", or a network JSON file) trained
 *     with the default training settings. A name for which <config dir>/training/<name>.json
 *     exists (the shipped training configs, e.g. "tiny") takes that training config. May be
 *     empty with Resume (the run's own config.json).
 *   - RunDirectory: the run folder (new or empty; with Resume the run to continue). It receives
 *     config.json, log.csv, weights.safetensors and checkpoints/step_NNNNNNNN (atomic).
 *   - Steps (total steps of the run) and CheckpointEvery: -1 = the config's.
 *   - Resume: continue the run in RunDirectory from its newest checkpoint.
 *   - VGGWeightsFile: VGG-19 weights for the perceptual loss; empty = off.
 *   - Seed: -1 = the config's; >= 0 overrides it (a new run only).
 *   - ImageSize: (width, height) to resize the training images to; (0, 0) = keep.
 *   - Device: OpenCL device "platform:device"; empty = the current device.
 *
 * Output: a vtkTable, one row per step: "step" (int), every loss term (double, named as in
 * log.csv: l1, perceptual, intermediate_loss_0_l1, ..., smooth_layers; NaN when the term is
 * off), "total", "lr", "grad_norm", "step_ms" (double) and "skipped" (int: 1 when the step had
 * non-finite gradients and made no update). Field data: "RunDirectory", "Messages" (the
 * trainer's lines), "FinalStep" (int), "TotalSteps" (int) and "Interrupted" (int).
 *
 * Pieces: only piece 0 trains (a run folder takes one trainer); other pieces (the other ranks of
 * pvbatch / pvserver) produce an empty table. To train over several ranks, run
 * `mpiexec -n K simpli train` (data-parallel, see docs/parallel.md).
 *
 * Progress: step / total steps, reported after every step. An abort (SetAbortExecute, e.g.
 * from a progress observer) stops the run after the current step with a complete checkpoint
 * (the trainer writes checkpoints atomically: never a half-written file); the table then holds
 * the steps done and Interrupted is 1. Errors (missing data, bad config field, run folder not
 * empty without Resume, ...) are reported with vtkErrorMacro naming the property, file and
 * field; the request fails with an empty table.
 */

#ifndef vtkSIMPLITrain_h
#define vtkSIMPLITrain_h

#include "vtkSimpliFiltersModule.h" // for export macro
#include <vtkTableAlgorithm.h>

class VTKSIMPLIFILTERS_EXPORT vtkSIMPLITrain : public vtkTableAlgorithm {
public:
  static vtkSIMPLITrain* New();
  vtkTypeMacro(vtkSIMPLITrain, vtkTableAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Training data: a scene folder, a folder of scenes, or "synthetic[:seed]".
   */
  vtkSetStringMacro(DataPath);
  vtkGetStringMacro(DataPath);
  ///@}

  ///@{
  /**
   * A training config JSON file, or a network config name / JSON file (see the class
   * description); empty with Resume = the run's config.json.
   */
  vtkSetStringMacro(Config);
  vtkGetStringMacro(Config);
  ///@}

  ///@{
  /**
   * The run folder.
   */
  vtkSetStringMacro(RunDirectory);
  vtkGetStringMacro(RunDirectory);
  ///@}

  ///@{
  /**
   * Total steps of the run; -1 = the config's (default).
   */
  vtkSetClampMacro(Steps, int, -1, VTK_INT_MAX);
  vtkGetMacro(Steps, int);
  ///@}

  ///@{
  /**
   * Steps between checkpoints (>= 1); -1 = the config's (default).
   */
  vtkSetClampMacro(CheckpointEvery, int, -1, VTK_INT_MAX);
  vtkGetMacro(CheckpointEvery, int);
  ///@}

  ///@{
  /**
   * Continue the run in RunDirectory from its newest checkpoint. Default off.
   */
  vtkSetMacro(Resume, bool);
  vtkGetMacro(Resume, bool);
  vtkBooleanMacro(Resume, bool);
  ///@}

  ///@{
  /**
   * VGG-19 weights (.safetensors) for the perceptual loss; empty = off.
   */
  vtkSetStringMacro(VGGWeightsFile);
  vtkGetStringMacro(VGGWeightsFile);
  ///@}

  ///@{
  /**
   * Seed of the network initialisation and sampling; -1 = the config's (default).
   */
  vtkSetClampMacro(Seed, int, -1, VTK_INT_MAX);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /**
   * Resize the training images to (width, height); (0, 0) = keep (default).
   */
  vtkSetVector2Macro(ImageSize, int);
  vtkGetVector2Macro(ImageSize, int);
  ///@}

  ///@{
  /**
   * OpenCL device "platform:device"; empty = the current device.
   */
  vtkSetStringMacro(Device);
  vtkGetStringMacro(Device);
  ///@}

protected:
  vtkSIMPLITrain();
  ~vtkSIMPLITrain() override;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  char* DataPath = nullptr;
  char* Config = nullptr;
  char* RunDirectory = nullptr;
  int Steps = -1;
  int CheckpointEvery = -1;
  bool Resume = false;
  char* VGGWeightsFile = nullptr;
  int Seed = -1;
  int ImageSize[2] = {0, 0};
  char* Device = nullptr;

private:
  vtkSIMPLITrain(const vtkSIMPLITrain&) = delete;
  void operator=(const vtkSIMPLITrain&) = delete;
};

#endif

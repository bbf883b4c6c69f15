// vtkSIMPLIBuildMLI on datasets_small/synthetic/scene_00 with the tiny config and random
// weights (RandomSeed): layout, agreement with running the generator directly, auto layers,
// input-connection mode, the cached network, bad input and abort. Also the scene collection ->
// simpli::Scene conversion (vtkToScene) the input mode relies on, round-tripped through
// vtkSIMPLISceneReader.
#include "SIMPLIMLIToVTK.h"
#include "SIMPLISceneToVTK.h"
#include "vtkSIMPLIBuildMLI.h"
#include "vtkSIMPLISceneReader.h"

#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mli_vtk_test_util.h"
#include "simpli/error.h"
#include "simpli/model/generator/generator.h"
#include "simpli/model/generator/scene_input.h"
#include "simpli/model/mli/mli.h"
#include "simpli/model/network/loader.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/scene/scene.h"
#include "simpli/ocl/autograd.h"

namespace simpli::vtktest {
namespace {

const std::string kScene = std::string(SIMPLI_DATA_DIR) + "/synthetic/scene_00";
constexpr int kSeed = 11;
// Two source views and one MLI correction keep a forward pass at a few seconds on 2 CPU cores.
const char* kViews = "0,6";
constexpr int kCorrections = 1;

// A filter set up for the scene folder, the tiny config and random weights.
void configure(vtkSIMPLIBuildMLI* f) {
  f->SetSceneFileName(kScene.c_str());
  f->SetConfig("tiny");
  f->SetRandomSeed(kSeed);
  f->SetSourceViews(kViews);
  f->SetCorrectionSteps(kCorrections);
}

vtkPartitionedDataSetCollection* outputOf(vtkAlgorithm* f) {
  return vtkPartitionedDataSetCollection::SafeDownCast(f->GetOutputDataObject(0));
}

// What the filter must reproduce: the generator run directly (same seed, same views).
struct Direct {
  generator::GeneratorOutput output;
  generator::GeneratorInput input;
  mli::MLI mli;
};

const Direct& direct() {
  static const Direct d = [] {
    Direct out;
    const scene::Scene scene = scene::readScene(kScene);
    const network::LoadedNetwork loaded = network::loadNetwork("tiny", "", uint64_t(kSeed));
    generator::SceneInputOptions o;
    o.views = {0, 6};
    o.referenceMargin = scene::recommendedReferenceMargin; // the filter's default
    out.input = generator::sceneInput(scene, o);
    generator::GeneratorOptions options;
    options.corrections = kCorrections;
    ocl::NoGradGuard noGrad;
    out.output = generator::Generator(*loaded.network).forward(out.input, options);
    out.mli = generator::toMLI(out.output, out.input.reference);
    return out;
  }();
  return d;
}

vtkPolyData* layer(vtkPartitionedDataSetCollection* c, unsigned int i) {
  vtkPartitionedDataSet* pds = c->GetPartitionedDataSet(i);
  return pds ? vtkPolyData::SafeDownCast(pds->GetPartition(0)) : nullptr;
}

// Largest |difference| between layer `pd` and layer k of `mli` (Color, Alpha, Depth).
double layerDifference(vtkPolyData* pd, const mli::MLI& mli, int k) {
  const mli::MLILayer& want = mli.layers[static_cast<std::size_t>(k)];
  auto* color = vtkFloatArray::SafeDownCast(pd->GetPointData()->GetArray("Color"));
  auto* alpha = vtkFloatArray::SafeDownCast(pd->GetPointData()->GetArray("Alpha"));
  auto* depth = vtkFloatArray::SafeDownCast(pd->GetPointData()->GetArray("Depth"));
  if (!color || !alpha || !depth || pd->GetNumberOfPoints() != vtkIdType(mli.texels()))
    return HUGE_VAL;
  double worst = 0;
  for (std::size_t p = 0; p < mli.texels(); ++p) {
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::abs(double(color->GetTypedComponent(vtkIdType(p), c)) -
                                       want.rgba[4 * p + c]));
    worst = std::max(worst, std::abs(double(alpha->GetValue(vtkIdType(p))) - want.rgba[4 * p + 3]));
    worst = std::max(worst, std::abs(double(depth->GetValue(vtkIdType(p))) - want.depth[p]));
  }
  return worst;
}

std::vector<std::string> stringValues(vtkFieldData* fd, const char* name) {
  std::vector<std::string> out;
  auto* a = vtkStringArray::SafeDownCast(fd->GetAbstractArray(name));
  for (vtkIdType i = 0; a && i < a->GetNumberOfValues(); ++i)
    out.push_back(a->GetValue(i));
  return out;
}

// --- vtkToScene ----------------------------------------------------------------------------------

TEST(SceneToVTK, RoundTripsTheSceneReader) {
  const scene::Scene want = scene::readScene(kScene);
  vtkNew<vtkSIMPLISceneReader> reader;
  reader->SetFileName(kScene.c_str());
  reader->Update();
  const scene::Scene got = vtkscene::vtkToScene(outputOf(reader), "test scene");
  ASSERT_EQ(got.size(), want.size());
  EXPECT_EQ(got.near, want.near);
  EXPECT_EQ(got.far, want.far);
  EXPECT_EQ(got.format, want.format);
  EXPECT_EQ(got.normalisation.scale, want.normalisation.scale);
  for (std::size_t v = 0; v < want.size(); ++v) {
    SCOPED_TRACE("view " + std::to_string(v));
    EXPECT_EQ(got.views[v].name, want.views[v].name);
    EXPECT_EQ(got.views[v].imagePath, want.views[v].imagePath);
    const scene::Camera &a = got.views[v].camera, &b = want.views[v].camera;
    EXPECT_EQ(a.R, b.R);
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.fx, b.fx);
    EXPECT_EQ(a.fy, b.fy);
    EXPECT_EQ(a.cx, b.cx);
    EXPECT_EQ(a.cy, b.cy);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    // 8-bit images without a resize come back bit for bit.
    ASSERT_EQ(got.views[v].image.width, want.views[v].image.width);
    ASSERT_EQ(got.views[v].image.height, want.views[v].image.height);
    EXPECT_TRUE(got.views[v].image.data == want.views[v].image.data);
  }
}

TEST(SceneToVTK, RejectsBadCollections) {
  vtkNew<vtkSIMPLISceneReader> reader;
  reader->SetFileName(kScene.c_str());
  reader->Update();
  vtkNew<vtkPartitionedDataSetCollection> scene;
  scene->DeepCopy(outputOf(reader));

  auto expectError = [&](const std::vector<std::string>& parts) {
    try {
      vtkscene::vtkToScene(scene, "test scene");
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      const std::string what = e.what();
      for (const auto& p : parts)
        EXPECT_NE(what.find(p), std::string::npos) << what;
    }
  };
  // An image whose size disagrees with its camera.
  vtkImageData* view3 =
      vtkImageData::SafeDownCast(scene->GetPartitionedDataSet(3)->GetPartition(0));
  auto* size = view3->GetFieldData()->GetArray("CameraImageSize");
  size->SetComponent(0, 0, 100);
  expectError({"test scene", "view 3", "CameraImageSize", "100"});
  size->SetComponent(0, 0, 192);
  // A view without RGB pixels.
  view3->GetPointData()->RemoveArray("RGB");
  expectError({"view 3", "RGB", "missing"});
  // No bounds.
  scene->GetFieldData()->RemoveArray("NearFar");
  expectError({"NearFar", "missing"});
  EXPECT_THROW(vtkscene::vtkToScene(nullptr, "x"), Error);
}

// --- Build MLI -----------------------------------------------------------------------------------

TEST(BuildMLI, MatchesTheGeneratorRunDirectly) {
  vtkNew<vtkSIMPLIBuildMLI> f;
  configure(f);
  vtkNew<ErrorRecorder> errors;
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  vtkPartitionedDataSetCollection* out = outputOf(f);
  const Direct& d = direct();
  const int L = 4; // the tiny config's layers
  ASSERT_EQ(d.mli.numLayers(), L);
  ASSERT_EQ(out->GetNumberOfPartitionedDataSets(), unsigned(L));
  for (int k = 0; k < L; ++k) {
    SCOPED_TRACE("layer " + std::to_string(k));
    vtkPolyData* pd = layer(out, unsigned(k));
    ASSERT_NE(pd, nullptr);
    EXPECT_EQ(pd->GetNumberOfPoints(), 192 * 128);
    EXPECT_EQ(pd->GetNumberOfPolys(), 2 * 191 * 127);
    auto* rgba = vtkUnsignedCharArray::SafeDownCast(pd->GetPointData()->GetScalars());
    ASSERT_NE(rgba, nullptr);
    EXPECT_STREQ(rgba->GetName(), "RGBA");
    EXPECT_EQ(rgba->GetNumberOfComponents(), 4);
    ASSERT_NE(pd->GetPointData()->GetArray("Depth"), nullptr);
    EXPECT_LE(layerDifference(pd, d.mli, k), 1e-6);
    EXPECT_EQ(pd->GetFieldData()->GetArray("LayerIndex")->GetComponent(0, 0), k);
  }
  // The reference camera (the sources' pose average) in the field data.
  vtkFieldData* fd = out->GetFieldData();
  ASSERT_NE(fd->GetArray("CameraExtrinsics"), nullptr);
  double e[12];
  fd->GetArray("CameraExtrinsics")->GetTuple(0, e);
  for (int r = 0; r < 3; ++r)
    EXPECT_NEAR(e[4 * r + 3], d.input.reference.t(r), 0.0);
  EXPECT_EQ(fd->GetArray("CameraImageSize")->GetComponent(0, 0), 192);
  EXPECT_EQ(fd->GetArray("NumberOfLayers")->GetComponent(0, 0), L);
  EXPECT_EQ(fd->GetArray("NumberOfPlanes")->GetComponent(0, 0), 17);
  EXPECT_EQ(stringValues(fd, "NetworkConfig"), std::vector<std::string>{"tiny"});
  auto* views = fd->GetArray("SourceViews");
  ASSERT_NE(views, nullptr);
  ASSERT_EQ(views->GetNumberOfTuples(), 2);
  EXPECT_EQ(views->GetComponent(1, 0), 6);
  // Stage times: ours around the generator's.
  const std::vector<std::string> names = stringValues(fd, "StageNames");
  auto* times = fd->GetArray("StageTimes");
  ASSERT_NE(times, nullptr);
  ASSERT_EQ(times->GetNumberOfTuples(), vtkIdType(names.size()));
  ASSERT_EQ(names.size(), d.output.stageMs.size() + 4) << errors->all();
  EXPECT_EQ(names.front(), "read_scene");
  EXPECT_EQ(names[1], "load_network");
  EXPECT_EQ(names.back(), "meshes");
  for (vtkIdType i = 0; i < times->GetNumberOfTuples(); ++i)
    EXPECT_GE(times->GetComponent(i, 0), 0.0);
}

TEST(BuildMLI, AutoLayersAndMeshOptionsReuseTheForwardPass) {
  // A threshold between the layers' largest alphas drops some layers and keeps others.
  const mli::MLI& mli = direct().mli;
  std::vector<float> maxAlpha;
  for (const mli::MLILayer& l : mli.layers) {
    float m = 0;
    for (std::size_t p = 0; p < mli.texels(); ++p)
      m = std::max(m, l.rgba[4 * p + 3]);
    maxAlpha.push_back(m);
  }
  std::vector<float> sorted = maxAlpha;
  std::sort(sorted.begin(), sorted.end());
  ASSERT_LT(sorted.front(), sorted.back()) << "every layer has the same largest alpha";
  const double threshold = 0.5 * (double(sorted.front()) + sorted.back());
  std::vector<int> kept;
  for (int k = 0; k < mli.numLayers(); ++k)
    if (maxAlpha[std::size_t(k)] >= threshold)
      kept.push_back(k);
  ASSERT_EQ(int(kept.size()), generator::toMLI(direct().output, direct().input.reference,
                                               static_cast<float>(threshold))
                                  .numLayers());

  vtkNew<vtkSIMPLIBuildMLI> f;
  configure(f);
  f->DropEmptyLayersOn();
  f->SetEmptyLayerThreshold(threshold);
  vtkNew<ErrorRecorder> errors;
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  vtkPartitionedDataSetCollection* out = outputOf(f);
  ASSERT_EQ(out->GetNumberOfPartitionedDataSets(), kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    vtkPolyData* pd = layer(out, unsigned(i));
    ASSERT_NE(pd, nullptr);
    EXPECT_EQ(pd->GetFieldData()->GetArray("LayerIndex")->GetComponent(0, 0), kept[i]);
    EXPECT_LE(layerDifference(pd, mli, kept[i]), 1e-6);
  }
  EXPECT_EQ(out->GetFieldData()->GetArray("NumberOfLayers")->GetComponent(0, 0), 4);
  const std::vector<std::string> ran = stringValues(out->GetFieldData(), "StageNames");
  EXPECT_NE(std::find(ran.begin(), ran.end(), "features"), ran.end());

  // Above every layer's alpha: all are kept (an MLI is never empty). Only the layer options
  // changed: the last forward pass is reused.
  f->SetEmptyLayerThreshold(1.0);
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  EXPECT_EQ(outputOf(f)->GetNumberOfPartitionedDataSets(), 4u);
  const std::vector<std::string> reused = stringValues(outputOf(f)->GetFieldData(), "StageNames");
  EXPECT_EQ(reused,
            (std::vector<std::string>{"read_scene", "load_network", "forward_reused", "meshes"}));
  for (unsigned int k = 0; k < 4; ++k)
    EXPECT_EQ(layerDifference(layer(outputOf(f), k), mli, int(k)), 0.0) << "layer " << k;
  // Transparent triangles dropped: fewer triangles, the same points.
  f->DropTransparentTrianglesOn();
  f->SetEmptyLayerThreshold(threshold);
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  vtkPolyData* pd = layer(outputOf(f), 0);
  ASSERT_NE(pd, nullptr);
  EXPECT_EQ(pd->GetNumberOfPoints(), 192 * 128);
  EXPECT_LT(pd->GetNumberOfPolys(), 2 * 191 * 127);
  // Adaptive meshes: also without rerunning the network; the texels travel in the field data.
  f->SetMeshMode(vtkSIMPLIBuildMLI::MESH_ADAPTIVE);
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  EXPECT_EQ(stringValues(outputOf(f)->GetFieldData(), "StageNames"), reused);
  pd = layer(outputOf(f), 0);
  ASSERT_NE(pd, nullptr);
  EXPECT_LT(pd->GetNumberOfPolys(), 191 * 127);
  ASSERT_NE(pd->GetFieldData()->GetArray("TextureDepth"), nullptr);
  EXPECT_EQ(pd->GetFieldData()->GetArray("TextureDepth")->GetNumberOfTuples(), 192 * 128);
  f->SetMeshMode(vtkSIMPLIBuildMLI::MESH_PER_TEXEL);
  // A different source view list runs the network again.
  f->SetSourceViews("0,5");
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  const std::vector<std::string> again = stringValues(outputOf(f)->GetFieldData(), "StageNames");
  EXPECT_EQ(std::find(again.begin(), again.end(), "forward_reused"), again.end());
}

TEST(BuildMLI, InputConnectionEqualsSceneFolder) {
  vtkNew<vtkSIMPLISceneReader> reader;
  reader->SetFileName(kScene.c_str());
  vtkNew<vtkSIMPLIBuildMLI> f;
  configure(f);
  f->SetSceneFileName("/no/such/folder"); // ignored: the input wins
  f->SetInputConnection(reader->GetOutputPort(0));
  vtkNew<ErrorRecorder> errors;
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  vtkPartitionedDataSetCollection* out = outputOf(f);
  ASSERT_EQ(out->GetNumberOfPartitionedDataSets(), 4u);
  for (unsigned int k = 0; k < 4; ++k)
    EXPECT_EQ(layerDifference(layer(out, k), direct().mli, int(k)), 0.0) << "layer " << k;
}

TEST(BuildMLI, FewerCorrectionsAndTheSceneDepthRange) {
  vtkNew<vtkSIMPLIBuildMLI> f;
  configure(f);
  f->SetCorrectionSteps(0); // the level-1 layers, at scale_lvl1 = half resolution
  vtkNew<ErrorRecorder> errors;
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  vtkPolyData* pd = layer(outputOf(f), 0);
  ASSERT_NE(pd, nullptr);
  EXPECT_EQ(pd->GetNumberOfPoints(), 96 * 64);

  // Planes between the scene's bounds: every depth lies within them.
  f->SetCorrectionSteps(kCorrections);
  f->SetDepthRange(vtkSIMPLIBuildMLI::DEPTH_RANGE_SCENE);
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  const scene::Scene scene = scene::readScene(kScene);
  double lo = HUGE_VAL, hi = 0;
  for (unsigned int k = 0; k < outputOf(f)->GetNumberOfPartitionedDataSets(); ++k) {
    double r[2];
    layer(outputOf(f), k)->GetPointData()->GetArray("Depth")->GetRange(r);
    lo = std::min(lo, r[0]);
    hi = std::max(hi, r[1]);
  }
  EXPECT_GE(lo, scene.near * (1 - 1e-4));
  EXPECT_LE(hi, scene.far * (1 + 1e-4));
  EXPECT_LT(hi, 100.0 * 0.5); // not the config's 1..100
}

// InputScale 0.5: the 192x128 sources go in at 96x64 and so does the MLI (one point per texel);
// back at 1 the output is the direct pass again (the cached pass is not reused across scales).
TEST(BuildMLI, InputScaleBuildsTheMLIAtThatSize) {
  vtkNew<vtkSIMPLIBuildMLI> f;
  configure(f);
  f->SetInputScale(0.5);
  vtkNew<ErrorRecorder> errors;
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  vtkPolyData* half = layer(outputOf(f), 0);
  ASSERT_NE(half, nullptr);
  EXPECT_EQ(half->GetNumberOfPoints(), 96 * 64);
  f->SetInputScale(1.0);
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  vtkPolyData* full = layer(outputOf(f), 0);
  ASSERT_NE(full, nullptr);
  EXPECT_EQ(full->GetNumberOfPoints(), 192 * 128);
  EXPECT_EQ(layerDifference(full, direct().mli, 0), 0.0);
  f->SetInputScale(100.0); // clamped, like every VTK range property
  EXPECT_EQ(f->GetInputScale(), 2.0);
}

// ReferenceMargin widens the MLI's camera on the same texel grid (a new forward pass: the cached
// one belongs to another frame); the default is the recommended margin, 0 the reference's frame.
TEST(BuildMLI, ReferenceMarginWidensTheMLIFrame) {
  vtkNew<vtkSIMPLIBuildMLI> f;
  configure(f);
  EXPECT_EQ(f->GetReferenceMargin(), scene::recommendedReferenceMargin);
  vtkNew<ErrorRecorder> errors;
  auto camera = [&](double margin) {
    f->SetReferenceMargin(margin);
    EXPECT_EQ(runWithErrors(f, errors), 1) << errors->all();
    EXPECT_EQ(layer(outputOf(f), 0)->GetNumberOfPoints(), 192 * 128);
    return vtkmli::cameraFromFieldData(outputOf(f)->GetFieldData(), "BuildMLI output");
  };
  const scene::Camera narrow = camera(0.0);
  EXPECT_GT(layerDifference(layer(outputOf(f), 0), direct().mli, 0), 1e-3);
  for (double margin : {scene::recommendedReferenceMargin, 0.25}) {
    const scene::Camera wide = camera(margin);
    const scene::Camera expected = scene::widenedCamera(narrow, margin);
    EXPECT_NEAR(wide.fx, expected.fx, 1e-12) << margin;
    EXPECT_NEAR(wide.cy, expected.cy, 1e-12) << margin;
    EXPECT_TRUE(wide.R.isApprox(narrow.R, 1e-12));
    EXPECT_EQ(wide.width, narrow.width);
  }
  camera(scene::recommendedReferenceMargin);
  EXPECT_EQ(layerDifference(layer(outputOf(f), 0), direct().mli, 0), 0.0);
  f->SetReferenceMargin(2.0); // clamped
  EXPECT_EQ(f->GetReferenceMargin(), 0.5);
}

TEST(BuildMLI, ANewSeedReloadsTheNetwork) {
  vtkNew<vtkSIMPLIBuildMLI> f;
  configure(f);
  f->Update();
  vtkNew<vtkPartitionedDataSetCollection> first;
  first->DeepCopy(outputOf(f));
  f->SetRandomSeed(kSeed + 1); // the cached network must not be reused
  f->Update();
  EXPECT_GT(layerDifference(layer(outputOf(f), 3), direct().mli, 3), 1e-3);
  EXPECT_EQ(layerDifference(layer(first, 3), direct().mli, 3), 0.0);
}

// Pieces (pvbatch ranks): only piece BuildPiece mod pieces builds, the others are empty without
// an error; -1 builds on every piece; the builder is named in the field data.
TEST(BuildMLI, OnlyTheBuildPieceBuilds) {
  vtkNew<vtkSIMPLIBuildMLI> f;
  configure(f);
  auto piece = [&](int p, int n) {
    f->UpdatePiece(p, n, 0);
    return outputOf(f)->GetNumberOfPartitionedDataSets();
  };
  const unsigned layers = piece(0, 1);
  ASSERT_GT(layers, 0u);
  EXPECT_EQ(piece(1, 2), 0u) << "piece 1 of 2 must leave the MLI to piece 0";
  EXPECT_EQ(piece(0, 2), layers);
  vtkIntArray* builder =
      vtkIntArray::SafeDownCast(outputOf(f)->GetFieldData()->GetArray("BuildPiece"));
  ASSERT_NE(builder, nullptr);
  EXPECT_EQ(builder->GetValue(0), 0);
  f->SetBuildPiece(3); // 3 mod 2: piece 1
  EXPECT_EQ(piece(0, 2), 0u);
  EXPECT_EQ(piece(1, 2), layers);
  builder = vtkIntArray::SafeDownCast(outputOf(f)->GetFieldData()->GetArray("BuildPiece"));
  ASSERT_NE(builder, nullptr);
  EXPECT_EQ(builder->GetValue(0), 1);
  EXPECT_EQ(piece(0, 1), layers) << "one piece builds whatever BuildPiece says";
  f->SetBuildPiece(-1);
  EXPECT_EQ(piece(0, 2), layers);
  EXPECT_EQ(piece(1, 2), layers);
  EXPECT_EQ(layerDifference(layer(outputOf(f), 3), direct().mli, 3), 0.0);
}

TEST(BuildMLI, BadInputFailsWithAClearMessage) {
  vtkNew<vtkSIMPLIBuildMLI> f;
  configure(f);
  vtkNew<ErrorRecorder> errors;

  f->SetSceneFileName((kScene + "/no_such").c_str());
  EXPECT_EQ(runWithErrors(f, errors), 0);
  EXPECT_TRUE(errors->has({"SceneFileName", "no_such"})) << errors->all();
  EXPECT_EQ(outputOf(f)->GetNumberOfPartitionedDataSets(), 0u);

  f->SetSceneFileName(nullptr);
  EXPECT_EQ(runWithErrors(f, errors), 0);
  EXPECT_TRUE(errors->has({"no scene", "SceneFileName"})) << errors->all();

  f->SetSceneFileName(kScene.c_str());
  f->SetSourceViews("0,99");
  EXPECT_EQ(runWithErrors(f, errors), 0);
  EXPECT_TRUE(errors->has({"SourceViews '0,99'", "99", "12 views"})) << errors->all();
  f->SetSourceViews("0,a");
  EXPECT_EQ(runWithErrors(f, errors), 0);
  EXPECT_TRUE(errors->has({"SourceViews '0,a'", "'a'"})) << errors->all();
  f->SetSourceViews("2,2");
  EXPECT_EQ(runWithErrors(f, errors), 0);
  EXPECT_TRUE(errors->has({"SourceViews '2,2'", "twice"})) << errors->all();
  f->SetSourceViews(kViews);

  f->SetNumberOfPlanes(5);
  EXPECT_EQ(runWithErrors(f, errors), 0);
  EXPECT_TRUE(errors->has({"NumberOfPlanes 5", "17"})) << errors->all();
  f->SetNumberOfPlanes(17); // the config's: fine
  f->SetCorrectionSteps(9);
  EXPECT_EQ(runWithErrors(f, errors), 0);
  EXPECT_TRUE(errors->has({"CorrectionSteps 9", "tiny"})) << errors->all();
  f->SetCorrectionSteps(kCorrections);

  f->SetRandomSeed(-1);
  f->SetWeightsFile((kScene + "/missing.safetensors").c_str());
  EXPECT_EQ(runWithErrors(f, errors), 0);
  EXPECT_TRUE(errors->has({"WeightsFile", "missing.safetensors", "does not exist"}))
      << errors->all();
  f->SetWeightsFile(nullptr);
  f->SetConfig("no_such_config");
  f->SetRandomSeed(kSeed);
  EXPECT_EQ(runWithErrors(f, errors), 0);
  EXPECT_TRUE(errors->has({"Config 'no_such_config'", "no_such_config"})) << errors->all();
  f->SetConfig("tiny");
  f->SetDevice("0:x");
  EXPECT_EQ(runWithErrors(f, errors), 0);
  EXPECT_TRUE(errors->has({"Device", "0:x"})) << errors->all();
  f->SetDevice(nullptr);

  // And it recovers.
  ASSERT_EQ(runWithErrors(f, errors), 1) << errors->all();
  EXPECT_EQ(outputOf(f)->GetNumberOfPartitionedDataSets(), 4u);
}

class AbortAt : public vtkCommand {
public:
  static AbortAt* New() { return new AbortAt; }
  void Execute(vtkObject* caller, unsigned long, void* data) override {
    const double p = *static_cast<double*>(data);
    if (p >= at && p < 1.0) {
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
      if (abortedAt < 0)
        abortedAt = p;
    }
  }
  double at = 0.3;
  double abortedAt = -1;
};

TEST(BuildMLI, AbortDuringTheForwardPassLeavesAnEmptyOutput) {
  vtkNew<vtkSIMPLIBuildMLI> f;
  configure(f);
  vtkNew<AbortAt> abort; // after the features: inside the forward pass
  f->AddObserver(vtkCommand::ProgressEvent, abort);
  vtkNew<ErrorRecorder> errors;
  EXPECT_EQ(runWithErrors(f, errors), 1);
  // Progress 0.2 .. 0.85 is the forward pass (after the scene and the network).
  EXPECT_GT(abort->abortedAt, 0.2);
  EXPECT_LT(abort->abortedAt, 0.85);
  EXPECT_TRUE(errors->messages.empty()) << errors->all();
  EXPECT_EQ(outputOf(f)->GetNumberOfPartitionedDataSets(), 0u);
}

} // namespace
} // namespace simpli::vtktest

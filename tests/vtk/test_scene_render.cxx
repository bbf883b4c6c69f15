// vtkSIMPLISceneReader (datasets_small/synthetic/scene_00: views, cameras, bounds, frusta,
// options, bad input, abort) and vtkSIMPLIRenderView (camera modes, sizes, time steps for the
// trajectory, agreement with the model's renderMLI, bad input).
#include "vtkMLIReader.h"
#include "vtkMLIWriter.h"
#include "vtkSIMPLIRenderView.h"
#include "vtkSIMPLISceneReader.h"

#include <vtkCellData.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mli_vtk_test_util.h"
#include "simpli/model/mli/files.h"
#include "simpli/model/raster/render_mli.h"
#include "simpli/model/scene/reference_camera.h"
#include "simpli/model/scene/scene.h"
#include "simpli/model/scene/trajectory.h"

namespace simpli::vtktest {
namespace {

const std::string kScene = std::string(SIMPLI_DATA_DIR) + "/synthetic/scene_00";

vtkImageData* viewImage(vtkPartitionedDataSetCollection* c, unsigned int i) {
  vtkPartitionedDataSet* pds = c->GetPartitionedDataSet(i);
  return pds ? vtkImageData::SafeDownCast(pds->GetPartition(0)) : nullptr;
}

scene::Camera fieldCamera(vtkFieldData* fd) {
  scene::Camera c;
  double k[4], e[12];
  fd->GetArray("CameraIntrinsics")->GetTuple(0, k);
  fd->GetArray("CameraExtrinsics")->GetTuple(0, e);
  c.fx = k[0];
  c.fy = k[1];
  c.cx = k[2];
  c.cy = k[3];
  for (int r = 0; r < 3; ++r) {
    for (int col = 0; col < 3; ++col)
      c.R(r, col) = e[4 * r + col];
    c.t(r) = e[4 * r + 3];
  }
  c.width = static_cast<int>(fd->GetArray("CameraImageSize")->GetComponent(0, 0));
  c.height = static_cast<int>(fd->GetArray("CameraImageSize")->GetComponent(0, 1));
  return c;
}

// --- scene reader ------------------------------------------------------------------------------

TEST(SceneReader, ReadsTheSyntheticScene) {
  const scene::Scene scene = scene::readScene(kScene);
  vtkNew<vtkSIMPLISceneReader> reader;
  EXPECT_EQ(reader->CanReadFile(kScene.c_str()), 1);
  EXPECT_EQ(reader->CanReadFile((kScene + "/no_such").c_str()), 0);
  reader->SetFileName(kScene.c_str());
  reader->SetFrustumScale(0.5);
  vtkNew<ErrorRecorder> errors;
  ASSERT_EQ(runWithErrors(reader, errors), 1) << errors->all();
  auto* views = vtkPartitionedDataSetCollection::SafeDownCast(reader->GetOutputDataObject(0));
  ASSERT_NE(views, nullptr);
  ASSERT_EQ(views->GetNumberOfPartitionedDataSets(), 12u);
  for (unsigned int v = 0; v < 12; ++v) {
    vtkImageData* image = viewImage(views, v);
    ASSERT_NE(image, nullptr) << v;
    int dims[3];
    image->GetDimensions(dims);
    EXPECT_EQ(dims[0], 192);
    EXPECT_EQ(dims[1], 128);
    EXPECT_EQ(dims[2], 1);
    auto* rgb = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
    ASSERT_NE(rgb, nullptr);
    EXPECT_STREQ(rgb->GetName(), "RGB");
    EXPECT_EQ(rgb->GetNumberOfComponents(), 3);
    // Pixels as the model reads them: top-left of the image = VTK row H-1; a middle pixel.
    const io::Image& img = scene.views[v].image;
    for (auto [x, y] : {std::pair{0, 0}, std::pair{100, 37}, std::pair{191, 127}})
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(rgb->GetTypedComponent((127 - y) * 192 + x, c),
                  std::lround((img.at(c, y, x) + 1.0) * 127.5))
            << "view " << v << " pixel " << x << "," << y;
    // The camera, exactly.
    const scene::Camera got = fieldCamera(image->GetFieldData());
    const scene::Camera& want = scene.views[v].camera;
    EXPECT_EQ(got.R, want.R);
    EXPECT_EQ(got.t, want.t);
    EXPECT_EQ(got.fx, want.fx);
    EXPECT_EQ(got.cy, want.cy);
    EXPECT_EQ(got.width, 192);
    EXPECT_EQ(image->GetFieldData()->GetArray("ViewIndex")->GetComponent(0, 0), v);
    auto* name = vtkStringArray::SafeDownCast(image->GetFieldData()->GetAbstractArray("ViewName"));
    ASSERT_NE(name, nullptr);
    EXPECT_EQ(name->GetValue(0), scene.views[v].name);
  }
  vtkFieldData* fd = views->GetFieldData();
  EXPECT_EQ(fd->GetArray("NearFar")->GetComponent(0, 0), scene.near);
  EXPECT_EQ(fd->GetArray("NearFar")->GetComponent(0, 1), scene.far);
  EXPECT_EQ(fd->GetArray("NormalisationScale")->GetComponent(0, 0), scene.normalisation.scale);
  EXPECT_DOUBLE_EQ(scene.near, 1.0); // normalised: the near bound on depth 1
  EXPECT_EQ(fd->GetArray("NumberOfViews")->GetComponent(0, 0), 12);

  auto* frustums = vtkPolyData::SafeDownCast(reader->GetOutputDataObject(1));
  ASSERT_NE(frustums, nullptr);
  ASSERT_EQ(frustums->GetNumberOfLines(), 12);
  ASSERT_EQ(frustums->GetNumberOfPoints(), 60);
  vtkDataArray* viewIndex = frustums->GetCellData()->GetArray("ViewIndex");
  ASSERT_NE(viewIndex, nullptr);
  for (int v = 0; v < 12; ++v) {
    EXPECT_EQ(viewIndex->GetComponent(v, 0), v);
    const scene::Camera& cam = scene.views[static_cast<std::size_t>(v)].camera;
    double p[3];
    frustums->GetPoint(5 * v, p);
    EXPECT_LT((Eigen::Vector3d(p[0], p[1], p[2]) - cam.centre()).norm(), 1e-12);
    const double corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; ++k) {
      frustums->GetPoint(5 * v + 1 + k, p);
      const Eigen::Vector3d X(p[0], p[1], p[2]);
      EXPECT_NEAR(cam.depth(X), 0.5, 1e-12);
      EXPECT_NEAR(cam.project(X).x(), corners[k][0], 1e-12);
      EXPECT_NEAR(cam.project(X).y(), corners[k][1], 1e-12);
    }
  }
  EXPECT_NE(frustums->GetFieldData()->GetArray("NearFar"), nullptr);
}

TEST(SceneReader, NormaliseOff) {
  vtkNew<vtkSIMPLISceneReader> reader;
  reader->SetFileName(kScene.c_str());
  reader->NormaliseOff();
  reader->Update();
  auto* views = vtkPartitionedDataSetCollection::SafeDownCast(reader->GetOutputDataObject(0));
  ASSERT_EQ(views->GetNumberOfPartitionedDataSets(), 12u);
  EXPECT_EQ(views->GetFieldData()->GetArray("NormalisationScale")->GetComponent(0, 0), 1.0);
  // datasets_small/README: near .. far of scene_00 is 1.88 .. 20.2 scene units.
  EXPECT_NEAR(views->GetFieldData()->GetArray("NearFar")->GetComponent(0, 0), 1.88, 0.01);
  EXPECT_NEAR(views->GetFieldData()->GetArray("NearFar")->GetComponent(0, 1), 20.2, 0.05);
}

TEST(SceneReader, BadFolderFailsNamingThePath) {
  TempDir dir;
  vtkNew<vtkSIMPLISceneReader> reader;
  vtkNew<ErrorRecorder> errors;
  const std::string missing = dir / "no_such_scene";
  reader->SetFileName(missing.c_str());
  EXPECT_EQ(runWithErrors(reader, errors), 0);
  EXPECT_TRUE(errors->has({"no_such_scene", "does not exist"})) << errors->all();
  auto* views = vtkPartitionedDataSetCollection::SafeDownCast(reader->GetOutputDataObject(0));
  EXPECT_EQ(views->GetNumberOfPartitionedDataSets(), 0u);
  EXPECT_EQ(vtkPolyData::SafeDownCast(reader->GetOutputDataObject(1))->GetNumberOfPoints(), 0);

  // A folder that is no scene, then a broken poses file.
  fs::create_directories(dir.path() / "empty");
  reader->SetFileName((dir / "empty").c_str());
  errors->messages.clear();
  EXPECT_EQ(runWithErrors(reader, errors), 0);
  EXPECT_TRUE(errors->has({"empty"})) << errors->all();
  fs::create_directories(dir.path() / "broken" / "images");
  writeText(dir.path() / "broken" / "poses_bounds.npy", "not a npy file");
  reader->SetFileName((dir / "broken").c_str());
  errors->messages.clear();
  EXPECT_EQ(runWithErrors(reader, errors), 0);
  EXPECT_TRUE(errors->has({"poses_bounds.npy"})) << errors->all();

  reader->SetFileName(nullptr);
  errors->messages.clear();
  EXPECT_EQ(runWithErrors(reader, errors), 0);
  EXPECT_TRUE(errors->has({"FileName is not set"})) << errors->all();
}

class AbortAt : public vtkCommand {
public:
  static AbortAt* New() { return new AbortAt; }
  void Execute(vtkObject* caller, unsigned long, void* data) override {
    if (*static_cast<double*>(data) >= at)
      static_cast<vtkAlgorithm*>(caller)->SetAbortExecute(1);
  }
  double at = 0.8;
};

TEST(SceneReader, AbortLeavesEmptyOutputs) {
  vtkNew<vtkSIMPLISceneReader> reader;
  reader->SetFileName(kScene.c_str());
  vtkNew<AbortAt> abort;
  reader->AddObserver(vtkCommand::ProgressEvent, abort);
  reader->Update();
  auto* views = vtkPartitionedDataSetCollection::SafeDownCast(reader->GetOutputDataObject(0));
  EXPECT_EQ(views->GetNumberOfPartitionedDataSets(), 0u);
}

// --- render view ---------------------------------------------------------------------------------

// Two fronto-parallel layers in an identity reference camera: far (z = 4) opaque blue, near
// (z = 2) red with alpha 0.5 everywhere.
mli::MLI twoPlanes(int W, int H) {
  scene::Camera cam;
  cam.fx = 0.8;
  cam.fy = 0.8 * W / H;
  cam.width = W;
  cam.height = H;
  mli::MLI mli = mli::MLI::allocate(cam, 2);
  for (std::size_t p = 0; p < mli.texels(); ++p) {
    mli.layers[0].depth[p] = 4.0f;
    mli.layers[1].depth[p] = 2.0f;
    const float far[4] = {0, 0, 1, 1}, near[4] = {1, 0, 0, 0.5f};
    for (int c = 0; c < 4; ++c) {
      mli.layers[0].rgba[4 * p + c] = far[c];
      mli.layers[1].rgba[4 * p + c] = near[c];
    }
  }
  return mli;
}

// An MLI folder read back as layers (what vtkMLIReader hands to the render view).
struct MLISource {
  TempDir dir;
  vtkNew<vtkMLIReader> reader;
  explicit MLISource(const mli::MLI& mli) {
    mli::writeMLI(dir / "mli", mli, mli::MLIFormat::Lossless);
    reader->SetFileName((dir / "mli").c_str());
  }
};

vtkImageData* render(vtkSIMPLIRenderView* r) {
  vtkNew<ErrorRecorder> errors;
  EXPECT_EQ(runWithErrors(r, errors), 1) << errors->all();
  return r->GetOutput();
}

// The filter's output equals renderMLI's (colour rounded to 8 bits, rows flipped).
void expectMatchesModel(vtkImageData* image, const mli::MLI& mli, const scene::Camera& cam,
                        raster::RasterInterpolation interpolation) {
  raster::RasterSettings s;
  s.interpolation = interpolation;
  const raster::RenderedLayers r = raster::renderMLI(mli, cam, s);
  const std::vector<float> colour = r.colour.toVectorF32(), depth = r.depth.toVectorF32();
  int dims[3];
  image->GetDimensions(dims);
  ASSERT_EQ(dims[0], cam.width);
  ASSERT_EQ(dims[1], cam.height);
  const std::size_t n = static_cast<std::size_t>(cam.width) * cam.height;
  vtkDataArray* rgb = image->GetPointData()->GetArray("RGB");
  vtkDataArray* z = image->GetPointData()->GetArray("Depth");
  int bad = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * cam.width + x;
      const vtkIdType t = static_cast<vtkIdType>(cam.height - 1 - y) * cam.width + x;
      for (int c = 0; c < 3; ++c)
        bad += rgb->GetComponent(t, c) != std::round(255.0 * std::min(1.0f, colour[c * n + p]));
      bad += z->GetComponent(t, 0) != depth[p];
    }
  EXPECT_EQ(bad, 0);
}

TEST(RenderView, ReferenceCameraTwoPlanes) {
  const mli::MLI mli = twoPlanes(24, 16);
  MLISource source(mli);
  vtkNew<vtkSIMPLIRenderView> view;
  view->SetInputConnection(source.reader->GetOutputPort());
  // The size comes from the MLI's camera, and is published before any data is requested.
  view->UpdateInformation();
  int whole[6];
  ASSERT_TRUE(view->GetOutputInformation(0)->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()));
  view->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  EXPECT_EQ(whole[1], 23);
  EXPECT_EQ(whole[3], 15);
  vtkImageData* image = render(view);
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 24);
  EXPECT_EQ(dims[1], 16);
  auto* rgb = vtkUnsignedCharArray::SafeDownCast(image->GetPointData()->GetScalars());
  ASSERT_NE(rgb, nullptr);
  EXPECT_STREQ(rgb->GetName(), "RGB");
  // Centre: half red over blue; depth 0.5 * 2 + 0.5 * 4 (up to the 1e-6 of the composite).
  const vtkIdType centre = 8 * 24 + 12;
  EXPECT_EQ(rgb->GetTypedComponent(centre, 0), 128);
  EXPECT_EQ(rgb->GetTypedComponent(centre, 1), 0);
  EXPECT_EQ(rgb->GetTypedComponent(centre, 2), 128);
  EXPECT_NEAR(image->GetPointData()->GetArray("Depth")->GetComponent(centre, 0), 3.0, 1e-4);
  EXPECT_NEAR(image->GetPointData()->GetArray("Opacity")->GetComponent(centre, 0), 1.0, 1e-4);
  const scene::Camera used = fieldCamera(image->GetFieldData());
  EXPECT_EQ(used.fx, mli.camera.fx);
  EXPECT_EQ(used.width, 24);
  EXPECT_EQ(image->GetFieldData()->GetArray("FrameIndex")->GetComponent(0, 0), -1);
  expectMatchesModel(image, mli, mli.camera, raster::RasterInterpolation::ScreenLinear);

  // Width / Height: both, or one keeping the aspect ratio.
  view->SetWidth(48);
  view->SetHeight(10);
  image = render(view);
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 48);
  EXPECT_EQ(dims[1], 10);
  view->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  EXPECT_EQ(whole[1], 47);
  EXPECT_EQ(whole[3], 9);
  view->SetHeight(0);
  image = render(view);
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 48);
  EXPECT_EQ(dims[1], 32);
}

TEST(RenderView, ExplicitCameraMatchesTheModel) {
  const mli::MLI mli = randomMLI(3, 12, 16, 5);
  MLISource source(mli);
  vtkNew<vtkSIMPLIRenderView> view;
  view->SetInputConnection(source.reader->GetOutputPort());
  scene::Camera cam = mli.camera;
  cam.t += cam.R * Eigen::Vector3d(0.3, -0.2, 0.1); // move the centre a little
  cam.width = 40;
  cam.height = 30;
  view->SetCameraMode(vtkSIMPLIRenderView::CAMERA_EXPLICIT);
  view->SetIntrinsics(cam.fx, cam.fy, cam.cx, cam.cy);
  double e[12];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      e[4 * r + c] = cam.R(r, c);
    e[4 * r + 3] = cam.t(r);
  }
  view->SetExtrinsics(e);
  view->SetImageSize(40, 30);
  std::vector<float> depths[2];
  for (int interp :
       {vtkSIMPLIRenderView::SCREEN_LINEAR, vtkSIMPLIRenderView::PERSPECTIVE_CORRECT}) {
    view->SetInterpolation(interp);
    vtkImageData* image = render(view);
    expectMatchesModel(image, mli, cam,
                       interp ? raster::RasterInterpolation::PerspectiveCorrect
                              : raster::RasterInterpolation::ScreenLinear);
    vtkDataArray* z = image->GetPointData()->GetArray("Depth");
    for (vtkIdType i = 0; i < z->GetNumberOfTuples(); ++i)
      depths[interp].push_back(static_cast<float>(z->GetComponent(i, 0)));
  }
  // The random depths make triangles span a range of z, where the two modes differ.
  EXPECT_NE(depths[0], depths[1]);
  // A bad rotation is reported with the property names, and the request fails.
  e[0] = 3.0;
  view->SetExtrinsics(e);
  vtkNew<ErrorRecorder> errors;
  EXPECT_EQ(runWithErrors(view, errors), 0);
  EXPECT_TRUE(errors->has({"explicit camera", "Extrinsics"})) << errors->all();
  EXPECT_EQ(view->GetOutput()->GetNumberOfPoints(), 0);
  view->SetExtrinsics(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0);
  view->SetImageSize(40, 0);
  errors->messages.clear();
  EXPECT_EQ(runWithErrors(view, errors), 0);
  EXPECT_TRUE(errors->has({"ImageSize (40, 0)"})) << errors->all();
}

TEST(RenderView, SceneViewCamera) {
  const scene::Scene scene = scene::readScene(kScene, [] {
    scene::SceneReadOptions o;
    o.loadImages = false;
    return o;
  }());
  scene::Camera ref = scene::referenceCamera(scene.cameras());
  ref.width = 32;
  ref.height = 24;
  mli::MLI mli = mli::MLI::allocate(ref, 2);
  for (std::size_t p = 0; p < mli.texels(); ++p) {
    mli.layers[0].depth[p] = 5.0f + 0.01f * static_cast<float>(p % 32);
    mli.layers[1].depth[p] = 2.0f;
    for (int c = 0; c < 4; ++c) {
      mli.layers[0].rgba[4 * p + c] = c == 3 ? 1.0f : 0.2f + 0.2f * c;
      mli.layers[1].rgba[4 * p + c] = c == 3 ? (p % 3 ? 0.3f : 0.9f) : 0.9f - 0.3f * c;
    }
  }
  MLISource source(mli);
  vtkNew<vtkSIMPLISceneReader> sceneReader;
  sceneReader->SetFileName(kScene.c_str());
  vtkNew<vtkSIMPLIRenderView> view;
  view->SetInputConnection(source.reader->GetOutputPort());
  view->SetCameraMode(vtkSIMPLIRenderView::CAMERA_SCENE_VIEW);

  // No scene connected: a clear error.
  vtkNew<ErrorRecorder> errors;
  EXPECT_EQ(runWithErrors(view, errors), 0);
  EXPECT_TRUE(errors->has({"no scene is connected"})) << errors->all();

  view->SetSceneConnection(sceneReader->GetOutputPort(0));
  view->SetViewIndex(7);
  vtkImageData* image = render(view);
  expectMatchesModel(image, mli, scene.views[7].camera, raster::RasterInterpolation::ScreenLinear);
  view->SetViewIndex(12);
  errors->messages.clear();
  EXPECT_EQ(runWithErrors(view, errors), 0);
  EXPECT_TRUE(errors->has({"ViewIndex 12 is out of range", "12 views"})) << errors->all();
}

TEST(RenderView, TrajectoryTimeSteps) {
  const mli::MLI mli = twoPlanes(20, 16);
  MLISource source(mli);
  vtkNew<vtkSIMPLIRenderView> view;
  view->SetInputConnection(source.reader->GetOutputPort());
  view->SetCameraMode(vtkSIMPLIRenderView::CAMERA_TRAJECTORY);
  view->SetTrajectoryType(vtkSIMPLIRenderView::TRAJECTORY_ORBIT);
  view->SetNumberOfFrames(8);
  view->SetFrameIndex(3);
  view->UpdateInformation();
  vtkInformation* info = view->GetOutputInformation(0);
  ASSERT_TRUE(info->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  ASSERT_EQ(info->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()), 8);
  EXPECT_EQ(info->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS())[7], 7.0);

  // Without a time request: FrameIndex. The automatic path: focus from the MLI's depth range
  // (2 .. 4), radii 5 % of it.
  scene::TrajectoryOptions o;
  o.kind = scene::TrajectoryKind::Orbit;
  o.frames = 8;
  o = scene::resolveTrajectory(o, mli.camera, {}, 2.0, 4.0);
  vtkImageData* image = render(view);
  EXPECT_EQ(image->GetFieldData()->GetArray("FrameIndex")->GetComponent(0, 0), 3);
  scene::Camera want = scene::trajectoryCamera(mli.camera, o, 3.0 / 8.0);
  scene::Camera got = fieldCamera(image->GetFieldData());
  EXPECT_LT((got.centre() - want.centre()).norm(), 1e-12);
  expectMatchesModel(image, mli, want, raster::RasterInterpolation::ScreenLinear);

  // A time request selects the frame.
  view->UpdateTimeStep(5.2);
  image = view->GetOutput();
  EXPECT_EQ(image->GetFieldData()->GetArray("FrameIndex")->GetComponent(0, 0), 5);
  got = fieldCamera(image->GetFieldData());
  want = scene::trajectoryCamera(mli.camera, o, 5.0 / 8.0);
  EXPECT_LT((got.centre() - want.centre()).norm(), 1e-12);
  EXPECT_EQ(image->GetInformation()->Get(vtkDataObject::DATA_TIME_STEP()), 5.0);

  // Explicit radii and focus depth; other modes publish no time steps.
  view->SetTrajectoryRadii(0.1, 0.2, 0.0);
  view->SetFocusDepth(3.0);
  view->UpdateTimeStep(1.0);
  o.radii = Eigen::Vector3d(0.1, 0.2, 0.0);
  o.focusDepth = 3.0;
  got = fieldCamera(view->GetOutput()->GetFieldData());
  EXPECT_LT((got.centre() - scene::trajectoryCamera(mli.camera, o, 1.0 / 8.0).centre()).norm(),
            1e-12);
  view->SetCameraMode(vtkSIMPLIRenderView::CAMERA_REFERENCE);
  view->UpdateInformation();
  EXPECT_FALSE(view->GetOutputInformation(0)->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
}

TEST(RenderView, AbortLeavesAnEmptyImage) {
  const mli::MLI mli = twoPlanes(24, 16);
  MLISource source(mli);
  vtkNew<vtkSIMPLIRenderView> view;
  view->SetInputConnection(source.reader->GetOutputPort());
  vtkNew<AbortAt> abort; // the render view reports progress 0.2 just before rendering
  abort->at = 0.2;
  view->AddObserver(vtkCommand::ProgressEvent, abort);
  view->Update();
  EXPECT_EQ(view->GetOutput()->GetNumberOfPoints(), 0);
}

TEST(RenderView, BadInput) {
  // An input without the camera arrays.
  vtkNew<vtkPartitionedDataSetCollection> empty;
  vtkNew<vtkSIMPLIRenderView> view;
  view->SetInputDataObject(0, empty);
  vtkNew<ErrorRecorder> errors;
  EXPECT_EQ(runWithErrors(view, errors), 0);
  EXPECT_TRUE(errors->has({"CameraIntrinsics", "missing"})) << errors->all();
  EXPECT_EQ(view->GetOutput()->GetNumberOfPoints(), 0);
}

} // namespace
} // namespace simpli::vtktest

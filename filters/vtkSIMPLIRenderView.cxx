#include "vtkSIMPLIRenderView.h"

#include "SIMPLIFilter.h"
#include "SIMPLIMLIToVTK.h"
#include "SIMPLISceneToVTK.h"

#include <vtkAlgorithmOutput.h>
#include <vtkFieldData.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkIntArray.h>
#include <vtkObjectFactory.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkUnsignedCharArray.h>

#include "simpli/error.h"
#include "simpli/model/raster/render_mli.h"
#include "simpli/model/scene/trajectory.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSIMPLIRenderView);

namespace {

const char* modeName(int mode) {
  switch (mode) {
  case vtkSIMPLIRenderView::CAMERA_SCENE_VIEW:
    return "scene view";
  case vtkSIMPLIRenderView::CAMERA_EXPLICIT:
    return "explicit";
  case vtkSIMPLIRenderView::CAMERA_TRAJECTORY:
    return "trajectory";
  default:
    return "reference";
  }
}

// Smallest and largest depth of the MLI's layers.
void depthRange(const simpli::mli::MLI& mli, double& near, double& far) {
  near = std::numeric_limits<double>::infinity();
  far = 0;
  for (const simpli::mli::MLILayer& layer : mli.layers)
    for (float d : layer.depth) {
      near = std::min(near, static_cast<double>(d));
      far = std::max(far, static_cast<double>(d));
    }
}

// Output size from the camera's and the Width / Height properties (0 = the camera's; one of
// them alone keeps the aspect ratio).
void outputSize(int cameraW, int cameraH, int width, int height, int& W, int& H) {
  W = cameraW;
  H = cameraH;
  if (width > 0 && height > 0) {
    W = width;
    H = height;
  } else if (width > 0) {
    W = width;
    H = std::max(1, static_cast<int>(std::lround(double(width) * cameraH / cameraW)));
  } else if (height > 0) {
    H = height;
    W = std::max(1, static_cast<int>(std::lround(double(height) * cameraW / cameraH)));
  }
}

// The data object on input `port` after updating its producer, or null.
vtkDataObject* updatedInput(vtkAlgorithm* self, int port) {
  if (self->GetNumberOfInputConnections(port) < 1)
    return nullptr;
  vtkAlgorithmOutput* connection = self->GetInputConnection(port, 0);
  vtkAlgorithm* producer = connection ? connection->GetProducer() : nullptr;
  if (!producer)
    return nullptr;
  producer->Update(connection->GetIndex());
  return producer->GetOutputDataObject(connection->GetIndex());
}

} // namespace

vtkSIMPLIRenderView::vtkSIMPLIRenderView() {
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(1);
}

void vtkSIMPLIRenderView::SetExtrinsics(const double e[12]) {
  if (std::equal(e, e + 12, this->Extrinsics))
    return;
  std::copy(e, e + 12, this->Extrinsics);
  this->Modified();
}

void vtkSIMPLIRenderView::SetExtrinsics(double r00, double r01, double r02, double t0, double r10,
                                        double r11, double r12, double t1, double r20, double r21,
                                        double r22, double t2) {
  const double e[12] = {r00, r01, r02, t0, r10, r11, r12, t1, r20, r21, r22, t2};
  this->SetExtrinsics(e);
}

int vtkSIMPLIRenderView::FillInputPortInformation(int port, vtkInformation* info) {
  if (port < 0 || port > 1)
    return 0;
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPartitionedDataSetCollection");
  if (port == 1)
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkSIMPLIRenderView::RequestInformation(vtkInformation* vtkNotUsed(request),
                                            vtkInformationVector** vtkNotUsed(inputVector),
                                            vtkInformationVector* outputVector) {
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  // Image consumers (ParaView's slice representation among them) draw nothing without a
  // WHOLE_EXTENT, so it is published here even when it depends on the inputs' cameras.
  int size[2] = {this->Width, this->Height};
  if ((this->Width > 0 && this->Height > 0) || this->PredictOutputSize(size)) {
    const int extent[6] = {0, size[0] - 1, 0, size[1] - 1, 0, 0};
    outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
  } else {
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT());
  }
  if (this->CameraMode == CAMERA_TRAJECTORY) {
    std::vector<double> steps(static_cast<std::size_t>(this->NumberOfFrames));
    for (int i = 0; i < this->NumberOfFrames; ++i)
      steps[static_cast<std::size_t>(i)] = i;
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_STEPS(), steps.data(),
                 this->NumberOfFrames);
    const double range[2] = {0.0, static_cast<double>(this->NumberOfFrames - 1)};
    outInfo->Set(vtkStreamingDemandDrivenPipeline::TIME_RANGE(), range, 2);
  } else {
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    outInfo->Remove(vtkStreamingDemandDrivenPipeline::TIME_RANGE());
  }
  return 1;
}

bool vtkSIMPLIRenderView::PredictOutputSize(int size[2]) {
  try {
    auto* mli = vtkPartitionedDataSetCollection::SafeDownCast(updatedInput(this, 0));
    if (!mli)
      return false;
    const simpli::scene::Camera reference =
        simpli::vtkmli::cameraFromFieldData(mli->GetFieldData(), "render view: MLI input");
    int W = reference.width, H = reference.height;
    if (this->CameraMode == CAMERA_SCENE_VIEW) {
      auto* scene = vtkPartitionedDataSetCollection::SafeDownCast(updatedInput(this, 1));
      if (!scene)
        return false;
      const std::vector<simpli::scene::Camera> cams =
          simpli::vtkscene::sceneCameras(scene, "render view: scene input");
      if (this->ViewIndex >= static_cast<int>(cams.size()))
        return false;
      W = cams[static_cast<std::size_t>(this->ViewIndex)].width;
      H = cams[static_cast<std::size_t>(this->ViewIndex)].height;
    } else if (this->CameraMode == CAMERA_EXPLICIT && this->ImageSize[0] > 0 &&
               this->ImageSize[1] > 0) {
      W = this->ImageSize[0];
      H = this->ImageSize[1];
    }
    outputSize(W, H, this->Width, this->Height, size[0], size[1]);
    return true;
  } catch (const std::exception&) {
    return false; // RequestData reports it
  }
}

int vtkSIMPLIRenderView::RequestUpdateExtent(vtkInformation* vtkNotUsed(request),
                                             vtkInformationVector** vtkNotUsed(inputVector),
                                             vtkInformationVector* vtkNotUsed(outputVector)) {
  return 1; // composite inputs are taken whole; no time is passed on (they are static)
}

namespace {

// The camera of input 1's view ViewIndex.
simpli::scene::Camera sceneViewCamera(vtkSIMPLIRenderView* self,
                                      vtkPartitionedDataSetCollection* sceneInput) {
  if (!sceneInput)
    simpli::fail("render view: CameraMode is scene view but no scene is connected to input 1");
  const std::vector<simpli::scene::Camera> cams =
      simpli::vtkscene::sceneCameras(sceneInput, "render view: scene input");
  if (self->GetViewIndex() >= static_cast<int>(cams.size()))
    simpli::fail("render view: ViewIndex ", self->GetViewIndex(),
                 " is out of range (the scene has ", cams.size(), " views)");
  return cams[static_cast<std::size_t>(self->GetViewIndex())];
}

// Intrinsics, Extrinsics and ImageSize (0, 0: the size of `camera`, the MLI's) as a camera.
simpli::scene::Camera explicitCamera(vtkSIMPLIRenderView* self, simpli::scene::Camera camera) {
  const double* k = self->GetIntrinsics();
  const double* e = self->GetExtrinsics();
  const int* size = self->GetImageSize();
  camera.fx = k[0];
  camera.fy = k[1];
  camera.cx = k[2];
  camera.cy = k[3];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      camera.R(r, c) = e[4 * r + c];
    camera.t(r) = e[4 * r + 3];
  }
  if (size[0] > 0 || size[1] > 0) {
    if (size[0] <= 0 || size[1] <= 0)
      simpli::fail("render view: ImageSize (", size[0], ", ", size[1],
                   ") must be both positive or both 0 (the MLI's size)");
    camera.width = size[0];
    camera.height = size[1];
  }
  simpli::mli::validateMLICamera(camera, "render view: explicit camera (Intrinsics, Extrinsics)");
  return camera;
}

// Frame `frame` of the trajectory (TrajectoryType, NumberOfFrames, TrajectoryRadii, FocusDepth)
// around the MLI's camera, with the scene's cameras and bounds when input 1 has a scene. The
// frame is FrameIndex, or the pipeline's time step when one is requested.
simpli::scene::Camera trajectoryCamera(vtkSIMPLIRenderView* self, const simpli::mli::MLI& mli,
                                       vtkPartitionedDataSetCollection* sceneInput,
                                       vtkInformation* outInfo, int& frame) {
  simpli::scene::TrajectoryOptions o;
  o.kind = self->GetTrajectoryType() == vtkSIMPLIRenderView::TRAJECTORY_ORBIT
               ? simpli::scene::TrajectoryKind::Orbit
               : simpli::scene::TrajectoryKind::Spiral;
  o.frames = self->GetNumberOfFrames();
  const double* radii = self->GetTrajectoryRadii();
  o.radii = Eigen::Vector3d(radii[0], radii[1], radii[2]);
  o.focusDepth = self->GetFocusDepth();
  std::vector<simpli::scene::Camera> cams;
  double near = 0, far = 0;
  if (sceneInput) {
    cams = simpli::vtkscene::sceneCameras(sceneInput, "render view: scene input");
    simpli::vtkscene::nearFarFromFieldData(sceneInput->GetFieldData(), "render view: scene input",
                                           near, far);
  }
  if (!(near > 0))
    depthRange(mli, near, far);
  o = simpli::scene::resolveTrajectory(o, mli.camera, cams, near, far);
  frame = self->GetFrameIndex();
  if (outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP())) {
    const double t = outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_TIME_STEP());
    frame = std::isfinite(t) ? static_cast<int>(std::lround(t)) : 0;
    frame = std::max(0, std::min(frame, self->GetNumberOfFrames() - 1));
  }
  if (frame >= self->GetNumberOfFrames())
    simpli::fail("render view: FrameIndex ", frame, " is out of range (NumberOfFrames ",
                 self->GetNumberOfFrames(), ")");
  return simpli::scene::trajectoryCamera(mli.camera, o, static_cast<double>(frame) / o.frames);
}

// The render as the output image: RGB (8-bit, point scalars), Depth and Opacity, VTK row order
// (row 0 at the bottom), the camera and the frame as field data.
void fillImage(vtkImageData* output, const simpli::raster::RenderedLayers& r,
               const simpli::scene::Camera& camera, int frame) {
  const int W = camera.width, H = camera.height;
  const std::vector<float> colour = r.colour.toVectorF32();
  const std::vector<float> depth = r.depth.toVectorF32();
  const std::vector<float> opacity = r.opacity.toVectorF32();
  const std::size_t n = static_cast<std::size_t>(W) * H;
  auto rgb = vtkSmartPointer<vtkUnsignedCharArray>::New();
  rgb->SetName(simpli::vtkscene::kRGBArray);
  rgb->SetNumberOfComponents(3);
  rgb->SetNumberOfTuples(static_cast<vtkIdType>(n));
  auto z = vtkSmartPointer<vtkFloatArray>::New();
  z->SetName("Depth");
  z->SetNumberOfTuples(static_cast<vtkIdType>(n));
  auto a = vtkSmartPointer<vtkFloatArray>::New();
  a->SetName("Opacity");
  a->SetNumberOfTuples(static_cast<vtkIdType>(n));
  for (int y = 0; y < H; ++y) {
    const std::size_t row = static_cast<std::size_t>(H - 1 - y); // VTK row 0 = bottom
    for (int x = 0; x < W; ++x) {
      const std::size_t src = static_cast<std::size_t>(y) * W + x, dst = row * W + x;
      for (int c = 0; c < 3; ++c) {
        const double v = std::round(255.0 * colour[c * n + src]);
        rgb->SetTypedComponent(static_cast<vtkIdType>(dst), c,
                               static_cast<unsigned char>(v < 0 ? 0 : (v > 255 ? 255 : v)));
      }
      z->SetValue(static_cast<vtkIdType>(dst), depth[src]);
      a->SetValue(static_cast<vtkIdType>(dst), opacity[src]);
    }
  }
  output->SetExtent(0, W - 1, 0, H - 1, 0, 0);
  output->SetSpacing(1, 1, 1);
  output->SetOrigin(0, 0, 0);
  output->GetPointData()->SetScalars(rgb);
  output->GetPointData()->AddArray(z);
  output->GetPointData()->AddArray(a);
  simpli::vtkmli::addCameraFieldData(output->GetFieldData(), camera);
  auto frameArray = vtkSmartPointer<vtkIntArray>::New();
  frameArray->SetName("FrameIndex");
  frameArray->InsertNextValue(frame);
  output->GetFieldData()->AddArray(frameArray);
  if (frame >= 0)
    output->GetInformation()->Set(vtkDataObject::DATA_TIME_STEP(), frame);
}

} // namespace

int vtkSIMPLIRenderView::RequestData(vtkInformation* vtkNotUsed(request),
                                     vtkInformationVector** inputVector,
                                     vtkInformationVector* outputVector) {
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  if (!output) {
    vtkErrorMacro(<< "No vtkImageData output to fill");
    return 0;
  }
  output->Initialize();
  const std::string what =
      std::string("SIMPLI render view (") + modeName(this->CameraMode) + " camera)";
  return simpli::vtkfilter::runRequest(
      this, what,
      [&](const simpli::vtkfilter::Progress& progress) {
        auto* mliInput = vtkPartitionedDataSetCollection::GetData(inputVector[0], 0);
        if (!mliInput)
          simpli::fail("render view: input 0 (the MLI) is missing or not a "
                       "vtkPartitionedDataSetCollection of layers");
        auto* sceneInput = inputVector[1]->GetNumberOfInformationObjects() > 0
                               ? vtkPartitionedDataSetCollection::GetData(inputVector[1], 0)
                               : nullptr;
        progress(0.0);
        const simpli::mli::MLI mli =
            simpli::vtkmli::collectionToMLI(mliInput, "render view: MLI input");

        simpli::scene::Camera camera = mli.camera;
        int frame = -1;
        if (this->CameraMode == CAMERA_SCENE_VIEW)
          camera = sceneViewCamera(this, sceneInput);
        else if (this->CameraMode == CAMERA_EXPLICIT)
          camera = explicitCamera(this, camera);
        else if (this->CameraMode == CAMERA_TRAJECTORY)
          camera = trajectoryCamera(this, mli, sceneInput, outInfo, frame);
        // Output size: Width / Height override the camera's (one of them: keep the aspect ratio).
        outputSize(camera.width, camera.height, this->Width, this->Height, camera.width,
                   camera.height);

        simpli::raster::RasterSettings settings;
        settings.maxFragments = this->MaxFragments;
        settings.interpolation = this->Interpolation == PERSPECTIVE_CORRECT
                                     ? simpli::raster::RasterInterpolation::PerspectiveCorrect
                                     : simpli::raster::RasterInterpolation::ScreenLinear;
        if (!progress(0.2))
          return;
        const simpli::raster::RenderedLayers r = simpli::raster::renderMLI(mli, camera, settings);
        progress(0.9);
        fillImage(output, r, camera, frame);
        const int extent[6] = {0, camera.width - 1, 0, camera.height - 1, 0, 0};
        outInfo->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
        progress(1.0);
      },
      [output] { output->Initialize(); });
}

void vtkSIMPLIRenderView::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "CameraMode: " << modeName(this->CameraMode) << "\n";
  os << indent << "ViewIndex: " << this->ViewIndex << "\n";
  os << indent << "Intrinsics: " << this->Intrinsics[0] << " " << this->Intrinsics[1] << " "
     << this->Intrinsics[2] << " " << this->Intrinsics[3] << "\n";
  os << indent << "Extrinsics:";
  for (double e : this->Extrinsics)
    os << " " << e;
  os << "\n";
  os << indent << "ImageSize: " << this->ImageSize[0] << " " << this->ImageSize[1] << "\n";
  os << indent
     << "TrajectoryType: " << (this->TrajectoryType == TRAJECTORY_ORBIT ? "orbit" : "spiral")
     << "\n";
  os << indent << "NumberOfFrames: " << this->NumberOfFrames << "\n";
  os << indent << "FrameIndex: " << this->FrameIndex << "\n";
  os << indent << "TrajectoryRadii: " << this->TrajectoryRadii[0] << " " << this->TrajectoryRadii[1]
     << " " << this->TrajectoryRadii[2] << "\n";
  os << indent << "FocusDepth: " << this->FocusDepth << "\n";
  os << indent << "Width: " << this->Width << " Height: " << this->Height << "\n";
  os << indent << "Interpolation: "
     << (this->Interpolation == PERSPECTIVE_CORRECT ? "perspective-correct" : "screen-linear")
     << "\n";
  os << indent << "MaxFragments: " << this->MaxFragments << "\n";
}

// One actor per MLI layer, the simpli camera as a vtkCamera (see SIMPLILayerActors.h).
#include "SIMPLILayerActors.h"

#include "SIMPLIMLIToVTK.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderStepsPass.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkShaderProperty.h>
#include <vtkTexture.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <X11/Xlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <thread>

#include "simpli/error.h"

namespace simpli::vtkrender {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The RGB of a 4-component unsigned char array (the alpha dropped: an opaque copy).
vtkSmartPointer<vtkUnsignedCharArray> opaqueColours(vtkDataArray* rgba) {
  auto rgb = vtkSmartPointer<vtkUnsignedCharArray>::New();
  rgb->SetName("RGB");
  rgb->SetNumberOfComponents(3);
  rgb->SetNumberOfTuples(rgba->GetNumberOfTuples());
  for (vtkIdType t = 0; t < rgba->GetNumberOfTuples(); ++t)
    for (int c = 0; c < 3; ++c)
      rgb->SetValue(3 * t + c, static_cast<unsigned char>(rgba->GetComponent(t, c)));
  return rgb;
}

vtkSmartPointer<vtkActor> layerActor(vtkPolyData* layer, bool opaque) {
  vtkNew<vtkPolyDataMapper> mapper;
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  vtkProperty* property = actor->GetProperty();
  property->SetColor(1.0, 1.0, 1.0);
  property->SetAmbient(1.0);
  property->SetDiffuse(0.0);
  property->SetSpecular(0.0);
  property->LightingOff();
  if (vtkSmartPointer<vtkImageData> image = vtkmli::layerTexture(layer)) {
    if (opaque) {
      auto rgb = vtkSmartPointer<vtkImageData>::New();
      rgb->SetDimensions(image->GetDimensions());
      rgb->GetPointData()->SetScalars(opaqueColours(image->GetPointData()->GetScalars()));
      image = rgb;
    }
    mapper->SetInputData(layer);
    mapper->ScalarVisibilityOff();
    vtkNew<vtkTexture> texture;
    texture->SetInputData(image);
    texture->InterpolateOn();
    texture->RepeatOff();
    texture->EdgeClampOn();
    texture->MipmapOff();
    texture->PremultipliedAlphaOff(); // the MLI's RGBA is straight
    actor->SetTexture(texture);
    // The fragment colour is the texel: VTK's own texture code multiplies it with the lit
    // colour (white here) and discards alpha-0 fragments, and the discard keeps llvmpipe from
    // testing depth before shading (measured: 4 translucent textured layers at 1024x768, 58 ->
    // 42 ms of CPU per frame; a discard changes nothing visible with depth writes off).
    actor->GetShaderProperty()->AddFragmentShaderReplacement(
        "//VTK::TCoord::Impl", true, "fragOutput0 = texture(actortexture, tcoordVCVSOutput);\n",
        false);
  } else {
    vtkPolyData* input = layer;
    vtkNew<vtkPolyData> copy;
    if (opaque && layer->GetPointData()->GetScalars()) {
      copy->ShallowCopy(layer);
      copy->GetPointData()->SetScalars(opaqueColours(layer->GetPointData()->GetScalars()));
      input = copy;
    }
    mapper->SetInputData(input);
    mapper->ScalarVisibilityOn();
    mapper->SetScalarModeToUsePointData();
    mapper->SetColorModeToDirectScalars(); // RGBA as is (ParaView: MapScalars off)
  }
  return actor;
}

} // namespace

std::vector<vtkSmartPointer<vtkActor>> addLayerActors(vtkRenderer* renderer,
                                                      vtkPartitionedDataSetCollection* layers,
                                                      const LayerActorOptions& options) {
  std::vector<vtkSmartPointer<vtkActor>> actors;
  for (unsigned int k = 0; k < layers->GetNumberOfPartitionedDataSets(); ++k) {
    vtkPartitionedDataSet* pds = layers->GetPartitionedDataSet(k);
    auto* layer = pds ? vtkPolyData::SafeDownCast(pds->GetPartition(0)) : nullptr;
    if (!layer)
      fail("MLI actors: data set ", k, " of the layer collection is not a vtkPolyData");
    actors.push_back(layerActor(layer, k == 0 && options.opaqueBackLayer));
    renderer->AddActor(actors.back());
  }
  return actors;
}

void useLayerOrderBlending(vtkRenderer* renderer) {
  renderer->SetUseDepthPeeling(0);
  vtkNew<vtkRenderStepsPass> steps;
  renderer->SetPass(steps);
}

void setCamera(vtkCamera* vc, const scene::Camera& c, double nearZ, double farZ) {
  const double fxPixels = c.fx * c.width, fyPixels = c.fy * c.height;
  if (std::abs(fxPixels - fyPixels) > 1e-6 * std::max(fxPixels, fyPixels))
    fail("VTK camera: pixels are not square (fx' W = ", fxPixels, ", fy' H = ", fyPixels,
         "); a vtkCamera has one view angle");
  const Eigen::Vector3d C = c.centre();
  const Eigen::Vector3d forward = c.R.row(2).transpose(), down = c.R.row(1).transpose();
  const Eigen::Vector3d F = C + forward;
  vc->SetPosition(C.x(), C.y(), C.z());
  vc->SetFocalPoint(F.x(), F.y(), F.z());
  vc->SetViewUp(-down.x(), -down.y(), -down.z());
  vc->SetViewAngle(2.0 * std::atan(0.5 / c.fy) * 180.0 / kPi);
  vc->SetWindowCenter(1.0 - 2.0 * c.cx, 2.0 * c.cy - 1.0);
  vc->SetClippingRange(nearZ, farZ);
}

std::vector<float> grabRGB(vtkRenderWindow* window) {
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  vtkImageData* image = grab->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  const int W = dims[0], H = dims[1];
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  std::vector<float> rgb(static_cast<std::size_t>(3) * W * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 3; ++c)
        rgb[3 * (static_cast<std::size_t>(y) * W + x) + c] = static_cast<float>(
            scalars->GetComponent(static_cast<vtkIdType>(H - 1 - y) * W + x, c) / 255.0);
  return rgb;
}

bool holdXDisplay() {
  static Display* display = nullptr; // kept open on purpose, until exit
  if (display)
    return true;
  if (!std::getenv("DISPLAY"))
    return false;
  for (int attempt = 0; attempt < 600; ++attempt) {
    if ((display = XOpenDisplay(nullptr)))
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

} // namespace simpli::vtkrender

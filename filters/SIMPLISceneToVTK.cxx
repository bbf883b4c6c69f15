// Scene <-> VTK helpers (see SIMPLISceneToVTK.h).
#include "SIMPLISceneToVTK.h"

#include "SIMPLIMLIToVTK.h"

#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkPartitionedDataSet.h>
#include <vtkPartitionedDataSetCollection.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>

#include "simpli/error.h"

#include <cmath>
#include <cstdio>
#include <utility>

namespace simpli::vtkscene {

std::string viewName(int k) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "View%03d", k);
  return buf;
}

void addNearFar(vtkFieldData* fd, double near, double far) {
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(kNearFarArray);
  a->SetNumberOfComponents(2);
  a->SetComponentName(0, "near");
  a->SetComponentName(1, "far");
  const double v[2] = {near, far};
  a->InsertNextTuple(v);
  fd->AddArray(a);
}

bool nearFarFromFieldData(vtkFieldData* fd, const std::string& context, double& near, double& far) {
  vtkDataArray* a = fd ? fd->GetArray(kNearFarArray) : nullptr;
  if (!a)
    return false;
  if (a->GetNumberOfComponents() != 2 || a->GetNumberOfTuples() != 1)
    fail(context, ": field data array \"", kNearFarArray, "\" has ", a->GetNumberOfTuples(),
         " tuple(s) of ", a->GetNumberOfComponents(), " component(s), expected 1 tuple of 2");
  near = a->GetComponent(0, 0);
  far = a->GetComponent(0, 1);
  if (!(std::isfinite(near) && std::isfinite(far) && near > 0 && far >= near))
    fail(context, ": field data array \"", kNearFarArray, "\" = (", near, ", ", far,
         "), expected 0 < near <= far");
  return true;
}

void imageToVTK(const io::Image& image, vtkImageData* out) {
  const int W = image.width, H = image.height;
  out->Initialize();
  out->SetDimensions(W, H, 1);
  out->SetSpacing(1, 1, 1);
  out->SetOrigin(0, 0, 0);
  auto rgb = vtkSmartPointer<vtkUnsignedCharArray>::New();
  rgb->SetName(kRGBArray);
  rgb->SetNumberOfComponents(3);
  rgb->SetNumberOfTuples(static_cast<vtkIdType>(W) * H);
  unsigned char* p = rgb->GetPointer(0);
  for (int y = 0; y < H; ++y) {
    const int row = H - 1 - y; // VTK's row 0 is the bottom image row
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 3; ++c) {
        const double v = std::round((image.at(c, y, x) + 1.0) * 127.5);
        p[3 * (static_cast<std::size_t>(row) * W + x) + c] =
            static_cast<unsigned char>(v < 0 ? 0 : (v > 255 ? 255 : v));
      }
  }
  out->GetPointData()->SetScalars(rgb);
}

io::Image imageFromVTK(vtkImageData* image, const std::string& context) {
  if (!image)
    fail(context, ": not a vtkImageData");
  int dims[3];
  image->GetDimensions(dims);
  if (dims[0] < 1 || dims[1] < 1 || dims[2] != 1)
    fail(context, ": image dimensions ", dims[0], " x ", dims[1], " x ", dims[2],
         ", expected a 2-D image (W x H x 1)");
  vtkDataArray* scalars = image->GetPointData()->GetScalars();
  if (!scalars)
    scalars = image->GetPointData()->GetArray(kRGBArray);
  auto* rgb = vtkUnsignedCharArray::SafeDownCast(scalars);
  if (!rgb)
    fail(context, ": point data \"", kRGBArray, "\" (unsigned char RGB) is missing",
         scalars ? " (the active scalars are not unsigned char)" : "");
  const int nc = rgb->GetNumberOfComponents();
  const int W = dims[0], H = dims[1];
  if ((nc != 3 && nc != 4) || rgb->GetNumberOfTuples() != static_cast<vtkIdType>(W) * H)
    fail(context, ": point data \"", rgb->GetName() ? rgb->GetName() : "(unnamed)", "\" has ",
         rgb->GetNumberOfTuples(), " tuple(s) of ", nc, " component(s), expected ", W * H,
         " of 3 (RGB) or 4");
  io::Image out(W, H);
  const unsigned char* p = rgb->GetPointer(0);
  for (int y = 0; y < H; ++y) {
    const std::size_t row = static_cast<std::size_t>(H - 1 - y); // VTK's row 0 is the bottom
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 3; ++c)
        // x * (1 / 127.5) - 1 in double, rounded once to float: readImage's formula, so that
        // the pixels of an 8-bit file come back bit for bit.
        out.at(c, y, x) = static_cast<float>(p[nc * (row * W + x) + c] * (1.0 / 127.5) - 1.0);
  }
  return out;
}

namespace {

// The first value of string array `name` of `fd`, or "" when absent.
std::string stringValue(vtkFieldData* fd, const char* name) {
  auto* a = fd ? vtkStringArray::SafeDownCast(fd->GetAbstractArray(name)) : nullptr;
  return a && a->GetNumberOfValues() > 0 ? a->GetValue(0) : std::string();
}

} // namespace

scene::Scene vtkToScene(vtkPartitionedDataSetCollection* collection, const std::string& context) {
  if (!collection)
    fail(context, ": no scene (expected the vtkPartitionedDataSetCollection of the scene reader)");
  const unsigned int n = collection->GetNumberOfPartitionedDataSets();
  if (n == 0)
    fail(context, ": the scene holds no views (no partitioned data sets)");
  scene::Scene scene;
  scene.root = context;
  vtkFieldData* fd = collection->GetFieldData();
  if (!nearFarFromFieldData(fd, context, scene.near, scene.far))
    fail(context, ": field data array \"", kNearFarArray,
         "\" is missing (the scene reader's near/far bounds)");
  scene.boundsSource = context + " field data " + kNearFarArray;
  if (vtkDataArray* s = fd->GetArray(kNormalisationScaleArray)) {
    const double scale = s->GetNumberOfTuples() > 0 ? s->GetComponent(0, 0) : 0.0;
    if (!(std::isfinite(scale) && scale > 0))
      fail(context, ": field data array \"", kNormalisationScaleArray, "\" = ", scale,
           ", expected a positive number");
    scene.normalisation.scale = scale;
  }
  if (const std::string format = stringValue(fd, kSceneFormatArray); !format.empty())
    scene.format = scene::parseSceneFormat(format);
  const std::vector<scene::Camera> cameras = sceneCameras(collection, context);
  for (unsigned int i = 0; i < n; ++i) {
    const std::string where = context + ": scene view " + std::to_string(i);
    auto* image = vtkImageData::SafeDownCast(collection->GetPartitionedDataSet(i)->GetPartition(0));
    scene::SceneView view;
    view.image = imageFromVTK(image, where);
    view.camera = cameras[i];
    if (view.camera.width != view.image.width || view.camera.height != view.image.height)
      fail(where, ": field data array \"", vtkmli::kImageSizeArray, "\" = (", view.camera.width,
           ", ", view.camera.height, ") but the image is ", view.image.width, " x ",
           view.image.height);
    view.name = stringValue(image->GetFieldData(), kViewNameArray);
    if (view.name.empty())
      view.name = viewName(static_cast<int>(i));
    view.imagePath = stringValue(image->GetFieldData(), kImagePathArray);
    view.originalWidth = view.image.width;
    view.originalHeight = view.image.height;
    scene.views.push_back(std::move(view));
  }
  return scene;
}

std::vector<scene::Camera> sceneCameras(vtkPartitionedDataSetCollection* scene,
                                        const std::string& context) {
  if (!scene)
    fail(context, ": no scene (expected the vtkPartitionedDataSetCollection of the scene reader)");
  std::vector<scene::Camera> cameras;
  for (unsigned int i = 0; i < scene->GetNumberOfPartitionedDataSets(); ++i) {
    vtkPartitionedDataSet* pds = scene->GetPartitionedDataSet(i);
    auto* image = pds && pds->GetNumberOfPartitions() > 0
                      ? vtkImageData::SafeDownCast(pds->GetPartition(0))
                      : nullptr;
    if (!image)
      fail(context, ": scene view ", i, " is not a vtkImageData");
    cameras.push_back(vtkmli::cameraFromFieldData(image->GetFieldData(),
                                                  context + ": scene view " + std::to_string(i)));
  }
  return cameras;
}

} // namespace simpli::vtkscene

// Scene <-> VTK helpers (see SIMPLISceneToVTK.h).
#include "SIMPLISceneToVTK.h"

#include "SIMPLIMLIToVTK.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkPartitionedDataSet.h"
#include "vtkPartitionedDataSetCollection.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include "simpli/error.h"

#include <cmath>
#include <cstdio>

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

void imageToVTK(const Image& image, vtkImageData* out) {
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

std::vector<Camera> sceneCameras(vtkPartitionedDataSetCollection* scene,
                                 const std::string& context) {
  if (!scene)
    fail(context, ": no scene (expected the vtkPartitionedDataSetCollection of the scene reader)");
  std::vector<Camera> cameras;
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

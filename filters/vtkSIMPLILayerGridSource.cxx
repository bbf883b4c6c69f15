#include "vtkSIMPLILayerGridSource.h"

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkIdTypeArray.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <cmath>

vtkStandardNewMacro(vtkSIMPLILayerGridSource);

namespace {

// [0,1] -> [0,255], rounded: truncation would turn products that land a hair below an
// integer (binary floating point) into the next lower byte.
unsigned char toByte(double c) {
  return static_cast<unsigned char>(std::lround(c * 255.0));
}

// Clamp to [0,1]; NaN is kept so that CheckSettings() can report it instead of hiding it.
double clampUnit(double c) {
  if (c < 0.0) {
    return 0.0;
  }
  if (c > 1.0) {
    return 1.0;
  }
  return c;
}

} // namespace

vtkSIMPLILayerGridSource::vtkSIMPLILayerGridSource() {
  this->SetNumberOfInputPorts(0);
}

void vtkSIMPLILayerGridSource::SetColor(double r, double g, double b, double a) {
  const double c[4] = {clampUnit(r), clampUnit(g), clampUnit(b), clampUnit(a)};
  bool changed = false;
  for (int k = 0; k < 4; ++k) {
    // NaN != NaN, so treat "NaN again" as unchanged to avoid a spurious Modified().
    if (!(this->Color[k] == c[k]) && !(std::isnan(this->Color[k]) && std::isnan(c[k]))) {
      this->Color[k] = c[k];
      changed = true;
    }
  }
  if (changed) {
    this->Modified();
  }
}

bool vtkSIMPLILayerGridSource::CheckSettings() {
  if (!(this->Depth > 0.0) || !std::isfinite(this->Depth)) {
    vtkErrorMacro(<< "Depth = " << this->Depth << " is invalid: it must be a finite value > 0");
    return false;
  }
  if (this->Fx == 0.0 || !std::isfinite(this->Fx)) {
    vtkErrorMacro(<< "Fx = " << this->Fx << " is invalid: it must be finite and non-zero");
    return false;
  }
  if (this->Fy == 0.0 || !std::isfinite(this->Fy)) {
    vtkErrorMacro(<< "Fy = " << this->Fy << " is invalid: it must be finite and non-zero");
    return false;
  }
  if (!std::isfinite(this->Cx)) {
    vtkErrorMacro(<< "Cx = " << this->Cx << " is invalid: it must be finite");
    return false;
  }
  if (!std::isfinite(this->Cy)) {
    vtkErrorMacro(<< "Cy = " << this->Cy << " is invalid: it must be finite");
    return false;
  }
  for (int k = 0; k < 4; ++k) {
    if (std::isnan(this->Color[k])) {
      vtkErrorMacro(<< "Color[" << k << "] = " << this->Color[k]
                    << " is invalid: it must be a number in [0, 1]");
      return false;
    }
  }
  return true;
}

int vtkSIMPLILayerGridSource::RequestData(vtkInformation* vtkNotUsed(request),
                                          vtkInformationVector** vtkNotUsed(inputVector),
                                          vtkInformationVector* outputVector) {
  vtkPolyData* output = vtkPolyData::GetData(outputVector, 0);
  if (!output) {
    vtkErrorMacro(<< "No vtkPolyData output to fill");
    return 0;
  }
  output->Initialize();
  if (!this->CheckSettings()) {
    return 0;
  }

  const vtkIdType w = this->Width;
  const vtkIdType h = this->Height;
  const vtkIdType numPoints = w * h;
  const vtkIdType numTriangles = 2 * (w - 1) * (h - 1);

  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataType(this->OutputPointsPrecision == DOUBLE_PRECISION ? VTK_DOUBLE : VTK_FLOAT);
  points->SetNumberOfPoints(numPoints);

  auto rgba = vtkSmartPointer<vtkUnsignedCharArray>::New();
  rgba->SetName("RGBA");
  rgba->SetNumberOfComponents(4);
  rgba->SetNumberOfTuples(numPoints);

  auto alpha = vtkSmartPointer<vtkFloatArray>::New();
  alpha->SetName("Alpha");
  alpha->SetNumberOfTuples(numPoints);

  auto depth = vtkSmartPointer<vtkFloatArray>::New();
  depth->SetName("Depth");
  depth->SetNumberOfTuples(numPoints);

  auto tcoords = vtkSmartPointer<vtkFloatArray>::New();
  tcoords->SetName("TCoords");
  tcoords->SetNumberOfComponents(2);
  tcoords->SetNumberOfTuples(numPoints);

  // Offsets/connectivity are filled directly: for big layers (4096^2 texels) this avoids
  // 33M InsertNextCell calls.
  auto offsets = vtkSmartPointer<vtkIdTypeArray>::New();
  offsets->SetNumberOfTuples(numTriangles + 1);
  auto connectivity = vtkSmartPointer<vtkIdTypeArray>::New();
  connectivity->SetNumberOfTuples(3 * numTriangles);
  for (vtkIdType t = 0; t <= numTriangles; ++t) {
    offsets->SetValue(t, 3 * t);
  }

  const unsigned char colorBytes[4] = {toByte(this->Color[0]), toByte(this->Color[1]),
                                       toByte(this->Color[2]), toByte(this->Color[3])};
  const float alphaValue = static_cast<float>(this->Color[3]);
  const float depthValue = static_cast<float>(this->Depth);
  const double d = this->Depth;

  vtkIdType tri = 0;
  for (vtkIdType i = 0; i < h; ++i) {
    this->UpdateProgress(static_cast<double>(i) / static_cast<double>(h));
    if (this->GetAbortExecute()) {
      // No partial layers: an aborted request leaves an empty output.
      vtkDebugMacro(<< "Aborted at row " << i << " of " << h);
      output->Initialize();
      return 1;
    }
    const double v = static_cast<double>(i) / static_cast<double>(h - 1);
    const double y = d * (v - this->Cy) / this->Fy;
    for (vtkIdType j = 0; j < w; ++j) {
      const double u = static_cast<double>(j) / static_cast<double>(w - 1);
      const vtkIdType b = i * w + j;
      points->SetPoint(b, d * (u - this->Cx) / this->Fx, y, d);
      rgba->SetTypedTuple(b, colorBytes);
      alpha->SetValue(b, alphaValue);
      depth->SetValue(b, depthValue);
      tcoords->SetTypedComponent(b, 0, static_cast<float>(u));
      tcoords->SetTypedComponent(b, 1, static_cast<float>(1.0 - v));
      if (i + 1 < h && j + 1 < w) {
        const vtkIdType quad[6] = {b, b + w, b + w + 1, b, b + w + 1, b + 1};
        for (vtkIdType k = 0; k < 6; ++k) {
          connectivity->SetValue(3 * tri + k, quad[k]);
        }
        tri += 2;
      }
    }
  }

  auto polys = vtkSmartPointer<vtkCellArray>::New();
  polys->SetData(offsets, connectivity);

  output->SetPoints(points);
  output->SetPolys(polys);
  vtkPointData* pd = output->GetPointData();
  pd->SetScalars(rgba);
  pd->AddArray(alpha);
  pd->AddArray(depth);
  pd->SetTCoords(tcoords);
  return 1; // the executive reports progress 1.0 itself
}

void vtkSIMPLILayerGridSource::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Width: " << this->Width << "\n";
  os << indent << "Height: " << this->Height << "\n";
  os << indent << "Depth: " << this->Depth << "\n";
  os << indent << "Fx: " << this->Fx << "\n";
  os << indent << "Fy: " << this->Fy << "\n";
  os << indent << "Cx: " << this->Cx << "\n";
  os << indent << "Cy: " << this->Cy << "\n";
  os << indent << "Color: (" << this->Color[0] << ", " << this->Color[1] << ", " << this->Color[2]
     << ", " << this->Color[3] << ")\n";
  os << indent << "OutputPointsPrecision: " << this->OutputPointsPrecision << "\n";
}

#include "vtkSIMPLILayerGridSource.h"

#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

#include "SIMPLIFilter.h"
#include "SIMPLIMLIToVTK.h"
#include "simpli/error.h"
#include "simpli/model/mli/mli.h"

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkSIMPLILayerGridSource);

namespace {

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

void vtkSIMPLILayerGridSource::CheckSettings() const {
  using simpli::fail;
  if (!(this->Depth > 0.0) || !std::isfinite(this->Depth))
    fail("Depth = ", this->Depth, " is invalid: it must be a finite value > 0");
  if (!(this->Fx > 0.0) || !std::isfinite(this->Fx))
    fail("Fx = ", this->Fx, " is invalid: it must be a finite value > 0");
  if (!(this->Fy > 0.0) || !std::isfinite(this->Fy))
    fail("Fy = ", this->Fy, " is invalid: it must be a finite value > 0");
  if (!std::isfinite(this->Cx))
    fail("Cx = ", this->Cx, " is invalid: it must be finite");
  if (!std::isfinite(this->Cy))
    fail("Cy = ", this->Cy, " is invalid: it must be finite");
  for (int k = 0; k < 4; ++k)
    if (std::isnan(this->Color[k]))
      fail("Color[", k, "] = ", this->Color[k], " is invalid: it must be a number in [0, 1]");
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
  return simpli::vtkfilter::runRequest(
      this, "SIMPLI Layer Grid Source",
      [&](const simpli::vtkfilter::Progress& progress) {
        this->CheckSettings();
        // The layer is a one-layer MLI seen from its own reference camera (identity pose), so
        // it gets the mesh and arrays of every other MLI layer in the module.
        simpli::scene::Camera camera;
        camera.fx = this->Fx;
        camera.fy = this->Fy;
        camera.cx = this->Cx;
        camera.cy = this->Cy;
        camera.width = this->Width;
        camera.height = this->Height;
        simpli::mli::MLI mli = simpli::mli::MLI::allocate(camera, 1);
        simpli::mli::MLILayer& layer = mli.layers[0];
        const float rgba[4] = {
            static_cast<float>(this->Color[0]), static_cast<float>(this->Color[1]),
            static_cast<float>(this->Color[2]), static_cast<float>(this->Color[3])};
        const std::size_t W = static_cast<std::size_t>(this->Width);
        for (int i = 0; i < this->Height; ++i) {
          if (!progress(static_cast<double>(i) / this->Height)) {
            // No partial layers: an aborted request leaves an empty output.
            vtkDebugMacro(<< "Aborted at row " << i << " of " << this->Height);
            return;
          }
          for (std::size_t p = i * W; p < (i + 1) * W; ++p) {
            layer.depth[p] = static_cast<float>(this->Depth);
            std::copy(rgba, rgba + 4, layer.rgba.begin() + static_cast<std::ptrdiff_t>(4 * p));
          }
        }
        simpli::vtkmli::LayerOptions options;
        options.opaqueFarthestLayer = false; // one layer on its own: its alpha is the user's
        options.doublePrecisionPoints = this->OutputPointsPrecision == DOUBLE_PRECISION;
        output->ShallowCopy(simpli::vtkmli::layerToPolyData(mli, 0, options));
      },
      [&] { output->Initialize(); });
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

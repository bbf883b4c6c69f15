#include "vtkSIMPLIImageQuality.h"

#include "SIMPLIFilter.h"

#include <vtkCompositeDataIterator.h>
#include <vtkCompositeDataSet.h>
#include <vtkDataArray.h>
#include <vtkDataObject.h>
#include <vtkDataSetAttributes.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkSmartPointer.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkStringArray.h>
#include <vtkTable.h>

#include "simpli/error.h"
#include "simpli/model/metrics/image_quality.h"

#include <cmath>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkSIMPLIImageQuality);

namespace {

const char* portName(int port) {
  return port == 0 ? "rendered (port 0)" : "ground truth (port 1)";
}

// The views on one port: the image itself, or the non-empty leaves of a composite data set.
std::vector<vtkImageData*> collectViews(vtkDataObject* input, int port) {
  std::vector<vtkImageData*> views;
  if (!input) {
    simpli::fail("the ", portName(port), " input is missing");
  }
  if (auto* image = vtkImageData::SafeDownCast(input)) {
    views.push_back(image);
    return views;
  }
  auto* composite = vtkCompositeDataSet::SafeDownCast(input);
  if (!composite) {
    simpli::fail("the ", portName(port), " input is a ", input->GetClassName(),
                 ", expected a vtkImageData or a composite data set of vtkImageData");
  }
  vtkSmartPointer<vtkCompositeDataIterator> it;
  it.TakeReference(composite->NewIterator());
  it->SkipEmptyNodesOn();
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem()) {
    vtkDataObject* leaf = it->GetCurrentDataObject();
    auto* image = vtkImageData::SafeDownCast(leaf);
    if (!image) {
      simpli::fail("the ", portName(port), " input: view ", views.size(), " is a ",
                   leaf->GetClassName(), ", expected a vtkImageData");
    }
    views.push_back(image);
  }
  return views;
}

// The value that maps to 1 for arrays of this type when MaxValue is 0 (automatic).
double automaticMaxValue(vtkDataArray* a, const std::string& what) {
  switch (a->GetDataType()) {
  case VTK_UNSIGNED_CHAR:
  case VTK_CHAR:
  case VTK_SIGNED_CHAR:
    return 255.0;
  case VTK_UNSIGNED_SHORT:
  case VTK_SHORT:
    return 65535.0;
  case VTK_FLOAT:
  case VTK_DOUBLE:
    return 1.0;
  default:
    simpli::fail(what, ": array of type ", a->GetDataTypeAsString(),
                 " has no automatic MaxValue; set MaxValue to the value of white");
  }
}

} // namespace

vtkSIMPLIImageQuality::vtkSIMPLIImageQuality() {
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(1);
  // Default arrays: the point scalars of each input.
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS,
                               vtkDataSetAttributes::SCALARS);
  this->SetInputArrayToProcess(1, 1, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS,
                               vtkDataSetAttributes::SCALARS);
}

int vtkSIMPLIImageQuality::FillInputPortInformation(int port, vtkInformation* info) {
  if (port < 0 || port > 1) {
    return 0;
  }
  // Composite inputs are accepted as a whole (the executive must not loop over their leaves:
  // the views of both ports are paired here).
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkCompositeDataSet");
  return 1;
}

int vtkSIMPLIImageQuality::RequestUpdateExtent(vtkInformation* vtkNotUsed(request),
                                               vtkInformationVector** inputVector,
                                               vtkInformationVector* vtkNotUsed(outputVector)) {
  for (int port = 0; port < 2; ++port) {
    vtkInformation* info = inputVector[port]->GetInformationObject(0);
    if (info && info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT())) {
      int extent[6];
      info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), extent, 6);
    }
  }
  return 1;
}

namespace {

// One view as a metric image (row 0 = top), values scaled to [0, 1]. `a` is the array chosen
// for this view (null when absent), `association` its attribute type.
simpli::metrics::MetricImage toMetricImage(vtkDataArray* a, int association, int idx,
                                           vtkImageData* image, double maxValue,
                                           const std::string& what) {
  if (!a) {
    simpli::fail(what, ": the array to compare is missing (by default the point scalars; ",
                 "select one with SetInputArrayToProcess(", idx, ", ...))");
  }
  const std::string arrayWhat = what + ", array \"" + (a->GetName() ? a->GetName() : "") + "\"";
  int dims[3];
  image->GetDimensions(dims);
  if (association == vtkDataObject::FIELD_ASSOCIATION_CELLS) {
    for (int& d : dims) {
      d = d > 1 ? d - 1 : 1;
    }
  }
  if (dims[2] != 1) {
    simpli::fail(what, ": image is ", dims[0], " x ", dims[1], " x ", dims[2],
                 ", expected a 2-D image (one slice)");
  }
  const int w = dims[0], h = dims[1];
  if (a->GetNumberOfTuples() != static_cast<vtkIdType>(w) * h) {
    simpli::fail(arrayWhat, ": ", a->GetNumberOfTuples(), " tuples for a ", w, " x ", h, " image");
  }
  const int nc = a->GetNumberOfComponents();
  if (nc != 1 && nc != 3 && nc != 4) {
    simpli::fail(arrayWhat, ": ", nc, " components, expected 1 (grey), 3 (RGB) or 4 (RGBA)");
  }
  const int channels = nc == 4 ? 3 : nc;
  const double scale = maxValue > 0.0 ? maxValue : automaticMaxValue(a, arrayWhat);
  simpli::metrics::MetricImage m(w, h, channels);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      // VTK images start at the bottom row; metric images at the top.
      const vtkIdType t = static_cast<vtkIdType>(h - 1 - y) * w + x;
      for (int c = 0; c < channels; ++c) {
        double v = a->GetComponent(t, c) / scale;
        if (!(v >= -1e-4 && v <= 1.0 + 1e-4)) {
          simpli::fail(arrayWhat, ": value ", a->GetComponent(t, c), " at (x ", x, ", y ",
                       h - 1 - y, "), component ", c, " is outside [0, ", scale,
                       "] (MaxValue = ", scale, ")");
        }
        v = v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
        m.at(y, x, c) = static_cast<float>(v);
      }
    }
  }
  return m;
}

// PSNR and SSIM of one view pair on the central crop; errors name the view.
simpli::metrics::ImageQuality viewQuality(const simpli::metrics::MetricImage& r,
                                          const simpli::metrics::MetricImage& g, double crop,
                                          const std::string& view) {
  if (r.width != g.width || r.height != g.height || r.channels != g.channels)
    simpli::fail(view, ": rendered image is ", r.width, " x ", r.height, " with ", r.channels,
                 " channel(s) but the ground truth is ", g.width, " x ", g.height, " with ",
                 g.channels);
  try {
    return simpli::metrics::evaluateImageQuality(r, g, crop);
  } catch (const simpli::Error& e) {
    simpli::fail(view, ": ", e.what());
  }
}

// The output table: View ("0", "1", ..., "mean", "std"), PSNR, SSIM.
void fillQualityTable(const std::vector<simpli::metrics::ImageQuality>& qualities,
                      vtkTable* output) {
  auto views = vtkSmartPointer<vtkStringArray>::New();
  views->SetName("View");
  auto psnr = vtkSmartPointer<vtkDoubleArray>::New();
  psnr->SetName("PSNR");
  auto ssim = vtkSmartPointer<vtkDoubleArray>::New();
  ssim->SetName("SSIM");
  std::vector<double> psnrs, ssims;
  for (std::size_t v = 0; v < qualities.size(); ++v) {
    views->InsertNextValue(std::to_string(v));
    psnr->InsertNextValue(qualities[v].psnr);
    ssim->InsertNextValue(qualities[v].ssim);
    psnrs.push_back(qualities[v].psnr);
    ssims.push_back(qualities[v].ssim);
  }
  const simpli::metrics::MeanStd ps = simpli::metrics::meanAndStd(psnrs),
                                 ss = simpli::metrics::meanAndStd(ssims);
  views->InsertNextValue("mean");
  psnr->InsertNextValue(ps.mean);
  ssim->InsertNextValue(ss.mean);
  views->InsertNextValue("std");
  psnr->InsertNextValue(ps.std);
  ssim->InsertNextValue(ss.std);
  output->AddColumn(views);
  output->AddColumn(psnr);
  output->AddColumn(ssim);
}

} // namespace

int vtkSIMPLIImageQuality::RequestData(vtkInformation* vtkNotUsed(request),
                                       vtkInformationVector** inputVector,
                                       vtkInformationVector* outputVector) {
  vtkTable* output = vtkTable::GetData(outputVector, 0);
  if (!output) {
    vtkErrorMacro(<< "No vtkTable output to fill");
    return 0;
  }
  output->Initialize();

  return simpli::vtkfilter::runRequest(
      this, "Image quality",
      [&](const simpli::vtkfilter::Progress& progress) {
        const std::vector<vtkImageData*> rendered =
            collectViews(vtkDataObject::GetData(inputVector[0], 0), 0);
        const std::vector<vtkImageData*> truth =
            collectViews(vtkDataObject::GetData(inputVector[1], 0), 1);
        if (rendered.empty())
          simpli::fail("the ", portName(0), " input holds no image");
        if (rendered.size() != truth.size())
          simpli::fail("the ", portName(0), " input holds ", rendered.size(), " view(s) but the ",
                       portName(1), " input holds ", truth.size());
        std::vector<simpli::metrics::ImageQuality> qualities;
        for (std::size_t v = 0; v < rendered.size(); ++v) {
          if (!progress(static_cast<double>(v) / static_cast<double>(rendered.size())))
            return; // aborted: empty table, no error
          const std::string view = "view " + std::to_string(v);
          int assocR = vtkDataObject::FIELD_ASSOCIATION_POINTS;
          int assocG = vtkDataObject::FIELD_ASSOCIATION_POINTS;
          vtkDataArray* arrayR = this->GetInputArrayToProcess(0, rendered[v], assocR);
          vtkDataArray* arrayG = this->GetInputArrayToProcess(1, truth[v], assocG);
          const simpli::metrics::MetricImage r = toMetricImage(
              arrayR, assocR, 0, rendered[v], this->MaxValue, view + ", " + portName(0));
          const simpli::metrics::MetricImage g =
              toMetricImage(arrayG, assocG, 1, truth[v], this->MaxValue, view + ", " + portName(1));
          qualities.push_back(viewQuality(r, g, this->CropAreaFraction, view));
        }
        fillQualityTable(qualities, output);
      },
      [output] { output->Initialize(); });
}

void vtkSIMPLIImageQuality::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "CropAreaFraction: " << this->CropAreaFraction << "\n";
  os << indent << "MaxValue: " << this->MaxValue << (this->MaxValue > 0 ? "" : " (automatic)")
     << "\n";
}

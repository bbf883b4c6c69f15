#include "vtkMLIReader.h"

#include "SIMPLIFilter.h"
#include "SIMPLIMLIToVTK.h"

#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPartitionedDataSetCollection.h>

#include "simpli/error.h"
#include "simpli/model/mli/files.h"

#include <exception>
#include <filesystem>

vtkStandardNewMacro(vtkMLIReader);

vtkMLIReader::vtkMLIReader() {
  this->SetNumberOfInputPorts(0);
}

vtkMLIReader::~vtkMLIReader() {
  this->SetFileName(nullptr);
}

std::string vtkMLIReader::FolderOf(const char* name) {
  namespace fs = std::filesystem;
  const fs::path path(name);
  std::error_code ec;
  // ParaView's File > Open hands over the meta.json it matched; the MLI is its folder.
  if (path.filename() == "meta.json" && fs::is_regular_file(path, ec))
    return path.parent_path().empty() ? std::string(".") : path.parent_path().string();
  return path.string();
}

int vtkMLIReader::CanReadFile(const char* name) {
  if (!name || !*name)
    return 0;
  try {
    simpli::mli::detectMLIFormat(FolderOf(name));
    return 1;
  } catch (const std::exception&) {
    return 0;
  }
}

int vtkMLIReader::RequestData(vtkInformation* vtkNotUsed(request),
                              vtkInformationVector** vtkNotUsed(inputVector),
                              vtkInformationVector* outputVector) {
  vtkPartitionedDataSetCollection* output = vtkPartitionedDataSetCollection::GetData(outputVector);
  if (!output) {
    vtkErrorMacro(<< "No vtkPartitionedDataSetCollection output to fill");
    return 0;
  }
  output->Initialize();
  if (!this->FileName || !*this->FileName) {
    vtkErrorMacro(<< "FileName is not set (expected an MLI folder)");
    return 0;
  }

  const std::string what = std::string("Cannot read MLI '") + this->FileName + "'";
  return simpli::vtkfilter::runRequest(
      this, what,
      [&](const simpli::vtkfilter::Progress& progress) {
        simpli::mli::MLIReadOptions readOptions;
        readOptions.depthDecoding = this->DepthDecoding == DEPTH_BIN_CENTRE
                                        ? simpli::mli::MLIDepthDecoding::BinCentre
                                        : simpli::mli::MLIDepthDecoding::Viewer;
        progress(0.0);
        const simpli::mli::MLI mli = simpli::mli::readMLI(FolderOf(this->FileName), readOptions);
        if (progress.aborted())
          return; // aborted: empty output, no error
        simpli::vtkmli::LayerOptions options;
        options.dropTransparentTriangles = this->DropTransparentTriangles;
        options.skipEmptyLayers = this->SkipEmptyLayers;
        options.alphaThreshold = this->AlphaThreshold;
        options.meshMode = this->MeshMode == MESH_ADAPTIVE ? simpli::vtkmli::MeshMode::Adaptive
                                                           : simpli::vtkmli::MeshMode::PerTexel;
        options.meshTolerance = this->MeshTolerance;
        // Decoding the images dominates; call it half of the work, the meshes the other half.
        if (!simpli::vtkmli::mliToCollection(mli, options, output, progress.range(0.5, 1.0)))
          vtkDebugMacro(<< "Aborted while building the layer meshes of " << this->FileName);
      },
      [output] { output->Initialize(); });
}

void vtkMLIReader::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "DropTransparentTriangles: " << this->DropTransparentTriangles << "\n";
  os << indent << "SkipEmptyLayers: " << this->SkipEmptyLayers << "\n";
  os << indent << "AlphaThreshold: " << this->AlphaThreshold << "\n";
  os << indent << "MeshMode: " << (this->MeshMode == MESH_ADAPTIVE ? "Adaptive" : "PerTexel")
     << "\n";
  os << indent << "MeshTolerance: " << this->MeshTolerance << "\n";
  os << indent
     << "DepthDecoding: " << (this->DepthDecoding == DEPTH_BIN_CENTRE ? "BinCentre" : "Viewer")
     << "\n";
}

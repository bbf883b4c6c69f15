#include "vtkMLIWriter.h"

#include "SIMPLIFilter.h"
#include "SIMPLIMLIToVTK.h"

#include <vtkCommand.h>
#include <vtkErrorCode.h>
#include <vtkInformation.h>
#include <vtkInformationVector.h>
#include <vtkObjectFactory.h>
#include <vtkPartitionedDataSetCollection.h>

#include "simpli/error.h"
#include "simpli/model/mli/files.h"

#include <exception>
#include <string>

vtkStandardNewMacro(vtkMLIWriter);

vtkMLIWriter::vtkMLIWriter() = default;

vtkMLIWriter::~vtkMLIWriter() {
  this->SetFileName(nullptr);
}

int vtkMLIWriter::FillInputPortInformation(int port, vtkInformation* info) {
  if (port != 0) {
    return 0;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPartitionedDataSetCollection");
  return 1;
}

int vtkMLIWriter::Write() {
  this->SetErrorCode(vtkErrorCode::NoError);
  const int ok = this->Superclass::Write();
  return ok && this->GetErrorCode() == vtkErrorCode::NoError ? 1 : 0;
}

bool vtkMLIWriter::WriteCollection(vtkPartitionedDataSetCollection* input) {
  if (!this->FileName || !*this->FileName) {
    vtkErrorMacro(<< "FileName is not set (expected the MLI folder to write)");
    this->SetErrorCode(vtkErrorCode::NoFileNameError);
    return false;
  }
  if (!input) {
    vtkErrorMacro(<< "Cannot write MLI '" << this->FileName
                  << "': no input (expected a vtkPartitionedDataSetCollection of layers)");
    this->SetErrorCode(vtkErrorCode::UnknownError);
    return false;
  }
  const simpli::mli::MLIFormat format = this->Format == FORMAT_LOSSLESS
                                            ? simpli::mli::MLIFormat::Lossless
                                            : simpli::mli::MLIFormat::Jpeg;
  // The collection's own errors name the MLI ("MLI '<FileName>': ...").
  return simpli::vtkfilter::runRequest(
             this, "Cannot write",
             [&](const simpli::vtkfilter::Progress& progress) {
               progress(0.0);
               const simpli::mli::MLI mli = simpli::vtkmli::collectionToMLI(
                   input, std::string("MLI '") + this->FileName + "'");
               progress(0.2);
               // One call, atomic: it either produces the complete folder or leaves none behind.
               simpli::mli::writeMLI(this->FileName, mli, format);
             },
             [this] { this->SetErrorCode(vtkErrorCode::UnknownError); }) != 0;
}

int vtkMLIWriter::RequestData(vtkInformation* vtkNotUsed(request),
                              vtkInformationVector** inputVector,
                              vtkInformationVector* vtkNotUsed(outputVector)) {
  this->SetErrorCode(vtkErrorCode::NoError);
  vtkPartitionedDataSetCollection* input =
      vtkPartitionedDataSetCollection::GetData(inputVector[0], 0);
  this->InvokeEvent(vtkCommand::StartEvent, nullptr);
  const bool ok = this->WriteCollection(input);
  this->InvokeEvent(vtkCommand::EndEvent, nullptr);
  if (!ok) {
    return 0;
  }
  this->WriteTime.Modified();
  return 1;
}

void vtkMLIWriter::WriteData() {
  // vtkWriter's own RequestData would call this; ours calls WriteCollection directly so that a
  // failure can fail the request. Kept for callers that invoke WriteData() themselves.
  this->WriteCollection(vtkPartitionedDataSetCollection::SafeDownCast(this->GetInput()));
}

void vtkMLIWriter::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "Format: " << (this->Format == FORMAT_LOSSLESS ? "Lossless" : "Jpeg") << "\n";
}

/**
 * @class   vtkMLIWriter
 * @brief   writes layer meshes as a SIMPLI multi-layer image (MLI) folder
 *
 * The input is a vtkPartitionedDataSetCollection in the layout that vtkMLIReader produces
 * (see vtkMLIReader.h): one data set per layer, back to front, each with W x H points and the
 * point arrays "Color" (3 components), "Alpha" and "Depth", and the reference camera in the
 * collection's field data ("CameraIntrinsics", "CameraExtrinsics", "CameraImageSize"). The
 * layer images come from Color, Alpha and Depth (the 8-bit "RGBA" is not read) and the point
 * coordinates are not read either: an MLI stores depths, and its geometry follows from them
 * and the camera. Every data set in the collection becomes a layer, in collection order.
 *
 * Format selects the folder form: FORMAT_JPEG, the reference form of the SIMPLI project page
 * (lossy: 8-bit colour and alpha, 8-bit depth per layer range), or FORMAT_LOSSLESS, simpli's
 * float TIFF form (exact).
 *
 * The write is atomic: the folder is assembled in a hidden temporary sibling and renamed into
 * place when complete, so a failure never leaves a partial MLI, and an existing MLI folder at
 * FileName is replaced only by a complete one. Only an MLI that simpli wrote and that holds
 * nothing else is replaced (simpli::mli::mliReplaceRefusal); any other non-empty folder is
 * refused with an error naming it and the entry, never emptied. Invalid input (missing camera array or point array, a layer whose point count is
 * not W x H, values out of range, ...) fails the request with vtkErrorMacro naming the file,
 * the layer, the array and the value; Write() then returns 0 and nothing is written.
 */

#ifndef vtkMLIWriter_h
#define vtkMLIWriter_h

#include "vtkSimpliFiltersModule.h" // for export macro
#include <vtkWriter.h>

class vtkPartitionedDataSetCollection;

class VTKSIMPLIFILTERS_EXPORT vtkMLIWriter : public vtkWriter {
public:
  static vtkMLIWriter* New();
  vtkTypeMacro(vtkMLIWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The MLI folder to create (or replace).
   */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  enum Formats {
    FORMAT_JPEG = 0,    ///< reference JPEG form (layer_XX.jpg, layer_alpha_XX.jpg, ...)
    FORMAT_LOSSLESS = 1 ///< simpli's 32-bit float TIFF form
  };

  ///@{
  /**
   * The folder form. Default FORMAT_JPEG (readable by the official web viewer).
   */
  vtkSetClampMacro(Format, int, FORMAT_JPEG, FORMAT_LOSSLESS);
  vtkGetMacro(Format, int);
  void SetFormatToJpeg() { this->SetFormat(FORMAT_JPEG); }
  void SetFormatToLossless() { this->SetFormat(FORMAT_LOSSLESS); }
  ///@}

  /**
   * Writes the input. Returns 1 on success, 0 when the request failed (the error was reported
   * with vtkErrorMacro and GetErrorCode() is not vtkErrorCode::NoError).
   */
  int Write() override;

protected:
  vtkMLIWriter();
  ~vtkMLIWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;
  void WriteData() override;

  // Writes `input`; reports the failure and returns false on error.
  bool WriteCollection(vtkPartitionedDataSetCollection* input);

  char* FileName = nullptr;
  int Format = FORMAT_JPEG;

private:
  vtkMLIWriter(const vtkMLIWriter&) = delete;
  void operator=(const vtkMLIWriter&) = delete;
};

#endif

/**
 * @class   vtkSIMPLISceneReader
 * @brief   reads a multi-view scene folder (LLFF, COLMAP text, RealEstate10K) as images and cameras
 *
 * FileName is a scene folder (or a poses_bounds.npy / camera .txt file given directly); the
 * format is detected from its contents by simpli::readScene (simpli/model/scene.h): LLFF
 * (poses_bounds.npy + images/), a COLMAP text model (sparse/0/cameras.txt, images.txt, ...) or
 * a RealEstate10K / SWORD camera file. Cameras, bounds and points are normalised like the
 * network sees them (the near bound lands on depth 1, or SfM point percentiles; see
 * simpli/model/normalisation.h) unless Normalise is off.
 *
 * Output port 0: a vtkPartitionedDataSetCollection, one vtkPartitionedDataSet per view holding
 * one vtkImageData (W x H x 1, spacing 1, origin 0; VTK's row 0 is the bottom image row), named
 * after the view ("View000", ...), with a vtkDataAssembly /Scene/Views/ViewNNN. Image point data
 * "RGB" (vtkUnsignedCharArray, 3 components, the active scalars). Image field data, the view's
 * camera in the module's conventions (OpenCV axes, relative intrinsics, z-depth):
 *   - "CameraIntrinsics" (double, 4): fx, fy, cx, cy relative to the image size;
 *   - "CameraExtrinsics" (double, 12): world->camera [R | t], 3 x 4 row-major;
 *   - "CameraImageSize" (int, 2): width, height;
 *   - "ViewIndex" (int), "ViewName" and "ImagePath" (strings).
 * Collection field data: "NearFar" (double, 2: near and far bound, in the output's units),
 * "NormalisationScale" (double: output units per scene unit; 1 when Normalise is off),
 * "SceneFormat" (string: LLFF, COLMAP, RealEstate10K), "NumberOfViews" (int).
 *
 * Output port 1: a vtkPolyData with one camera frustum per view: the centre and the four image
 * corners back-projected at depth FrustumScale, joined by one polyline per view (the rectangle
 * and the four edges to the centre). Cell data "ViewIndex" (int); field data "NearFar" as on
 * port 0.
 *
 * Errors (missing folder, unknown format, malformed pose files, unreadable images, ...) are
 * reported with vtkErrorMacro naming the path, the field and the value; the request fails with
 * empty outputs. Progress: reading (most of the work), then per view; an abort leaves empty
 * outputs.
 */

#ifndef vtkSIMPLISceneReader_h
#define vtkSIMPLISceneReader_h

#include "vtkSimpliFiltersModule.h" // for export macro
#include <vtkPartitionedDataSetCollectionAlgorithm.h>

class VTKSIMPLIFILTERS_EXPORT vtkSIMPLISceneReader
    : public vtkPartitionedDataSetCollectionAlgorithm {
public:
  static vtkSIMPLISceneReader* New();
  vtkTypeMacro(vtkSIMPLISceneReader, vtkPartitionedDataSetCollectionAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The scene folder (or its poses_bounds.npy / camera .txt file).
   */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  /**
   * 1 if `name` is a folder or file whose scene format can be detected, else 0 (reads no
   * images).
   */
  int CanReadFile(const char* name);

  ///@{
  /**
   * Depth of the frustum base (the back-projected image corners) in the output's units,
   * > 0. Default 0.25.
   */
  vtkSetClampMacro(FrustumScale, double, 1e-9, VTK_DOUBLE_MAX);
  vtkGetMacro(FrustumScale, double);
  ///@}

  ///@{
  /**
   * Normalise the scene as the network expects it (default on); off keeps the scene's units.
   */
  vtkSetMacro(Normalise, bool);
  vtkGetMacro(Normalise, bool);
  vtkBooleanMacro(Normalise, bool);
  ///@}

  ///@{
  /**
   * Images are resized down to a multiple of this (the network needs 16); <= 1 keeps the
   * stored size. Default 16, as readScene.
   */
  vtkSetClampMacro(SizeMultiple, int, 0, 4096);
  vtkGetMacro(SizeMultiple, int);
  ///@}

  ///@{
  /**
   * Image folder relative to the scene folder (e.g. images_4 for LLFF); empty: "images".
   */
  vtkSetStringMacro(ImagesDirectory);
  vtkGetStringMacro(ImagesDirectory);
  ///@}

  /**
   * Convenience: the frustum output (port 1).
   */
  vtkAlgorithmOutput* GetFrustumOutputPort() { return this->GetOutputPort(1); }

protected:
  vtkSIMPLISceneReader();
  ~vtkSIMPLISceneReader() override;

  int FillOutputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  char* FileName = nullptr;
  double FrustumScale = 0.25;
  bool Normalise = true;
  int SizeMultiple = 16;
  char* ImagesDirectory = nullptr;

private:
  vtkSIMPLISceneReader(const vtkSIMPLISceneReader&) = delete;
  void operator=(const vtkSIMPLISceneReader&) = delete;
};

#endif

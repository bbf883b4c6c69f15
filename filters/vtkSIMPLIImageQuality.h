/**
 * @class   vtkSIMPLIImageQuality
 * @brief   PSNR and SSIM of rendered views against ground-truth images (the paper's protocol)
 *
 * Input port 0 takes the rendered views, port 1 the ground truth. Each input is either one
 * vtkImageData (one view) or a composite data set (vtkPartitionedDataSet,
 * vtkPartitionedDataSetCollection, vtkMultiBlockDataSet, ...) whose non-empty leaves are
 * vtkImageData, one per view; the k-th leaf of port 0 is compared with the k-th leaf of port 1
 * (leaves in the iteration order of vtkCompositeDataSet).
 *
 * The compared array is the input array to process: index 0 for port 0, index 1 for port 1,
 * by default the point scalars of each image (SetInputArrayToProcess selects others, point or
 * cell data). It needs 1, 3 or 4 components; with 4 (RGBA screenshots) the 4th is ignored.
 * Values are divided by MaxValue (0, the default, means: 255 for 8-bit integer arrays, 65535
 * for 16-bit ones, 1 for floating-point arrays) and must then lie in [0, 1] (up to 1e-4, which
 * is clamped away); anything else is an error, since it usually means a [-1, 1] image or a
 * wrong MaxValue.
 *
 * Each pair is cropped centrally to CropAreaFraction of its area (default 0.9: each side loses
 * round(size (1 - sqrt(0.9)) / 2) pixels, the protocol of the SIMPLI paper) and compared with
 * simpli's metrics (simpli/model/metrics.h): PSNR with peak 1, and SSIM of Wang et al. (11 x 11
 * Gaussian window, sigma 1.5, K1 = 0.01, K2 = 0.03, mean over the valid window positions and
 * over channels). Identical views have PSNR = inf.
 *
 * Output: a vtkTable with the columns "View" (string: "0", "1", ..., "mean", "std"), "PSNR"
 * and "SSIM" (double): one row per view, then the mean and the population standard deviation
 * over the views.
 *
 * Errors (no image, different view counts, images of different sizes, 3-D images, missing or
 * unsuitable arrays, out-of-range values, images smaller than the SSIM window after cropping)
 * are reported with vtkErrorMacro naming the view, the port, the array and the value, and the
 * request fails with an empty table.
 */

#ifndef vtkSIMPLIImageQuality_h
#define vtkSIMPLIImageQuality_h

#include "vtkSimpliFiltersModule.h" // for export macro
#include <vtkTableAlgorithm.h>

class VTKSIMPLIFILTERS_EXPORT vtkSIMPLIImageQuality : public vtkTableAlgorithm {
public:
  static vtkSIMPLIImageQuality* New();
  vtkTypeMacro(vtkSIMPLIImageQuality, vtkTableAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * Convenience for port 1 (the ground truth); port 0 is SetInputConnection(0, ...).
   */
  void SetGroundTruthConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }

  ///@{
  /**
   * Fraction of the image area kept by the central crop, in (0, 1]. Default 0.9.
   */
  vtkSetClampMacro(CropAreaFraction, double, 1e-6, 1.0);
  vtkGetMacro(CropAreaFraction, double);
  ///@}

  ///@{
  /**
   * The array value that maps to 1 (white); 0 selects it from the array type (255 for 8-bit
   * integers, 65535 for 16-bit integers, 1 for floating point). Default 0.
   */
  vtkSetClampMacro(MaxValue, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaxValue, double);
  ///@}

protected:
  vtkSIMPLIImageQuality();
  ~vtkSIMPLIImageQuality() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  // Each image input is requested whole (its own whole extent): the two ports may hold images
  // of different sizes, which is an error reported by RequestData, not a pipeline failure.
  int RequestUpdateExtent(vtkInformation* request, vtkInformationVector** inputVector,
                          vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  double CropAreaFraction = 0.9;
  double MaxValue = 0.0;

private:
  vtkSIMPLIImageQuality(const vtkSIMPLIImageQuality&) = delete;
  void operator=(const vtkSIMPLIImageQuality&) = delete;
};

#endif

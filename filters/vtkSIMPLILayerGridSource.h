/**
 * @class   vtkSIMPLILayerGridSource
 * @brief   one MLI layer mesh for a constant-depth plane seen by a pinhole camera
 *
 * vtkSIMPLILayerGridSource emits the mesh that SIMPLI uses for one layer of a multiplane or
 * layered image (MPI/MLI) when every texel of the layer lies at the same depth. It is the
 * simplest instance of the layer-mesh conventions of the simpli VTK module, so that pipelines,
 * renderings and the ParaView plugin can be checked against an analytic answer.
 *
 * Geometry. The layer has Width x Height texels, one vertex per texel (SIMPLI samples layer
 * textures exactly at the vertices). Vertex (i, j) (row i, column j, from 0) sits on the corner
 * grid u = j / (Width - 1), v = i / (Height - 1), not on the texel centre, and is
 * back-projected through the reference camera with relative intrinsics (Fx, Fy, Cx, Cy), in
 * the OpenCV convention (x right, y down, z forward):
 *
 *   X = Depth * ((u - Cx) / Fx, (v - Cy) / Fy, 1)
 *
 * The world frame is the reference camera frame. Point b = i * Width + j is vertex (i, j);
 * every quad of neighbouring vertices yields the triangles (b, b + Width, b + Width + 1) and
 * (b, b + Width + 1, b + 1).
 *
 * Point data: "RGBA" (vtkUnsignedCharArray, 4 components, the active scalars; render it with
 * direct scalars / MapScalars off), "Alpha" and "Depth" (vtkFloatArray, 1 component) and the
 * texture coordinates "TCoords" = (u, 1 - v), so that image row 0 is the top of a texture.
 *
 * The layer is built as a one-layer MLI through the module's MLI-to-VTK conversion, so it also
 * carries that layout's "Color" array and "LayerIndex" field data (SIMPLIMLIToVTK.h).
 *
 * Invalid settings (a Depth, Fx or Fy that is not > 0, non-finite values) are reported
 * with vtkErrorMacro naming the property and its value, and the request fails.
 */

#ifndef vtkSIMPLILayerGridSource_h
#define vtkSIMPLILayerGridSource_h

#include "vtkSimpliFiltersModule.h" // for export macro
#include <vtkPolyDataAlgorithm.h>

class VTKSIMPLIFILTERS_EXPORT vtkSIMPLILayerGridSource : public vtkPolyDataAlgorithm {
public:
  static vtkSIMPLILayerGridSource* New();
  vtkTypeMacro(vtkSIMPLILayerGridSource, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Layer resolution in texels (= vertices per row / column of the corner grid).
   * Clamped to [2, 4096]; default 16 x 16.
   */
  vtkSetClampMacro(Width, int, 2, 4096);
  vtkGetMacro(Width, int);
  vtkSetClampMacro(Height, int, 2, 4096);
  vtkGetMacro(Height, int);
  ///@}

  ///@{
  /**
   * z-depth of the plane in the reference camera frame. Must be > 0; it is checked (not
   * clamped) when the data is generated, so that a wrong value is reported. Default 1.
   */
  vtkSetMacro(Depth, double);
  vtkGetMacro(Depth, double);
  ///@}

  ///@{
  /**
   * Intrinsics relative to the image size (fx / width, fy / height, cx / width, cy / height).
   * Fx and Fy must be > 0 (an MLI's reference camera). Defaults: Fx = Fy = 1, Cx = Cy = 0.5.
   */
  vtkSetMacro(Fx, double);
  vtkGetMacro(Fx, double);
  vtkSetMacro(Fy, double);
  vtkGetMacro(Fy, double);
  vtkSetMacro(Cx, double);
  vtkGetMacro(Cx, double);
  vtkSetMacro(Cy, double);
  vtkGetMacro(Cy, double);
  ///@}

  ///@{
  /**
   * Constant colour of the layer, RGBA in [0, 1] (each component is clamped). Default opaque
   * white.
   */
  void SetColor(double r, double g, double b, double a);
  void SetColor(const double rgba[4]) { this->SetColor(rgba[0], rgba[1], rgba[2], rgba[3]); }
  vtkGetVector4Macro(Color, double);
  ///@}

  ///@{
  /**
   * Precision of the output points: vtkAlgorithm::SINGLE_PRECISION (default) or
   * vtkAlgorithm::DOUBLE_PRECISION.
   */
  vtkSetClampMacro(OutputPointsPrecision, int, SINGLE_PRECISION, DOUBLE_PRECISION);
  vtkGetMacro(OutputPointsPrecision, int);
  ///@}

protected:
  vtkSIMPLILayerGridSource();
  ~vtkSIMPLILayerGridSource() override = default;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  // Throws simpli::Error naming the first invalid property and its value.
  void CheckSettings() const;

  int Width = 16;
  int Height = 16;
  double Depth = 1.0;
  double Fx = 1.0;
  double Fy = 1.0;
  double Cx = 0.5;
  double Cy = 0.5;
  double Color[4] = {1.0, 1.0, 1.0, 1.0};
  int OutputPointsPrecision = SINGLE_PRECISION;

private:
  vtkSIMPLILayerGridSource(const vtkSIMPLILayerGridSource&) = delete;
  void operator=(const vtkSIMPLILayerGridSource&) = delete;
};

#endif

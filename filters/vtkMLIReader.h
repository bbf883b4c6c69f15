/**
 * @class   vtkMLIReader
 * @brief   reads a SIMPLI multi-layer image (MLI) folder into layer meshes
 *
 * An MLI is a folder holding meta.json and per-layer images, in one of two forms that the
 * reader tells apart by meta.json (simpli/model/mli_io.h): the reference JPEG form of the
 * SIMPLI project page (8-bit colour and alpha, 8-bit depth per layer range) and simpli's
 * lossless form (32-bit float TIFFs). FileName is the folder, or the meta.json inside it.
 *
 * Output: a vtkPartitionedDataSetCollection, one vtkPartitionedDataSet holding one vtkPolyData
 * per layer, back to front (dataset 0 = layer 00, the farthest), named "LayerKK", with a
 * vtkDataAssembly /MLI/Layers/LayerKK.
 *
 * Layer meshes (MeshMode MESH_PER_TEXEL, the default): one point per texel on the corner grid
 * u = j/(W-1), v = i/(H-1), back-projected at the texel depth through the reference camera into
 * world coordinates; two triangles per texel quad. Point data:
 *   - "RGBA" (vtkUnsignedCharArray, 4 components, the active scalars): round(255 x) of the
 *     straight colour and alpha; render with direct scalars (ParaView: MapScalars off);
 *   - "Color" (float, 3 components) and "Alpha" (float): the exact texel values in [0, 1];
 *   - "Depth" (float): reference-camera z;
 *   - "TCoords" (float, 2 components, the active texture coordinates): (u, 1 - v).
 * Layer field data: "LayerIndex" (int). Collection field data, the reference camera:
 *   - "CameraIntrinsics" (double, 4 components): fx, fy, cx, cy relative to the image size;
 *   - "CameraExtrinsics" (double, 12 components): world->camera [R | t], 3 x 4 row-major;
 *   - "CameraImageSize" (int, 2 components): layer width and height in texels;
 *   - "NumberOfLayers" (int): L of the MLI, including layers left out by SkipEmptyLayers.
 * MeshMode MESH_ADAPTIVE: adaptive meshes (simpli/model/mli/adaptive_mesh.h) with "TCoords" and
 * "Depth" per point and the layer's texels in its field data ("TextureRGBA" for a texture,
 * exact "TextureColor", "TextureAlpha", "TextureDepth", "TextureSize").
 * vtkMLIWriter writes either layout back; with the lossless form the round trip is exact.
 *
 * Errors (missing folder, malformed meta.json, unreadable or mis-sized layer image, invalid
 * values) are reported with vtkErrorMacro, naming the file, the field and the value, and the
 * request fails with an empty output. Progress is reported per layer; an abort leaves an empty
 * output.
 */

#ifndef vtkMLIReader_h
#define vtkMLIReader_h

#include "vtkSimpliFiltersModule.h" // for export macro
#include <vtkPartitionedDataSetCollectionAlgorithm.h>

#include <string> // for std::string

class VTKSIMPLIFILTERS_EXPORT vtkMLIReader : public vtkPartitionedDataSetCollectionAlgorithm {
public:
  static vtkMLIReader* New();
  vtkTypeMacro(vtkMLIReader, vtkPartitionedDataSetCollectionAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The MLI folder (or its meta.json).
   */
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  /**
   * 1 if `name` is an MLI folder (or the meta.json of one) whose meta.json is valid, else 0.
   * Reads meta.json only.
   */
  int CanReadFile(const char* name);

  ///@{
  /**
   * Drop the triangles whose three vertices all have an alpha below AlphaThreshold (points are
   * kept, so that they stay one-to-one with texels). Default off: the full reference mesh.
   */
  vtkSetMacro(DropTransparentTriangles, bool);
  vtkGetMacro(DropTransparentTriangles, bool);
  vtkBooleanMacro(DropTransparentTriangles, bool);
  ///@}

  ///@{
  /**
   * Leave out the layers whose every alpha is below AlphaThreshold. Default off.
   */
  vtkSetMacro(SkipEmptyLayers, bool);
  vtkGetMacro(SkipEmptyLayers, bool);
  vtkBooleanMacro(SkipEmptyLayers, bool);
  ///@}

  ///@{
  /**
   * Alpha below which a triangle or layer counts as transparent, in [0, 1]. Default 1/255 (what
   * an 8-bit export rounds to 0).
   */
  vtkSetClampMacro(AlphaThreshold, double, 0.0, 1.0);
  vtkGetMacro(AlphaThreshold, double);
  ///@}

  enum MeshModes {
    MESH_PER_TEXEL = 0, ///< one point per texel, per-point RGBA (the reference mesh)
    MESH_ADAPTIVE = 1   ///< adaptive mesh, RGBA as a per-layer texture (real-time display)
  };

  ///@{
  /**
   * The layers' mesh form. MESH_PER_TEXEL (default): one point per texel with per-point RGBA,
   * what the rasterizer and training use. MESH_ADAPTIVE: triangles only where the depth needs
   * them (within MeshTolerance) and where something is visible (alpha >= AlphaThreshold), depth
   * steps cut rather than bridged, TCoords per point and the RGBA at full resolution in the
   * layer's field data (TextureRGBA ..., see SIMPLIMLIToVTK.h); draw it with a texture per layer.
   */
  vtkSetClampMacro(MeshMode, int, MESH_PER_TEXEL, MESH_ADAPTIVE);
  vtkGetMacro(MeshMode, int);
  ///@}

  ///@{
  /**
   * MESH_ADAPTIVE: largest reprojection error in pixels of the layer grid, at the visible
   * texels, for a camera displaced by 0.05 x the MLI's focus depth (mli/adaptive_mesh.h).
   * Default 1 (60-65 fps at 1024x768 on 2 CPU cores, < 0.05 dB; docs/benchmarks.md).
   */
  vtkSetClampMacro(MeshTolerance, double, 0.0, 1.0e6);
  vtkGetMacro(MeshTolerance, double);
  ///@}

  enum DepthDecodings {
    DEPTH_VIEWER = 0,    ///< D = lo + q (hi - lo) / 255, as the official web viewer decodes
    DEPTH_BIN_CENTRE = 1 ///< D = lo + (q + 0.5)(hi - lo) / 256, the centre of the encoder's bin
  };

  ///@{
  /**
   * How 8-bit depth codes q of the JPEG form become depths (no effect on the lossless form).
   * Default DEPTH_VIEWER.
   */
  vtkSetClampMacro(DepthDecoding, int, DEPTH_VIEWER, DEPTH_BIN_CENTRE);
  vtkGetMacro(DepthDecoding, int);
  ///@}

protected:
  vtkMLIReader();
  ~vtkMLIReader() override;

  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  // The folder named by FileName (FileName itself, or its parent when it names a meta.json).
  static std::string FolderOf(const char* name);

  char* FileName = nullptr;
  bool DropTransparentTriangles = false;
  bool SkipEmptyLayers = false;
  double AlphaThreshold = 1.0 / 255.0;
  int MeshMode = MESH_PER_TEXEL;
  double MeshTolerance = 1.0;
  int DepthDecoding = DEPTH_VIEWER;

private:
  vtkMLIReader(const vtkMLIReader&) = delete;
  void operator=(const vtkMLIReader&) = delete;
};

#endif

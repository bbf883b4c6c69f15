/**
 * @class   vtkSIMPLIBuildMLI
 * @brief   builds a SIMPLI multi-layer image (MLI) of a scene with the SIMPLI network
 *
 * The scene comes from input port 0 (optional): a scene collection as vtkSIMPLISceneReader's
 * port 0 produces it (views as images with their cameras, NearFar bounds). With nothing
 * connected, SceneFileName names a scene folder that is read as vtkSIMPLISceneReader reads it
 * with its defaults (simpli::readScene: normalised, sizes floored to multiples of 16). The two
 * give the same MLI when the images need no resize (the collection carries 8-bit pixels).
 *
 * The network (simpli/model/network/loader.h): weights from WeightsFile (empty = the default
 * weights, simpli::network::defaultWeightsPath()), config from Config (a name such as "tiny" or
 * "official-4l", or the path of a JSON file; empty = the one stored in the weights' metadata).
 * RandomSeed >= 0 initialises the weights randomly instead (testing; WeightsFile must then be
 * empty). The loaded network is kept between updates while WeightsFile (and its modification
 * time), Config, RandomSeed and Device stay the same; the last forward pass's MLI is kept too
 * and reused while the network, the source views' pixels and cameras, the depth range and
 * CorrectionSteps stay the same (so DropEmptyLayers, EmptyLayerThreshold,
 * DropTransparentTriangles, MeshMode and MeshTolerance take effect without rerunning the
 * network).
 *
 * The forward pass (simpli/model/generator/generator.h) takes the views listed in SourceViews
 * ("0,2,5"; empty = every view), with the reference camera at their pose average, the planes
 * over the config's depth range or the scene's NearFar (DepthRange), and runs CorrectionSteps
 * MLI corrections (-1 = all of the config's). The number of planes is a property of the trained
 * network (the layer decoder's group size depends on it): NumberOfPlanes 0 takes the config's,
 * any other value must equal it (else the request fails naming both); the planes used are
 * reported in the output's field data.
 *
 * Output: a vtkPartitionedDataSetCollection exactly as vtkMLIReader produces it (one
 * vtkPolyData per layer, back to front, point data RGBA / Color / Alpha / Depth / TCoords, the
 * reference camera and NumberOfLayers in the field data; see vtkMLIReader). DropEmptyLayers
 * leaves out the layers whose every alpha is below EmptyLayerThreshold ("auto" layers; when
 * every layer is empty all are kept, an MLI is never empty); DropTransparentTriangles, MeshMode
 * and MeshTolerance as in vtkMLIReader. Further collection field data:
 *   - "StageNames" (string) and "StageTimes" (double, milliseconds), one tuple per stage:
 *     read_scene, load_network (near 0 when the cached network was reused), the generator's
 *     stages (timed with the device queue finished after each) and to_mli, or forward_reused
 *     (0) when the last MLI was reused, then meshes;
 *   - "SourceViews" (int, the scene views used), "NumberOfPlanes" (int), "NetworkConfig" and
 *     "NetworkWeights" (strings: the config's name and where the weights came from).
 *
 * Pieces (pvbatch / pvserver on K MPI ranks run the pipeline as piece `rank` of K): the MLI is
 * one piece's data. BuildPiece names it (modulo the number of pieces; default 0): that piece
 * builds the MLI, every other piece produces an empty collection without reading the scene or
 * loading the network, so a K-rank pvbatch builds it once, not K times, and shows one copy. A
 * script with several scenes spreads them over the ranks with BuildPiece = the scene's index
 * (round robin, as `simpli infer SCENES_DIR` deals scenes). BuildPiece -1 builds the whole MLI
 * on every piece (a copy per rank). The building piece is in the field data ("BuildPiece").
 *
 * Progress: scene, network, then the generator's stages (level 0/1, layers, each correction),
 * then the meshes. An abort (AbortExecute) is honoured between stages, also inside the forward
 * pass, and leaves an empty output. Errors (missing or unreadable scene folder, missing weights
 * file, unknown config, bad SourceViews entry, NumberOfPlanes or CorrectionSteps the network
 * does not have, OpenCL failures) are reported with vtkErrorMacro naming the property, file and
 * value; the request fails with an empty output.
 */

#ifndef vtkSIMPLIBuildMLI_h
#define vtkSIMPLIBuildMLI_h

#include "vtkSimpliFiltersModule.h" // for export macro
#include <vtkPartitionedDataSetCollectionAlgorithm.h>

class VTKSIMPLIFILTERS_EXPORT vtkSIMPLIBuildMLI : public vtkPartitionedDataSetCollectionAlgorithm {
public:
  static vtkSIMPLIBuildMLI* New();
  vtkTypeMacro(vtkSIMPLIBuildMLI, vtkPartitionedDataSetCollectionAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The scene folder read when no scene is connected to input port 0.
   */
  vtkSetStringMacro(SceneFileName);
  vtkGetStringMacro(SceneFileName);
  ///@}

  ///@{
  /**
   * The weights (.safetensors); empty = the default weights.
   */
  vtkSetStringMacro(WeightsFile);
  vtkGetStringMacro(WeightsFile);
  ///@}

  ///@{
  /**
   * The network config: a name ("tiny", "official-4l", ...) or a JSON file; empty = the config
   * stored in the weights file.
   */
  vtkSetStringMacro(Config);
  vtkGetStringMacro(Config);
  ///@}

  ///@{
  /**
   * Leave out the layers whose every alpha is below EmptyLayerThreshold. Default off (all of
   * the network's layers).
   */
  vtkSetMacro(DropEmptyLayers, bool);
  vtkGetMacro(DropEmptyLayers, bool);
  vtkBooleanMacro(DropEmptyLayers, bool);
  ///@}

  ///@{
  /**
   * Alpha below which a layer (DropEmptyLayers) or a triangle (DropTransparentTriangles) is
   * transparent, in [0, 1]. Default 1/255 (what an 8-bit export rounds to 0).
   */
  vtkSetClampMacro(EmptyLayerThreshold, double, 0.0, 1.0);
  vtkGetMacro(EmptyLayerThreshold, double);
  ///@}

  ///@{
  /**
   * Drop the triangles whose three vertices are all transparent (points are kept). Default off.
   */
  vtkSetMacro(DropTransparentTriangles, bool);
  vtkGetMacro(DropTransparentTriangles, bool);
  vtkBooleanMacro(DropTransparentTriangles, bool);
  ///@}

  enum MeshModes {
    MESH_PER_TEXEL = 0, ///< one point per texel, per-point RGBA (the reference mesh)
    MESH_ADAPTIVE = 1   ///< adaptive mesh, RGBA as a per-layer texture (real-time display)
  };

  ///@{
  /**
   * The layers' mesh form. MESH_PER_TEXEL (default): one point per texel with per-point RGBA,
   * what the rasterizer and training use. MESH_ADAPTIVE: triangles only where the depth needs
   * them (within MeshTolerance) and where something is visible (alpha >= EmptyLayerThreshold),
   * depth steps cut rather than bridged, TCoords per point and the RGBA at full resolution in the
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

  ///@{
  /**
   * Planes of the plane sweep: 0 = the config's (default); any other value must equal it.
   */
  vtkSetClampMacro(NumberOfPlanes, int, 0, 4096);
  vtkGetMacro(NumberOfPlanes, int);
  ///@}

  ///@{
  /**
   * MLI correction steps: -1 = all of the config's (default), 0 .. the config's.
   */
  vtkSetClampMacro(CorrectionSteps, int, -1, 64);
  vtkGetMacro(CorrectionSteps, int);
  ///@}

  ///@{
  /**
   * The source images are resized by this factor (to multiples of 16) before the network, and
   * the MLI is built at that size: 1 = as they are (default). A network holds best near the
   * size it was trained at (the shipped one on 512x384 photos: 0.75 with 5 or more sources,
   * 0.5 with 2; README "Input size").
   * Clamped to [1/64, 2].
   */
  vtkSetClampMacro(InputScale, double, 1.0 / 64, 2.0);
  vtkGetMacro(InputScale, double);
  ///@}

  ///@{
  /**
   * The MLI's reference frame widened by this fraction of the image on every side, on the same
   * texel grid (scene::widenedCamera): the layers then also cover what views off to the side see
   * beyond the sources' common frame. 0 = the reference's frame; default 0.06
   * (scene::recommendedReferenceMargin, +0.8 dB on LLFF flower). Clamped to [0, 0.5].
   */
  vtkSetClampMacro(ReferenceMargin, double, 0.0, 0.5); // scene::maxReferenceMargin
  vtkGetMacro(ReferenceMargin, double);
  ///@}

  ///@{
  /**
   * Source views, comma-separated 0-based indices ("0,2,5"); empty = every view (default).
   */
  vtkSetStringMacro(SourceViews);
  vtkGetStringMacro(SourceViews);
  ///@}

  enum DepthRanges {
    DEPTH_RANGE_CONFIG = 0, ///< the config's min/max depth (what the network trained with)
    DEPTH_RANGE_SCENE = 1   ///< the scene's NearFar bounds
  };

  ///@{
  /**
   * Where the planes' depth range comes from. Default DEPTH_RANGE_CONFIG.
   */
  vtkSetClampMacro(DepthRange, int, DEPTH_RANGE_CONFIG, DEPTH_RANGE_SCENE);
  vtkGetMacro(DepthRange, int);
  ///@}

  ///@{
  /**
   * OpenCL device "platform:device" (see `simpli devices`); empty = the current device
   * (SIMPLI_CL_DEVICE, else the first GPU, else the first CPU).
   */
  vtkSetStringMacro(Device);
  vtkGetStringMacro(Device);
  ///@}

  ///@{
  /**
   * Testing: >= 0 initialises the network randomly with this seed instead of loading weights;
   * -1 = off (default).
   */
  vtkSetClampMacro(RandomSeed, int, -1, VTK_INT_MAX);
  vtkGetMacro(RandomSeed, int);
  ///@}

  ///@{
  /**
   * The piece that builds the MLI, modulo the number of pieces (see the class comment); the
   * others produce an empty output. -1 = every piece builds it. Default 0.
   */
  vtkSetClampMacro(BuildPiece, int, -1, VTK_INT_MAX);
  vtkGetMacro(BuildPiece, int);
  ///@}

  /**
   * Forgets the cached network and MLI (the next update loads and runs it again).
   */
  void ReleaseNetwork();

protected:
  vtkSIMPLIBuildMLI();
  ~vtkSIMPLIBuildMLI() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestInformation(vtkInformation* request, vtkInformationVector** inputVector,
                         vtkInformationVector* outputVector) override;
  int RequestData(vtkInformation* request, vtkInformationVector** inputVector,
                  vtkInformationVector* outputVector) override;

  char* SceneFileName = nullptr;
  char* WeightsFile = nullptr;
  char* Config = nullptr;
  bool DropEmptyLayers = false;
  double EmptyLayerThreshold = 1.0 / 255.0;
  bool DropTransparentTriangles = false;
  int MeshMode = MESH_PER_TEXEL;
  double MeshTolerance = 1.0;
  int NumberOfPlanes = 0;
  int CorrectionSteps = -1;
  double InputScale = 1.0;
  double ReferenceMargin = 0.06; // scene::recommendedReferenceMargin
  char* SourceViews = nullptr;
  int DepthRange = DEPTH_RANGE_CONFIG;
  char* Device = nullptr;
  int RandomSeed = -1;
  int BuildPiece = 0;

private:
  vtkSIMPLIBuildMLI(const vtkSIMPLIBuildMLI&) = delete;
  void operator=(const vtkSIMPLIBuildMLI&) = delete;

  class vtkInternals;
  vtkInternals* Internals;
};

#endif

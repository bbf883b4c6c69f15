// Conversion between simpli::MLI (model/) and the VTK form of an MLI. Private to the module
// (PRIVATE_HEADERS): it mentions Eigen through simpli::Camera, which the wrappers must not see.
// Other filters of the module that produce or consume MLIs use it too, so that every MLI in a
// pipeline has the same layout:
//
// vtkPartitionedDataSetCollection, one vtkPartitionedDataSet per layer (one partition, a
// vtkPolyData), back to front: dataset 0 is the farthest layer that was kept. Each dataset's
// metadata NAME is "LayerKK" (KK = the layer's index in the MLI, two digits at least); the
// vtkDataAssembly has the root "MLI" with one child "Layers" whose children "Layer00",
// "Layer01", ... each hold their dataset index (paths /MLI/Layers/LayerKK).
//
// Collection field data (the reference camera; one tuple per camera, an MLI has one):
//   CameraIntrinsics  vtkDoubleArray, 4 components: fx, fy, cx, cy relative to the image size
//                     (fx' = fx_pixels / W, cx' = cx_pixels / W, ...; OpenCV axes)
//   CameraExtrinsics  vtkDoubleArray, 12 components: world->camera [R | t], 3 x 4 row-major
//                     (R00 R01 R02 t0 R10 ... t2)
//   CameraImageSize   vtkIntArray, 2 components: width W, height H of the layers (texels)
//   NumberOfLayers    vtkIntArray, 1 value: L of the MLI (layers skipped as empty count too)
// Doubles hold the camera exactly, so it round-trips bit for bit.
//
// Layer vtkPolyData: W x H points (vertex (i, j) = point i W + j, on the corner grid, in world
// coordinates: mli/mesh.h), two triangles per texel quad (fewer when transparent triangles are
// dropped; points never are). Point data:
//   RGBA     vtkUnsignedCharArray, 4 components, the active scalars: round(255 c), straight
//            (not premultiplied) colour and alpha, for display with MapScalars off. The
//            farthest layer (index 0) has alpha 255 (LayerOptions::opaqueFarthestLayer): the
//            rasterizer's rule that the farthest
//            fragment of a pixel is opaque (spec §6.7), so that a viewer blending the layers
//            over any background (ParaView's GUI) shows what `simpli render` shows. Alpha
//            keeps the exact value.
//   Color    vtkFloatArray, 3 components: straight RGB in [0, 1], the exact texel values
//   Alpha    vtkFloatArray: opacity in [0, 1], exact
//   Depth    vtkFloatArray: reference-camera z of the texel, exact
//   TCoords  vtkFloatArray, 2 components, the active texture coordinates: (u, 1 - v), so that
//            image row 0 is the top of a texture
// Layer field data: LayerIndex (vtkIntArray, 1 value: the index KK in the MLI).
//
// Adaptive layers (LayerOptions::meshMode = Adaptive; the display form of mli/adaptive_mesh.h):
// the vtkPolyData holds the adaptive mesh, points in world coordinates and triangles only where
// the depth needs them and something is visible. Point data:
//   TCoords  vtkFloatArray, 2 components, the active texture coordinates: ((x + 0.5) / W,
//            1 - (y + 0.5) / H) for corner-grid position (x, y), so that texel (i, j)'s centre
//            is sampled exactly at the vertex on its ray (as the per-texel mesh's vertex colour)
//   Depth    vtkFloatArray: reference-camera z of the vertex
// The layer's RGBA travels at full resolution in the layer's field data, W x H tuples in
// vtkImageData order (row 0 = the bottom image row, i.e. MLI row H - 1), ready to be the
// scalars of the texture image (layerTexture):
//   TextureRGBA   vtkUnsignedCharArray, 4 components: round(255 c), straight colour and alpha
//                 (alpha 255 for layer 0, as RGBA above)
//   TextureColor  vtkFloatArray, 3 components; TextureAlpha, TextureDepth  vtkFloatArray: the
//                 exact texel values (so that collectionToMLI is exact for this form too)
//   TextureSize   vtkIntArray, 2 components: W, H
//   MeshTolerance vtkDoubleArray, 1 value: the tolerance the mesh was built with (pixels)
//
// Going back (collectionToMLI), Color, Alpha and Depth (TextureColor, TextureAlpha and
// TextureDepth for an adaptive layer) are the source of truth (RGBA is 8-bit and is ignored)
// and the geometry is rebuilt from Depth and the camera (point coordinates are not read), so
// reading and writing the lossless form is exact.
#pragma once

#include <functional>
#include <string>

#include <vtkSmartPointer.h>

#include "simpli/model/mli/adaptive_mesh.h"
#include "simpli/model/mli/mli.h"

class vtkFieldData;
class vtkImageData;
class vtkPartitionedDataSetCollection;
class vtkPolyData;

namespace simpli::vtkmli {

inline constexpr const char* kIntrinsicsArray = "CameraIntrinsics";
inline constexpr const char* kExtrinsicsArray = "CameraExtrinsics";
inline constexpr const char* kImageSizeArray = "CameraImageSize";
inline constexpr const char* kNumberOfLayersArray = "NumberOfLayers";
inline constexpr const char* kLayerIndexArray = "LayerIndex";
inline constexpr const char* kRGBAArray = "RGBA";
inline constexpr const char* kColorArray = "Color";
inline constexpr const char* kAlphaArray = "Alpha";
inline constexpr const char* kDepthArray = "Depth";
inline constexpr const char* kTCoordsArray = "TCoords";
inline constexpr const char* kTextureRGBAArray = "TextureRGBA";
inline constexpr const char* kTextureColorArray = "TextureColor";
inline constexpr const char* kTextureAlphaArray = "TextureAlpha";
inline constexpr const char* kTextureDepthArray = "TextureDepth";
inline constexpr const char* kTextureSizeArray = "TextureSize";
inline constexpr const char* kMeshToleranceArray = "MeshTolerance";
inline constexpr const char* kAssemblyRoot = "MLI";
inline constexpr const char* kAssemblyLayers = "Layers";

enum class MeshMode {
  PerTexel, ///< one vertex per texel, per-point RGBA (what the rasterizer and training use)
  Adaptive  ///< mli/adaptive_mesh.h with the RGBA as a texture (real-time display)
};

struct LayerOptions {
  MeshMode meshMode = MeshMode::PerTexel;
  /// Adaptive meshes: largest reprojection error in pixels (mli::AdaptiveMeshOptions).
  double meshTolerance = mli::AdaptiveMeshOptions{}.tolerancePixels;
  /// Per-texel meshes: drop the triangles whose three vertices all have alpha < alphaThreshold
  /// (adaptive meshes always leave transparent regions out).
  bool dropTransparentTriangles = false;
  /// Leave out the layers whose every alpha is < alphaThreshold.
  bool skipEmptyLayers = false;
  double alphaThreshold = 1.0 / 255.0;
  /// Point coordinates as vtkDoubleArray, back-projected in double precision from the stored
  /// (float) depths; float otherwise, as the model's mesh holds them.
  bool doublePrecisionPoints = false;
  /// Display RGBA (and TextureRGBA) of layer 0 with alpha 255: the rasterizer's rule that the
  /// farthest layer is opaque (see RGBA above). Off for a layer shown on its own
  /// (vtkSIMPLILayerGridSource), whose alpha is the user's.
  bool opaqueFarthestLayer = true;
};

/// "Layer07" for k = 7 (at least two digits, like the file names).
std::string layerName(int k);

/// Adds (replacing same-named arrays) the camera arrays described above to `fd`.
void addCameraFieldData(vtkFieldData* fd, const scene::Camera& camera);

/// The camera in `fd`; throws simpli::Error starting with `context` and naming the array and
/// the value when an array is missing, has the wrong shape or the camera is invalid.
scene::Camera cameraFromFieldData(vtkFieldData* fd, const std::string& context);

/// Layer k of `mli` as a vtkPolyData in options.meshMode's form (the MLI must be valid: see
/// validateMLI).
vtkSmartPointer<vtkPolyData> layerToPolyData(const mli::MLI& mli, int k,
                                             const LayerOptions& options);

/// The texture of an adaptive layer: a W x H vtkImageData whose point data are the layer's
/// Texture* arrays (shared, not copied; TextureRGBA the active scalars, the others under their
/// names). Null for a layer without a texture (the per-texel form).
vtkSmartPointer<vtkImageData> layerTexture(vtkPolyData* layer);

/// Replaces the contents of `out` with `mli`. `progress(f)` is called before each layer with
/// f in [0, 1); when it returns false the conversion stops, `out` is emptied and the result is
/// false. Throws simpli::Error for an invalid MLI.
bool mliToCollection(const mli::MLI& mli, const LayerOptions& options,
                     vtkPartitionedDataSetCollection* out,
                     const std::function<bool(double)>& progress = {});

/// The MLI held by `in` (dataset order = layer order, back to front). Throws simpli::Error
/// starting with `context` and naming the layer, the array and the value for a missing camera
/// or array, a layer that is not one data set with W x H points (per-texel form) or W x H
/// texture tuples (adaptive form, told apart by its TextureDepth array), or values that
/// validateMLI rejects.
mli::MLI collectionToMLI(vtkPartitionedDataSetCollection* in, const std::string& context);

} // namespace simpli::vtkmli

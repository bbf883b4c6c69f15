// The VTK form of a multi-view scene (vtkSIMPLISceneReader's output) and how other filters of
// the module read it back. Private to the module (PRIVATE_HEADERS): it mentions simpli::Camera.
//
// vtkPartitionedDataSetCollection, one vtkPartitionedDataSet per view with one vtkImageData
// (point data "RGB", uchar x 3, VTK row order: row 0 = bottom); each image's field data holds
// its camera (CameraIntrinsics, CameraExtrinsics, CameraImageSize as in SIMPLIMLIToVTK.h) and
// ViewIndex / ViewName / ImagePath; the collection's field data holds NearFar (double x 2),
// NormalisationScale, SceneFormat and NumberOfViews. Assembly /Scene/Views/ViewNNN.
#pragma once

#include <string>
#include <vector>

#include "simpli/model/io/image.h"
#include "simpli/model/scene/camera.h"
#include "simpli/model/scene/scene.h"

class vtkFieldData;
class vtkImageData;
class vtkPartitionedDataSetCollection;

namespace simpli::vtkscene {

inline constexpr const char* kNearFarArray = "NearFar";
inline constexpr const char* kNormalisationScaleArray = "NormalisationScale";
inline constexpr const char* kSceneFormatArray = "SceneFormat";
inline constexpr const char* kNumberOfViewsArray = "NumberOfViews";
inline constexpr const char* kViewIndexArray = "ViewIndex";
inline constexpr const char* kViewNameArray = "ViewName";
inline constexpr const char* kImagePathArray = "ImagePath";
inline constexpr const char* kRGBArray = "RGB";

/// "View007" for k = 7.
std::string viewName(int k);

/// Adds NearFar = (near, far) to `fd`.
void addNearFar(vtkFieldData* fd, double near, double far);

/// NearFar of `fd`; false when absent. Throws simpli::Error (starting with `context`) when it
/// is present but not 2 finite values with 0 < near <= far.
bool nearFarFromFieldData(vtkFieldData* fd, const std::string& context, double& near, double& far);

/// An RGB image ([-1, 1] CHW, row 0 = top) as a vtkImageData with uchar "RGB" point scalars
/// (round((v + 1) 127.5), clamped; VTK row order).
void imageToVTK(const io::Image& image, vtkImageData* out);

/// The inverse of imageToVTK: the image's 3- or 4-component unsigned char point scalars (the
/// active scalars, else the "RGB" array; a fourth component is ignored) as [-1, 1] values
/// x / 127.5 - 1, exactly as readImage decodes an 8-bit file. Throws simpli::Error starting with
/// `context` for a missing or mis-shaped array or an image that is not 2-D.
io::Image imageFromVTK(vtkImageData* image, const std::string& context);

/// The inverse of vtkSIMPLISceneReader's port 0: a simpli::Scene with every view's image
/// (imageFromVTK), camera (field data, as sceneCameras), ViewName and ImagePath (when
/// present), NearFar (required), NormalisationScale and SceneFormat (when present); root is
/// `context` (it names the scene in the model's messages). Images of a scene read from 8-bit files
/// without a resize come back bit for bit. Throws simpli::Error starting with `context` and naming
/// the view and the array for anything missing or invalid (camera image size different from the
/// image's, no views, no NearFar).
scene::Scene vtkToScene(vtkPartitionedDataSetCollection* scene, const std::string& context);

/// The cameras of the views of a scene collection, in dataset order. Throws simpli::Error
/// starting with `context` and naming the view and the array when a view is not an image or
/// its camera is missing or invalid.
std::vector<scene::Camera> sceneCameras(vtkPartitionedDataSetCollection* scene,
                                        const std::string& context);

} // namespace simpli::vtkscene

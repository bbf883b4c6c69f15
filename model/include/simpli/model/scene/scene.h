#pragma once
// A multi-view scene as every reader delivers it: per view the image file, the loaded image
// (simpli::Image, [-1,1] CHW) and its Camera, plus near/far bounds, the detected format and the
// normalisation that was applied (spec §1.2, §9).
//
// Formats (detected from the folder contents, see detectSceneFormat):
//  * LLFF: <root>/poses_bounds.npy + <root>/images/ (sorted png/jpg/jpeg);
//  * COLMAP text model: cameras.txt, images.txt, optional points3D.txt in <root>/sparse/0/,
//    <root>/sparse/ or <root>/, images in <root>/images/; PINHOLE and SIMPLE_PINHOLE only;
//  * RealEstate10K / SWORD camera file: <root>/<root name>.txt or <root>/cameras.txt, images
//    <frame id>.png/.jpg beside it or in <root>/images/.
// Details of each format are in scene/readers.h.
//
// Units: after readScene the cameras, bounds and points are in *normalised* units (see
// scene/normalisation.h); Scene::normalisation maps them back to scene units.
#include "simpli/model/io/image.h"
#include "simpli/model/scene/camera.h"
#include "simpli/model/scene/normalisation.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace simpli::scene {

enum class SceneFormat { Auto, LLFF, Colmap, RealEstate10K };

const char* toString(SceneFormat format);
/// "auto", "llff", "colmap", "re10k" (also "realestate10k", "sword"); throws for anything else.
SceneFormat parseSceneFormat(const std::string& name);

/// Bounds used when a format provides none (RealEstate10K; COLMAP without points3D.txt) and
/// none are given explicitly: the reference network's fixed plane range 1..100, i.e. the scene
/// is assumed to be scaled for the network already, as the reference's validation data are
/// (spec §9.3, §9.5).
constexpr double kDefaultNear = 1.0;
constexpr double kDefaultFar = 100.0;

/// Bounds whose far / near ratio exceeds this give a poor result (readScene warns): the
/// network's planes span a ratio of kDefaultFar / kDefaultNear = 100.
constexpr double kMaxGoodDepthRatio = 1000.0;
/// Views whose centres all lie within this fraction of the near bound of each other show no
/// parallax (readScene warns).
constexpr double kMinGoodBaseline = 1e-6;

/// Tolerance on max |R^T R - I| for a pose's rotation.
constexpr double kRotationTolerance = 1e-3;

struct SceneView {
  std::string name;      ///< image name as the format refers to it (file name, frame id)
  std::string imagePath; ///< the image file
  io::Image image;       ///< empty when SceneReadOptions::loadImages is false
  Camera camera;         ///< normalised units; width/height = image size after the resize
  int originalWidth = 0, originalHeight = 0; ///< size stored in the image file
};

struct SceneReadOptions {
  SceneFormat format = SceneFormat::Auto;
  /// false: every image is still decoded (to validate it and get its size) but its pixels
  /// are dropped; for tools that only need the geometry.
  bool loadImages = true;
  /// Images are resized down to the nearest multiple of this (the network needs 16); <= 1
  /// keeps the stored size.
  int sizeMultiple = 16;
  /// Image folder relative to the scene root (e.g. "images_4" for LLFF); empty: "images", or
  /// the folder chooseImageFolder (scene/readers.h) picks for imagesFactor / preferredWidth.
  std::string imagesDir;
  int imagesFactor = 0;   ///< > 0: read images_<factor> (LLFF / NeRF layout)
  int preferredWidth = 0; ///< > 0: read the images_* folder closest to this width
  /// Explicit near / far bounds in scene units; 0 = take them from the scene (or defaults).
  double near = 0, far = 0;
  NormalisationOptions normalisation;
};

struct Scene {
  std::string root; ///< the scene folder
  SceneFormat format = SceneFormat::Auto;
  std::string posesFile; ///< the file the cameras were read from
  std::string imagesDir; ///< the image folder read, relative to root ("" = the default)
  std::vector<SceneView> views;
  double near = 0, far = 0;            ///< normalised units
  std::string boundsSource;            ///< where near/far came from
  std::vector<Eigen::Vector3d> points; ///< SfM points (COLMAP), normalised units
  Normalisation normalisation;

  size_t size() const { return views.size(); }
  int width() const { return views.empty() ? 0 : views[0].camera.width; }
  int height() const { return views.empty() ? 0 : views[0].camera.height; }
  std::vector<Camera> cameras() const;
  std::vector<io::Image> images() const;
  double sceneNear() const { return normalisation.toScene(near); }
  double sceneFar() const { return normalisation.toScene(far); }
};

/// Detects the format of a scene folder (or of a poses_bounds.npy / camera .txt file given
/// directly). Throws simpli::Error naming the path when it does not exist or matches no format.
SceneFormat detectSceneFormat(const std::string& path);

/// Reads, validates and normalises a scene. Throws simpli::Error naming the file and the value
/// for: a missing folder, no images, image count != pose count, images of different sizes,
/// unreadable images, malformed pose files, non-finite poses, rotations that are not
/// orthonormal (tolerance kRotationTolerance), near <= 0 or far <= near, unsupported COLMAP
/// camera models, COLMAP image names not on disk, cameras that scene::validateCamera refuses
/// (scene/camera_checks.h). Warns (simpli/warning.h) where the result will be poor: camera
/// concerns (scene::cameraConcerns), bounds beyond kMaxGoodDepthRatio, no baseline.
Scene readScene(const std::string& path, const SceneReadOptions& options = {});

/// Largest distance between two camera centres (0 for fewer than two cameras).
double maxBaseline(const std::vector<Camera>& cameras);

} // namespace simpli::scene

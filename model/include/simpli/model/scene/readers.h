#pragma once
// The format-specific halves of readScene: each reads the camera file(s) of one format and
// locates the images, in scene units; readScene then loads and checks the images, settles the
// bounds and normalises. Exposed for tests and for tools that need only the cameras.
#include "simpli/model/scene/camera.h"
#include "simpli/model/scene/scene.h"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace simpli::scene {

struct SceneSource {
  SceneFormat format = SceneFormat::Auto;
  std::string root;
  std::string posesFile;
  std::vector<std::string> names;      ///< per view
  std::vector<std::string> imagePaths; ///< per view
  /// Per view, scene units. width/height are the image size the file declares for the
  /// intrinsics (LLFF h, w; COLMAP WIDTH, HEIGHT), 0 when the format declares none.
  std::vector<Camera> cameras;
  double near = 0, far = 0; ///< 0 when the format has no bounds
  std::string boundsSource;
  std::vector<Eigen::Vector3d> points; ///< SfM points, scene units (COLMAP points3D.txt)
};

/// LLFF: <root>/poses_bounds.npy, N x 17 float64 (or float32), row = 3x5 camera-to-world matrix
/// (row-major) whose columns are [down, right, backwards, centre, (h, w, focal)], then the
/// view's near and far depth. Converted to world->camera with OpenCV axes
/// x = right = col1, y = down = col0, z = forward = -col2; relative intrinsics
/// fx = focal / w, fy = focal / h, cx = cy = 0.5 (these are the same for images that were
/// down-sampled from h x w, which is how LLFF's images_4 etc. relate to the stored h, w).
/// Images: sorted png/jpg/jpeg files (case-insensitive) in <root>/<imagesDir or "images">; their
/// count must equal N. near = min over views, far = max over views; each view's near must be
/// > 0 and its far > near; h and w must round to a size of at least one pixel.
SceneSource readLlffSource(const std::string& root, const std::string& imagesDir = "");

/// COLMAP text model (cameras.txt, images.txt, optional points3D.txt) in <root>/sparse/0,
/// <root>/sparse or <root>; images in <root>/<imagesDir or "images">/<NAME>. Camera models
/// PINHOLE (fx fy cx cy) and SIMPLE_PINHOLE (f cx cy); pixel coordinates have their origin at
/// the image corner (COLMAP's convention), so relative intrinsics are fx/W, cx/W, fy/H, cy/H.
/// Models with distortion are rejected with advice to run `colmap image_undistorter`.
/// images.txt gives world->camera rotation as QW QX QY QZ and translation TX TY TZ, one pose
/// line "IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME" per image, each followed by a POINTS2D
/// line (X Y POINT3D_ID triplets) that may be empty or left out (some tools write none; lines
/// are told apart by their shape); '#' lines are comments. A malformed line, a duplicate
/// IMAGE_ID or NAME is an error naming the line and the field. Views are sorted by image name.
/// Bounds from points3D.txt: per view, the depths of the points in front of the camera that project
/// inside the image; near = min over views of the 1st percentile, far = max over views of the 99th
/// percentile. No points3D.txt: no bounds (readScene then uses the explicit or default bounds).
SceneSource readColmapSource(const std::string& root, const std::string& imagesDir = "");

/// RealEstate10K / SWORD camera file: `path` is the file, or a folder holding <folder name>.txt
/// or cameras.txt. Each non-empty line is "frame_id fx fy cx cy 0 0 r11 r12 r13 t1 r21 r22 r23
/// t2 r31 r32 r33 t3" with relative intrinsics and world->camera [R|t], except line 1 when it
/// is a header (the video's URL: a line that neither has 19 fields nor starts with an integer
/// frame id); '#' lines are comments. A malformed line or a frame id that appears twice is an
/// error naming the line. Images <frame_id>.png/.jpg/.jpeg beside the file or in
/// <folder>/<imagesDir or "images">. Frames without an image are left out with one warning
/// listing them (the reference stops at the first one silently); none with an image is an
/// error. No bounds.
SceneSource readRealEstateSource(const std::string& path, const std::string& imagesDir = "");

/// The image folder of a scene root to read, relative to it, from the folders `images` and
/// `images_<N>` (the LLFF / NeRF layout, images_N = down-sampled by N). factor > 0: images_N
/// (factor 1 = images), an error naming the folders found when it is missing. Otherwise, with
/// preferredWidth > 0: the folder whose first image's width is closest to preferredWidth on a
/// log scale (ties: the larger). "" (the reader's default, images/) when neither is given or
/// the root has no such folder.
std::string chooseImageFolder(const std::string& root, int factor, int preferredWidth);
/// Image files (png/jpg/jpeg, any case) directly inside `folder`, sorted by name. Throws when
/// the folder does not exist.
std::vector<std::string> listImageFiles(const std::string& folder);

/// Checks a pose read from a scene file: scene::validateCamera (scene/camera_checks.h) with
/// kRotationTolerance. Errors name `file` and `view`.
void checkCamera(const Camera& camera, const std::string& file, const std::string& view);

/// Depths (camera z) of the points in front of the camera that project inside the image.
std::vector<double> visiblePointDepths(const Camera& camera,
                                       const std::vector<Eigen::Vector3d>& points);

} // namespace simpli::scene

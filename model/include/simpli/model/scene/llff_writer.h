#pragma once
// Writing scenes in LLFF layout — the exact inverse of readLlffSource (scene/readers.h):
//   <dir>/poses_bounds.npy  N x 17 float64, C order, .npy version 1.0. Row i: the 3x5 matrix
//                           [down | right | backwards | centre | (h, w, focal)] row-major
//                           (camera-to-world rotation columns in LLFF's axis order), then the
//                           view's near and far depth;
//   <dir>/images/NNN.png    8-bit RGB, NNN = zero-padded view index (sorted = view order);
//   <dir>/depth/NNN.png     optional, 16-bit grey: camera-space z = value * depthScale,
//                           0 = no surface.
// OpenCV camera axes x = right, y = down, z = forward are LLFF's (col1, col0, -col2), so
// col0 = R^T e_y, col1 = R^T e_x, col2 = -R^T e_z for world->camera R.
// LLFF has one focal length in pixels and the principal point at the image centre, so only
// cameras with square pixels (fx * width == fy * height) and cx = cy = 0.5 can be written.
#include "simpli/model/io/image.h"
#include "simpli/model/scene/camera.h"

#include <array>
#include <string>
#include <vector>

namespace simpli::scene {

/// The 17 values of a poses_bounds.npy row. Throws simpli::Error naming `view` when the camera
/// cannot be represented (size not positive, non-square pixels, off-centre principal point,
/// rotation not orthonormal) or the bounds are invalid (near <= 0, far <= near).
std::array<double, 17> llffPoseRow(const Camera& camera, double near, double far,
                                   const std::string& view = "0");

/// Writes poses_bounds.npy atomically; near and far are per view.
void writePosesBounds(const std::string& path, const std::vector<Camera>& cameras,
                      const std::vector<double>& near, const std::vector<double>& far);

/// Writes a depth map (row-major height x width, camera z) as a 16-bit PNG with
/// value = round(depth / scale), atomically. Throws naming the file and the pixel when a depth
/// is negative, not finite or above 65535 * scale.
void writeDepthPng(const std::string& path, const std::vector<float>& depth, int width, int height,
                   double scale);

/// Reads a 16-bit depth PNG back: depth = value * scale (0 stays 0 = no surface). Throws naming
/// the file when it is missing, not decodable or not 16-bit single-channel.
std::vector<float> readDepthPng(const std::string& path, double scale, int* width = nullptr,
                                int* height = nullptr);

/// Base name of view `index` of `count` (no extension): the index zero-padded to at least 3
/// digits and to as many as count - 1 needs, so that the byte-wise sorted file names (the order
/// LLFF readers use) are the view order.
std::string llffViewName(size_t index, size_t count);

struct LlffSceneData {
  std::vector<Camera> cameras;
  std::vector<io::Image> images;          ///< [-1, 1] CHW, written as 8-bit PNG
  std::vector<double> near, far;          ///< per view, scene units
  std::vector<std::vector<float>> depths; ///< empty, or per view height x width camera z
  double depthScale = 0.001;              ///< scene units per depth PNG count
};

/// Writes poses_bounds.npy, images/ and (when depths are given) depth/ into the existing folder
/// `dir`. Throws naming the view when counts or sizes disagree (every image must have its
/// camera's width x height) or a camera cannot be written.
void writeLlffScene(const std::string& dir, const LlffSceneData& data);

} // namespace simpli::scene

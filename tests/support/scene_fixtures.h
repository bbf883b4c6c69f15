#pragma once
// Small scenes (LLFF, COLMAP, RealEstate10K) written programmatically, so that the tests need
// no data files.
#include "simpli/model/scene/camera.h"
#include "support/temp_dir.h"

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace simpli::test {

/// Writes a deterministic colour pattern (distinct per seed) as PNG or JPEG (by extension).
/// depth: 8 or 16 bits; channels: 1, 3 or 4.
void writePatternImage(const std::string& path, int width, int height, int seed, int depth = 8,
                       int channels = 3);

/// A forward-facing rig of n cameras (looking along world +z, small rotations, centres spread
/// over ~0.2 units), relative intrinsics fx = 1.0, fy = 1.5 (square pixels for 48 x 32 images),
/// cx = cy = 0.5, width/height as given.
std::vector<scene::Camera> makeRig(int n, int width = 48, int height = 32);

/// Points in front of the rig, depths roughly 2..10.
std::vector<Eigen::Vector3d> makePoints(int n);

/// One LLFF row (17 values) for a camera: LLFF [down, right, back, centre, (h, w, focal)] +
/// near, far. Uses focal = fx * width (so fy * height must equal it).
std::vector<double> llffRow(const scene::Camera& camera, double near, double far);

/// <dir>/poses_bounds.npy + <dir>/images/img_XX.png (width x height).
void writeLlffScene(const std::string& dir, const std::vector<scene::Camera>& cameras, double near,
                    double far);

/// COLMAP text model in <dir>/<modelSubdir> (e.g. "sparse/0" or "") with PINHOLE cameras, and
/// images <dir>/images/<name>. points3D.txt is written only when points is non-empty.
void writeColmapScene(const std::string& dir, const std::vector<scene::Camera>& cameras,
                      const std::vector<Eigen::Vector3d>& points,
                      const std::string& modelSubdir = "sparse/0");

/// RealEstate10K camera file <dir>/<fileName> (default <dir name>.txt) with frame ids
/// 1000, 2000, ... and images <dir>/<imagesSubdir>/<id>.png.
void writeRealEstateScene(const std::string& dir, const std::vector<scene::Camera>& cameras,
                          const std::string& fileName = "", const std::string& imagesSubdir = "");

/// Rotation about a unit axis by an angle in radians.
Eigen::Matrix3d rotation(const Eigen::Vector3d& axis, double angle);

} // namespace simpli::test

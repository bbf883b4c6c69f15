// LLFF scenes: poses_bounds.npy + images/ (see scene/readers.h for the conventions).
#include "simpli/error.h"
#include "simpli/model/io/npy.h"
#include "simpli/model/scene/readers.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace fs = std::filesystem;

namespace simpli::scene {

namespace {
// LLFF's h and w are the size of the images the poses were computed for (COLMAP's limit).
constexpr double kMaxDeclaredSize = 1000000;
} // namespace

SceneSource readLlffSource(const std::string& root, const std::string& imagesDir) {
  std::error_code ec;
  if (!fs::is_directory(root, ec))
    fail("scene folder '", root, "' does not exist");
  SceneSource src;
  src.format = SceneFormat::LLFF;
  src.root = root;
  src.posesFile = (fs::path(root) / "poses_bounds.npy").string();
  const std::string& file = src.posesFile;

  const io::NpyArray a = io::readNpy(file);
  if (a.shape.size() != 2)
    fail(file, ": 'shape' has ", a.shape.size(), " dimensions, expected 2 (N x 17)");
  if (a.shape[1] != 17)
    fail(file, ": 'shape' has ", a.shape[1], " columns, expected 17 (3x5 pose + near, far)");
  const size_t n = a.shape[0];
  if (n == 0)
    fail(file, ": no poses ('shape' is (0, 17))");
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < 17; ++j)
      if (!std::isfinite(a.at(i, j)))
        fail(file, ": view ", i, ": value ", j, " is ", a.at(i, j), " (not finite)");

  const std::string imageFolder =
      (fs::path(root) / (imagesDir.empty() ? std::string("images") : imagesDir)).string();
  src.imagePaths = listImageFiles(imageFolder);
  if (src.imagePaths.empty())
    fail("no images (png/jpg/jpeg) in '", imageFolder, "'");
  if (src.imagePaths.size() != n)
    fail(file, " has ", n, " poses but '", imageFolder, "' has ", src.imagePaths.size(), " images");

  src.near = 0;
  src.far = 0;
  for (size_t i = 0; i < n; ++i) {
    // Row-major 3x5: element (r, c) is value 5 r + c.
    auto m = [&](int r, int c) { return a.at(i, size_t(5 * r + c)); };
    Eigen::Matrix3d c2w; // columns: OpenCV x (right), y (down), z (forward) in world
    for (int r = 0; r < 3; ++r) {
      c2w(r, 0) = m(r, 1);
      c2w(r, 1) = m(r, 0);
      c2w(r, 2) = -m(r, 2);
    }
    const Eigen::Vector3d centre(m(0, 3), m(1, 3), m(2, 3));
    const double h = m(0, 4), w = m(1, 4), focal = m(2, 4);
    const std::string view = std::to_string(i);
    if (!(h > 0) || !(w > 0) || !(focal > 0))
      fail(file, ": view ", view, ": (h, w, focal) = (", h, ", ", w, ", ", focal,
           ") must be positive");
    // The declared size is the one the focal length is in pixels of; it must be a size (a value
    // below 0.5 rounds to 0 pixels).
    if (h < 0.5 || w < 0.5 || h > kMaxDeclaredSize || w > kMaxDeclaredSize)
      fail(file, ": view ", view, ": declared image size (h, w) = (", h, ", ", w,
           ") is not an image size (expected 0.5 .. ", kMaxDeclaredSize,
           ", rounded to whole pixels)");
    Camera cam;
    cam.R = c2w.transpose();
    cam.t = -cam.R * centre;
    cam.fx = focal / w;
    cam.fy = focal / h;
    cam.cx = 0.5;
    cam.cy = 0.5;
    cam.width = int(std::lround(w));
    cam.height = int(std::lround(h));
    checkCamera(cam, file, view);
    const double nearI = a.at(i, 15), farI = a.at(i, 16);
    if (!(nearI > 0))
      fail(file, ": view ", view, ": near bound ", nearI, " must be > 0");
    if (!(farI > nearI))
      fail(file, ": view ", view, ": far bound ", farI, " must be > near bound ", nearI);
    src.near = i == 0 ? nearI : std::min(src.near, nearI);
    src.far = i == 0 ? farI : std::max(src.far, farI);
    src.cameras.push_back(cam);
    src.names.push_back(fs::path(src.imagePaths[i]).filename().string());
  }
  src.boundsSource = file + ": min near, max far over the views";
  return src;
}

} // namespace simpli::scene

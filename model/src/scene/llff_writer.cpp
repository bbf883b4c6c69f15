// LLFF scene writer (see scene/llff_writer.h).
#include "simpli/model/scene/llff_writer.h"

#include "simpli/error.h"
#include "simpli/model/io/files.h"
#include "simpli/model/io/npy.h"
#include "simpli/model/scene/readers.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <filesystem>

namespace fs = std::filesystem;

namespace simpli::scene {

std::array<double, 17> llffPoseRow(const Camera& camera, double near, double far,
                                   const std::string& view) {
  const std::string what = "LLFF writer";
  if (camera.width <= 0 || camera.height <= 0)
    fail(what, ": view ", view, ": image size ", camera.width, " x ", camera.height,
         " is not positive");
  checkCamera(camera, what, view);
  const double focalX = camera.fx * camera.width, focalY = camera.fy * camera.height;
  if (std::abs(focalX - focalY) > 1e-9 * std::abs(focalX))
    fail(what, ": view ", view, ": pixel focal lengths fx = ", focalX, " and fy = ", focalY,
         " differ; LLFF stores one focal length (square pixels only)");
  if (std::abs(camera.cx - 0.5) > 1e-12 || std::abs(camera.cy - 0.5) > 1e-12)
    fail(what, ": view ", view, ": principal point (cx, cy) = (", camera.cx, ", ", camera.cy,
         ") is not the image centre (0.5, 0.5), which LLFF assumes");
  if (!(near > 0) || !std::isfinite(near))
    fail(what, ": view ", view, ": near bound ", near, " must be > 0");
  if (!(far > near) || !std::isfinite(far))
    fail(what, ": view ", view, ": far bound ", far, " must be > near bound ", near);

  // Camera-to-world rotation columns are the OpenCV axes in world coordinates: rows of R.
  const Eigen::Vector3d right = camera.R.row(0).transpose();
  const Eigen::Vector3d down = camera.R.row(1).transpose();
  const Eigen::Vector3d forward = camera.R.row(2).transpose();
  const Eigen::Vector3d centre = camera.centre();
  std::array<double, 17> row{};
  for (int r = 0; r < 3; ++r) {
    row[size_t(5 * r + 0)] = down[r];
    row[size_t(5 * r + 1)] = right[r];
    row[size_t(5 * r + 2)] = -forward[r];
    row[size_t(5 * r + 3)] = centre[r];
  }
  row[4] = camera.height;
  row[9] = camera.width;
  row[14] = focalX;
  row[15] = near;
  row[16] = far;
  return row;
}

void writePosesBounds(const std::string& path, const std::vector<Camera>& cameras,
                      const std::vector<double>& near, const std::vector<double>& far) {
  if (cameras.empty())
    fail("LLFF writer '", path, "': no cameras");
  if (near.size() != cameras.size() || far.size() != cameras.size())
    fail("LLFF writer '", path, "': ", cameras.size(), " cameras but ", near.size(), " near and ",
         far.size(), " far bounds");
  std::vector<double> data;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const auto row = llffPoseRow(cameras[i], near[i], far[i], std::to_string(i));
    data.insert(data.end(), row.begin(), row.end());
  }
  io::writeNpy(path, data, {cameras.size(), 17});
}

void writeDepthPng(const std::string& path, const std::vector<float>& depth, int width, int height,
                   double scale) {
  if (width <= 0 || height <= 0 || depth.size() != size_t(width) * size_t(height))
    fail("depth map '", path, "': ", depth.size(), " values for ", width, " x ", height);
  if (!(scale > 0) || !std::isfinite(scale))
    fail("depth map '", path, "': depth scale ", scale, " must be > 0");
  cv::Mat counts(height, width, CV_16UC1);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double d = depth[size_t(y) * size_t(width) + size_t(x)];
      const double q = std::round(d / scale);
      if (!std::isfinite(d) || d < 0 || q > 65535.0)
        fail("depth map '", path, "': pixel (", x, ", ", y, ") depth ", d,
             " cannot be stored as a 16-bit count of ", scale, " (range 0 .. ", 65535.0 * scale,
             ")");
      counts.at<uint16_t>(y, x) = uint16_t(q);
    }
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", counts, png))
    fail("cannot encode depth map '", path, "' as PNG");
  io::writeFileAtomically(path, png.data(), png.size());
}

std::vector<float> readDepthPng(const std::string& path, double scale, int* width, int* height) {
  const std::vector<unsigned char> bytes = io::readFileBytes(path, "depth map");
  cv::Mat counts;
  try {
    counts = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    fail("cannot decode depth map '", path, "': ", e.what());
  }
  if (counts.empty())
    fail("cannot decode depth map '", path, "' (corrupt or not a PNG)");
  if (counts.type() != CV_16UC1)
    fail("depth map '", path, "' has ", counts.channels(), " channel(s) of OpenCV depth code ",
         counts.depth(), "; expected one 16-bit channel");
  std::vector<float> depth(size_t(counts.rows) * size_t(counts.cols));
  for (int y = 0; y < counts.rows; ++y)
    for (int x = 0; x < counts.cols; ++x)
      depth[size_t(y) * size_t(counts.cols) + size_t(x)] =
          float(double(counts.at<uint16_t>(y, x)) * scale);
  if (width)
    *width = counts.cols;
  if (height)
    *height = counts.rows;
  return depth;
}

std::string llffViewName(size_t index, size_t count) {
  size_t digits = 1;
  for (size_t v = count > 0 ? count - 1 : 0; v >= 10; v /= 10)
    ++digits;
  std::string s = std::to_string(index);
  const size_t width = std::max<size_t>(3, digits);
  if (s.size() < width)
    s.insert(0, width - s.size(), '0');
  return s;
}

void writeLlffScene(const std::string& dir, const LlffSceneData& data) {
  const size_t n = data.cameras.size();
  if (n == 0)
    fail("LLFF writer '", dir, "': no views");
  if (data.images.size() != n)
    fail("LLFF writer '", dir, "': ", n, " cameras but ", data.images.size(), " images");
  if (!data.depths.empty() && data.depths.size() != n)
    fail("LLFF writer '", dir, "': ", n, " cameras but ", data.depths.size(), " depth maps");
  if (data.near.size() != n || data.far.size() != n)
    fail("LLFF writer '", dir, "': ", n, " cameras but ", data.near.size(), " near and ",
         data.far.size(), " far bounds");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    fail("LLFF writer: output folder '", dir, "' does not exist");
  for (size_t i = 0; i < n; ++i) {
    const Camera& c = data.cameras[i];
    const io::Image& img = data.images[i];
    if (img.width != c.width || img.height != c.height)
      fail("LLFF writer '", dir, "': view ", i, ": image is ", img.width, " x ", img.height,
           " but its camera is for ", c.width, " x ", c.height);
    if (!data.depths.empty() && data.depths[i].size() != size_t(c.width) * size_t(c.height))
      fail("LLFF writer '", dir, "': view ", i, ": depth map has ", data.depths[i].size(),
           " values, expected ", c.width, " x ", c.height);
  }
  // Validate every camera before the first file appears.
  for (size_t i = 0; i < n; ++i)
    llffPoseRow(data.cameras[i], data.near[i], data.far[i], std::to_string(i));

  const fs::path root(dir);
  fs::create_directories(root / "images", ec);
  if (ec)
    fail("LLFF writer: cannot create '", (root / "images").string(), "': ", ec.message());
  if (!data.depths.empty()) {
    fs::create_directories(root / "depth", ec);
    if (ec)
      fail("LLFF writer: cannot create '", (root / "depth").string(), "': ", ec.message());
  }
  for (size_t i = 0; i < n; ++i) {
    const std::string name = llffViewName(i, n) + ".png";
    io::writeImagePng(data.images[i], (root / "images" / name).string());
    if (!data.depths.empty())
      writeDepthPng((root / "depth" / name).string(), data.depths[i], data.cameras[i].width,
                    data.cameras[i].height, data.depthScale);
  }
  writePosesBounds((root / "poses_bounds.npy").string(), data.cameras, data.near, data.far);
}

} // namespace simpli::scene

#include "support/scene_fixtures.h"

#include "simpli/model/io/npy.h"

#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;

namespace simpli::test {

void writePatternImage(const std::string& path, int width, int height, int seed, int depth,
                       int channels) {
  const int type = CV_MAKETYPE(depth == 16 ? CV_16U : CV_8U, channels);
  cv::Mat m(height, width, type);
  const int maxv = depth == 16 ? 65535 : 255;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < channels; ++c) {
        const int v = (x * 37 + y * 91 + c * 53 + seed * 17) % (maxv + 1);
        if (depth == 16)
          m.ptr<uint16_t>(y)[x * channels + c] = uint16_t(v * 257 % 65536);
        else
          m.ptr<uint8_t>(y)[x * channels + c] = uint8_t(v);
      }
  fs::create_directories(fs::path(path).parent_path());
  if (!cv::imwrite(path, m))
    throw std::runtime_error("test fixture: cannot write " + path);
}

Eigen::Matrix3d rotation(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

std::vector<scene::Camera> makeRig(int n, int width, int height) {
  std::vector<scene::Camera> cams;
  for (int i = 0; i < n; ++i) {
    scene::Camera c;
    const double a = 0.03 * (i - 0.5 * (n - 1));
    c.R = rotation(Eigen::Vector3d(0.2 + 0.1 * i, 1.0, 0.1 * i), a);
    const Eigen::Vector3d centre(0.1 * i - 0.1, 0.02 * i * i - 0.03, 0.01 * i);
    c.t = -c.R * centre;
    c.fx = 1.0;
    c.fy = 1.5;
    c.cx = 0.5;
    c.cy = 0.5;
    c.width = width;
    c.height = height;
    cams.push_back(c);
  }
  return cams;
}

std::vector<Eigen::Vector3d> makePoints(int n) {
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < n; ++i) {
    const double z = 2.0 + 8.0 * double(i) / double(n - 1);
    const double x = 0.3 * z * std::sin(1.7 * i);
    const double y = 0.2 * z * std::cos(2.3 * i);
    pts.emplace_back(x, y, z);
  }
  return pts;
}

std::vector<double> llffRow(const scene::Camera& c, double near, double far) {
  const Eigen::Matrix3d c2w = c.R.transpose(); // columns: right, down, forward
  const Eigen::Vector3d C = c.centre();
  Eigen::Matrix<double, 3, 5> m;
  m.col(0) = c2w.col(1);  // down
  m.col(1) = c2w.col(0);  // right
  m.col(2) = -c2w.col(2); // backwards
  m.col(3) = C;
  m.col(4) = Eigen::Vector3d(c.height, c.width, c.fx * c.width);
  std::vector<double> row;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 5; ++k)
      row.push_back(m(r, k));
  row.push_back(near);
  row.push_back(far);
  return row;
}

void writeLlffScene(const std::string& dir, const std::vector<scene::Camera>& cameras, double near,
                    double far) {
  fs::create_directories(fs::path(dir) / "images");
  std::vector<double> data;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const auto row = llffRow(cameras[i], near + 0.1 * double(i), far - double(i));
    data.insert(data.end(), row.begin(), row.end());
    std::ostringstream name;
    name << "img_" << std::setw(2) << std::setfill('0') << i << ".png";
    writePatternImage((fs::path(dir) / "images" / name.str()).string(), cameras[i].width,
                      cameras[i].height, int(i));
  }
  io::writeNpy((fs::path(dir) / "poses_bounds.npy").string(), data, {cameras.size(), 17});
}

void writeColmapScene(const std::string& dir, const std::vector<scene::Camera>& cameras,
                      const std::vector<Eigen::Vector3d>& points, const std::string& modelSubdir) {
  const fs::path model = modelSubdir.empty() ? fs::path(dir) : fs::path(dir) / modelSubdir;
  fs::create_directories(model);
  std::ostringstream cams, imgs;
  cams << std::setprecision(17) << "# Camera list with one line of data per camera:\n"
       << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n";
  imgs << std::setprecision(17) << "# Image list with two lines of data per image:\n";
  // Written in reverse name order: the reader sorts by name.
  for (size_t k = cameras.size(); k-- > 0;) {
    const scene::Camera& c = cameras[k];
    cams << k + 1 << " PINHOLE " << c.width << ' ' << c.height << ' ' << c.fx * c.width << ' '
         << c.fy * c.height << ' ' << c.cx * c.width << ' ' << c.cy * c.height << '\n';
    const Eigen::Quaterniond q(c.R);
    const std::string name = "view_" + std::to_string(k) + ".png";
    imgs << k + 10 << ' ' << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << c.t.x()
         << ' ' << c.t.y() << ' ' << c.t.z() << ' ' << k + 1 << ' ' << name << '\n';
    imgs << (k % 2 ? "" : "12.5 3.5 1 40.0 7.25 -1") << '\n'; // POINTS2D, sometimes empty
    writePatternImage((fs::path(dir) / "images" / name).string(), c.width, c.height, int(k));
  }
  writeText((model / "cameras.txt").string(), cams.str());
  writeText((model / "images.txt").string(), imgs.str());
  if (!points.empty()) {
    std::ostringstream pts;
    pts << std::setprecision(17) << "# 3D point list\n";
    for (size_t i = 0; i < points.size(); ++i)
      pts << i + 1 << ' ' << points[i].x() << ' ' << points[i].y() << ' ' << points[i].z()
          << " 128 128 128 0.5 10 0 11 2\n";
    writeText((model / "points3D.txt").string(), pts.str());
  }
}

void writeRealEstateScene(const std::string& dir, const std::vector<scene::Camera>& cameras,
                          const std::string& fileName, const std::string& imagesSubdir) {
  fs::create_directories(dir);
  const fs::path folder = fs::path(dir);
  const std::string file = fileName.empty() ? folder.filename().string() + ".txt" : fileName;
  std::ostringstream os;
  os << std::setprecision(17) << "https://www.youtube.com/watch?v=test\n";
  for (size_t i = 0; i < cameras.size(); ++i) {
    const scene::Camera& c = cameras[i];
    const long long id = 1000 * (long long)(i + 1);
    os << id << ' ' << c.fx << ' ' << c.fy << ' ' << c.cx << ' ' << c.cy << " 0 0";
    for (int r = 0; r < 3; ++r)
      os << ' ' << c.R(r, 0) << ' ' << c.R(r, 1) << ' ' << c.R(r, 2) << ' ' << c.t[r];
    os << '\n';
    writePatternImage((folder / imagesSubdir / (std::to_string(id) + ".png")).string(), c.width,
                      c.height, int(i));
  }
  writeText((folder / file).string(), os.str());
}

} // namespace simpli::test

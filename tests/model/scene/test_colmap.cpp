// COLMAP text models: layouts, camera models, bounds from points3D.txt, p10 normalisation,
// and bad input.
#include "support/expect_error.h"
#include "support/scene_fixtures.h"

#include "simpli/model/scene/readers.h"
#include "simpli/model/scene/scene.h"

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <sstream>

using namespace simpli;
using simpli::test::expectError;
using simpli::test::TempDir;
namespace fs = std::filesystem;

namespace {

class ColmapScene : public ::testing::Test {
protected:
  void SetUp() override {
    rig = test::makeRig(3);
    points = test::makePoints(200);
    root = dir / "colmap";
    test::writeColmapScene(root, rig, points);
  }
  std::string model(const std::string& file) const { return root + "/sparse/0/" + file; }
  // Replaces field `field` of the images.txt pose line of `name`.
  void editImageLine(const std::string& name, size_t field, const std::string& value) {
    std::istringstream in(test::readText(model("images.txt")));
    std::ostringstream out;
    std::string line;
    while (std::getline(in, line)) {
      if (line.find(name) != std::string::npos && line[0] != '#') {
        std::istringstream fields(line);
        std::vector<std::string> f;
        std::string x;
        while (fields >> x)
          f.push_back(x);
        f.at(field) = value;
        line.clear();
        for (const auto& s : f)
          line += (line.empty() ? "" : " ") + s;
      }
      out << line << '\n';
    }
    test::writeText(model("images.txt"), out.str());
  }
  TempDir dir;
  std::vector<scene::Camera> rig;
  std::vector<Eigen::Vector3d> points;
  std::string root;
};

// Independent computation of the expected bounds: per view p1 / p99 of in-frustum depths.
void expectedBounds(const std::vector<scene::Camera>& cams, const std::vector<Eigen::Vector3d>& pts,
                    double& nearB, double& farB, std::vector<double>& all) {
  nearB = 1e300;
  farB = 0;
  for (const scene::Camera& c : cams) {
    std::vector<double> d;
    for (const auto& X : pts) {
      const Eigen::Vector3d Xc = c.R * X + c.t;
      const double u = c.fx * Xc.x() / Xc.z() + c.cx, v = c.fy * Xc.y() / Xc.z() + c.cy;
      if (Xc.z() > 0 && u >= 0 && u <= 1 && v >= 0 && v <= 1)
        d.push_back(Xc.z());
    }
    all.insert(all.end(), d.begin(), d.end());
    nearB = std::min(nearB, scene::percentile(d, 1));
    farB = std::max(farB, scene::percentile(d, 99));
  }
}

} // namespace

TEST_F(ColmapScene, ReadsCamerasPointsAndBounds) {
  const scene::Scene s = scene::readScene(root);
  EXPECT_EQ(s.format, scene::SceneFormat::Colmap);
  EXPECT_EQ(s.posesFile, model("images.txt"));
  ASSERT_EQ(s.size(), 3u);
  double nearB, farB;
  std::vector<double> all;
  expectedBounds(rig, points, nearB, farB, all);
  ASSERT_GT(all.size(), 500u); // most points are visible in all views
  // The reference's rule: p10 of the SfM depths -> 1.25.
  EXPECT_EQ(s.normalisation.rule, scene::NormalisationMode::PointPercentile);
  const double scale = 1.25 / scene::percentile(all, 10);
  EXPECT_NEAR(s.normalisation.scale, scale, 1e-12);
  EXPECT_NEAR(s.near, nearB * scale, 1e-9);
  EXPECT_NEAR(s.far, farB * scale, 1e-9);
  EXPECT_NEAR(s.sceneNear(), nearB, 1e-9);
  ASSERT_EQ(s.points.size(), points.size());
  EXPECT_LT((s.points[7] - scale * points[7]).norm(), 1e-12);
  for (size_t i = 0; i < 3; ++i) {
    const scene::Camera& c = s.views[i].camera;
    EXPECT_EQ(s.views[i].name, "view_" + std::to_string(i) + ".png"); // sorted by name
    EXPECT_LT((c.R - rig[i].R).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((c.t - scale * rig[i].t).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(c.fx, 1.0, 1e-15);
    EXPECT_NEAR(c.fy, 1.5, 1e-15);
    EXPECT_NEAR(c.cx, 0.5, 1e-15);
    EXPECT_EQ(c.width, 48);
  }
}

TEST_F(ColmapScene, LayoutsAndSimplePinhole) {
  // <root>/*.txt layout, SIMPLE_PINHOLE, no points3D.txt: default bounds 1..100, scale 1.
  const std::string flat = dir / "flat";
  test::writeColmapScene(flat, rig, {}, "");
  test::writeText(flat + "/cameras.txt",
                  "# comment\n1 SIMPLE_PINHOLE 48 32 48 24 16\n2 SIMPLE_PINHOLE 48 32 48 24 16\n"
                  "3 PINHOLE 48 32 48 48 12 8\n");
  const scene::Scene s = scene::readScene(flat);
  EXPECT_EQ(s.format, scene::SceneFormat::Colmap);
  EXPECT_DOUBLE_EQ(s.near, scene::kDefaultNear);
  EXPECT_DOUBLE_EQ(s.far, scene::kDefaultFar);
  EXPECT_DOUBLE_EQ(s.normalisation.scale, 1.0);
  EXPECT_NE(s.boundsSource.find("default"), std::string::npos);
  EXPECT_DOUBLE_EQ(s.views[0].camera.fx, 1.0);
  EXPECT_DOUBLE_EQ(s.views[0].camera.fy, 1.5);
  EXPECT_DOUBLE_EQ(s.views[2].camera.cx, 0.25); // view_2 uses camera 3
  EXPECT_DOUBLE_EQ(s.views[2].camera.cy, 0.25);
  // <root>/sparse/*.txt (what image_undistorter + model_converter produce).
  const std::string sparse = dir / "sparse_layout";
  test::writeColmapScene(sparse, rig, points, "sparse");
  EXPECT_EQ(scene::readScene(sparse).size(), 3u);
  // Explicit bounds without points.
  scene::SceneReadOptions o;
  o.near = 0.5;
  o.far = 20;
  const scene::Scene e = scene::readScene(flat, o);
  EXPECT_DOUBLE_EQ(e.normalisation.scale, 2.0);
  EXPECT_DOUBLE_EQ(e.far, 40.0);
}

TEST_F(ColmapScene, DistortedCameraModel) {
  test::writeText(model("cameras.txt"),
                  "1 PINHOLE 48 32 48 48 24 16\n2 OPENCV 48 32 48 48 24 16 0.1 0 0 0\n"
                  "3 PINHOLE 48 32 48 48 24 16\n");
  expectError([&] { scene::readScene(root); },
              {"cameras.txt", "line 2", "OPENCV", "image_undistorter"});
  test::writeText(model("cameras.txt"), "1 SIMPLE_RADIAL 48 32 48 24 16 0.01\n");
  expectError([&] { scene::readScene(root); },
              {"cameras.txt", "SIMPLE_RADIAL", "image_undistorter"});
  test::writeText(model("cameras.txt"), "1 RADIAL 48 32 48 24 16 0.01 0.0\n");
  expectError([&] { scene::readScene(root); }, {"RADIAL", "image_undistorter"});
}

TEST_F(ColmapScene, UnknownModelAndBadCameraLines) {
  test::writeText(model("cameras.txt"), "1 FANCY_LENS 48 32 1 2 3\n");
  expectError([&] { scene::readScene(root); },
              {"cameras.txt", "line 1", "unknown camera model", "FANCY_LENS"});
  test::writeText(model("cameras.txt"), "1 PINHOLE 48 32 48 48 24\n");
  expectError([&] { scene::readScene(root); }, {"cameras.txt", "3 parameters", "expected 4"});
  test::writeText(model("cameras.txt"), "1 PINHOLE 48 32 48 nan 24 16\n");
  expectError([&] { scene::readScene(root); }, {"cameras.txt", "line 1", "nan", "not finite"});
  test::writeText(model("cameras.txt"), "1 PINHOLE 48 -32 48 48 24 16\n");
  expectError([&] { scene::readScene(root); }, {"cameras.txt", "48 x -32"});
  test::writeText(model("cameras.txt"), "1 PINHOLE 48 32 48 48 24 16\n");
  expectError([&] { scene::readScene(root); }, {"images.txt", "CAMERA_ID 3", "not in"});
}

TEST_F(ColmapScene, ImageNotOnDisk) {
  fs::remove(root + "/images/view_1.png");
  expectError([&] { scene::readScene(root); }, {"images.txt", "'view_1.png'", "not found"});
}

TEST_F(ColmapScene, BadPoses) {
  editImageLine("view_1.png", 5, "nan");
  expectError([&] { scene::readScene(root); }, {"images.txt", "TX", "nan"});
  test::writeColmapScene(root, rig, points);
  editImageLine("view_2.png", 1, "2.0");
  expectError([&] { scene::readScene(root); }, {"images.txt", "view_2.png", "quaternion", "norm"});
  test::writeColmapScene(root, rig, points);
  editImageLine("view_0.png", 3, "abc");
  expectError([&] { scene::readScene(root); }, {"images.txt", "QY", "'abc'", "not a number"});
  test::writeColmapScene(root, rig, points);
  editImageLine("view_0.png", 9, "view_1.png");
  expectError([&] { scene::readScene(root); }, {"images.txt", "view_1.png", "twice"});
}

TEST_F(ColmapScene, BadPointsFile) {
  test::writeText(model("points3D.txt"), "1 0.5 0.5\n");
  expectError([&] { scene::readScene(root); }, {"points3D.txt", "line 1"});
  test::writeText(model("points3D.txt"), "1 0.5 inf 3 1 1 1 0\n");
  expectError([&] { scene::readScene(root); }, {"points3D.txt", "line 1", "Y", "inf"});
  // Points all behind the cameras: no bounds from them, defaults apply.
  test::writeText(model("points3D.txt"), "1 0 0 -5 1 1 1 0\n");
  const scene::Scene s = scene::readScene(root);
  EXPECT_DOUBLE_EQ(s.sceneNear(), scene::kDefaultNear);
  EXPECT_EQ(s.normalisation.rule, scene::NormalisationMode::NearBound);
}

TEST_F(ColmapScene, BinaryModelAndMissingParts) {
  const std::string bin = dir / "binary";
  fs::create_directories(bin + "/sparse/0");
  test::writeText(bin + "/sparse/0/cameras.bin", "binary");
  expectError([&] { scene::readScene(bin); }, {"cameras.bin", "model_converter"});
  fs::remove_all(root + "/images");
  expectError([&] { scene::readScene(root); }, {root + "/images", "does not exist"});
  test::writeText(model("images.txt"), "# nothing\n");
  fs::create_directories(root + "/images");
  expectError([&] { scene::readScene(root); }, {"images.txt", "no images"});
}

namespace {

// images.txt for `rig` (IMAGE_ID k + 10, CAMERA_ID k + 1, NAME view_k.png), in name order;
// `points2D(k)` is the POINTS2D line written after image k, or "-" for none at all.
std::string imagesText(const std::vector<scene::Camera>& rig,
                       const std::function<std::string(size_t)>& points2D) {
  std::ostringstream os;
  os << std::setprecision(17) << "# Image list\n#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, ...\n";
  for (size_t k = 0; k < rig.size(); ++k) {
    const Eigen::Quaterniond q(rig[k].R);
    os << k + 10 << ' ' << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' '
       << rig[k].t.x() << ' ' << rig[k].t.y() << ' ' << rig[k].t.z() << ' ' << k + 1 << " view_"
       << k << ".png\n";
    const std::string p = points2D(k);
    if (p != "-")
      os << p << '\n';
  }
  return os.str();
}

} // namespace

// Some tools write images.txt without POINTS2D lines; every pose line is still a view (the
// reader once took every second line as a POINTS2D line and read 6 of 12 views).
TEST_F(ColmapScene, ImagesWithoutPoints2DLines) {
  const std::vector<scene::Camera> twelve = test::makeRig(12);
  test::writeColmapScene(root, twelve, points);
  test::writeText(model("images.txt"), imagesText(twelve, [](size_t) { return "-"; }));
  scene::SceneSource src = scene::readColmapSource(root);
  ASSERT_EQ(src.cameras.size(), 12u);
  for (size_t k = 0; k < 12; ++k) { // sorted by name: view_0, view_1, view_10, ...
    const size_t index = std::stoul(src.names[k].substr(5));
    EXPECT_LT((src.cameras[k].R - twelve.at(index).R).cwiseAbs().maxCoeff(), 1e-9) << index;
  }
  // Mixed: POINTS2D lines present, empty, absent, and absent at the end; comments between.
  test::writeText(model("images.txt"), imagesText(twelve, [](size_t k) -> std::string {
                    switch (k % 4) {
                    case 0:
                      return "12.5 3.5 1 40.0 7.25 -1";
                    case 1:
                      return "";
                    case 2:
                      return "# a comment where a POINTS2D line could be";
                    default:
                      return "-";
                    }
                  }));
  src = scene::readColmapSource(root);
  ASSERT_EQ(src.cameras.size(), 12u);
  std::vector<std::string> names = src.names;
  std::sort(names.begin(), names.end());
  EXPECT_EQ(std::unique(names.begin(), names.end()), names.end());
  EXPECT_EQ(scene::readScene(root).size(), 12u);
  // Windows line ends.
  std::string crlf;
  for (char c : imagesText(twelve, [](size_t) { return "1 2 -1"; }))
    crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  test::writeText(model("images.txt"), crlf);
  EXPECT_EQ(scene::readColmapSource(root).cameras.size(), 12u);
}

// A line that is neither a pose line nor POINTS2D triplets, or a repeated IMAGE_ID, is an error
// naming the line, the field and the value.
TEST_F(ColmapScene, MalformedImageLinesAreNamed) {
  auto withLine = [&](size_t after, const std::string& line) {
    test::writeText(model("images.txt"), imagesText(rig, [&](size_t k) -> std::string {
                      return k == after ? line : "1 2 -1";
                    }));
  };
  withLine(0, "12.5 3.5 1 40.0"); // 4 fields: not triplets, not a pose line
  expectError([&] { scene::readColmapSource(root); },
              {"images.txt", "line 4", "POINTS2D", "4 field(s)", "12.5 3.5 1 40.0"});
  withLine(1, "12.5 3.5 x");
  expectError([&] { scene::readColmapSource(root); }, {"images.txt", "line 6", "3 field(s)"});
  withLine(0, "1 2 -1 3 4 -1 5 6 -1 7 8"); // 11 fields, shaped like a pose line
  expectError([&] { scene::readColmapSource(root); },
              {"images.txt", "line 4", "quaternion", "norm"});
  // The same IMAGE_ID twice.
  std::string text = imagesText(rig, [](size_t) { return ""; });
  const size_t at = text.find("\n11 ");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 4, "\n10 ");
  test::writeText(model("images.txt"), text);
  expectError([&] { scene::readColmapSource(root); },
              {"images.txt", "IMAGE_ID 10", "twice", "also line 3"});
}

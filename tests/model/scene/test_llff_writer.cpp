// LLFF writer (scene/llff_writer.h): the exact inverse of the LLFF reader.
#include "simpli/model/io/files.h"
#include "simpli/model/io/npy.h"
#include "simpli/model/scene/llff_writer.h"
#include "simpli/model/scene/readers.h"
#include "simpli/model/scene/scene.h"

#include "support/expect_error.h"
#include "synthetic/synthetic_test_util.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>

using namespace simpli;
using Eigen::Vector3d;
using simpli::test::expectError;
using simpli::test::TempDir;

namespace {

scene::Camera someCamera(int i, int w = 24, int h = 16) {
  scene::Camera c;
  const Eigen::Matrix3d c2w =
      (Eigen::AngleAxisd(0.1 * i + 0.2, Vector3d::UnitY()) *
       Eigen::AngleAxisd(-0.05 * i, Vector3d::UnitX()) * Eigen::AngleAxisd(0.3, Vector3d::UnitZ()))
          .toRotationMatrix();
  c.R = c2w.transpose();
  c.t = -c.R * Vector3d(0.1 * i, -0.2, 0.05 * i * i);
  c.fx = 1.1;
  c.fy = 1.1 * w / h;
  c.width = w;
  c.height = h;
  return c;
}

io::Image someImage(int w, int h, int seed) {
  io::Image img(w, h);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        img.at(c, y, x) = float(((x * 7 + y * 13 + c * 29 + seed * 31) % 256) / 127.5 - 1.0);
  return img;
}

scene::LlffSceneData someScene(size_t n) {
  scene::LlffSceneData d;
  for (size_t i = 0; i < n; ++i) {
    d.cameras.push_back(someCamera(int(i)));
    d.images.push_back(someImage(24, 16, int(i)));
    d.near.push_back(1.5 + 0.1 * double(i));
    d.far.push_back(30.0 + double(i));
    std::vector<float> depth(24 * 16);
    for (size_t k = 0; k < depth.size(); ++k)
      depth[k] = float(2.0 + 0.01 * double(k) + double(i));
    d.depths.push_back(depth);
  }
  return d;
}

} // namespace

TEST(LlffWriter, PoseRowLayout) {
  const scene::Camera c = someCamera(2);
  const auto row = scene::llffPoseRow(c, 2.0, 40.0);
  const Vector3d centre = c.centre();
  for (int r = 0; r < 3; ++r) {
    EXPECT_EQ(row[size_t(5 * r + 0)], c.R(1, r));  // down = camera y in world
    EXPECT_EQ(row[size_t(5 * r + 1)], c.R(0, r));  // right = camera x
    EXPECT_EQ(row[size_t(5 * r + 2)], -c.R(2, r)); // backwards = -camera z
    EXPECT_EQ(row[size_t(5 * r + 3)], centre[r]);
  }
  EXPECT_EQ(row[4], 16.0);
  EXPECT_EQ(row[9], 24.0);
  EXPECT_DOUBLE_EQ(row[14], 1.1 * 24);
  EXPECT_EQ(row[15], 2.0);
  EXPECT_EQ(row[16], 40.0);
}

TEST(LlffWriter, NpyFileIsVersion1Float64COrder) {
  TempDir dir;
  const scene::LlffSceneData d = someScene(3);
  scene::writePosesBounds(dir.str("poses_bounds.npy"), d.cameras, d.near, d.far);
  const std::vector<unsigned char> bytes = io::readFileBytes(dir.str("poses_bounds.npy"), "npy");
  ASSERT_GT(bytes.size(), 10u);
  EXPECT_EQ(bytes[0], 0x93);
  EXPECT_EQ(bytes[6], 1); // format version 1.0
  EXPECT_EQ(bytes[7], 0);
  const std::string header(bytes.begin() + 10, bytes.begin() + 10 + (bytes[8] | bytes[9] << 8));
  EXPECT_NE(header.find("'descr': '<f8'"), std::string::npos) << header;
  EXPECT_NE(header.find("'fortran_order': False"), std::string::npos) << header;
  EXPECT_NE(header.find("'shape': (3, 17)"), std::string::npos) << header;
  EXPECT_EQ(bytes.size(), 10 + header.size() + 3 * 17 * 8);
  const io::NpyArray a = io::readNpy(dir.str("poses_bounds.npy"));
  ASSERT_EQ(a.shape, (std::vector<size_t>{3, 17}));
  for (size_t i = 0; i < 3; ++i) {
    const auto row = scene::llffPoseRow(d.cameras[i], d.near[i], d.far[i]);
    for (size_t j = 0; j < 17; ++j)
      EXPECT_EQ(a.at(i, j), row[j]);
  }
}

TEST(LlffWriter, RoundTripThroughTheLlffReader) {
  TempDir dir;
  const scene::LlffSceneData d = someScene(4);
  scene::writeLlffScene(dir.str(), d);
  const scene::SceneSource src = scene::readLlffSource(dir.str());
  ASSERT_EQ(src.cameras.size(), 4u);
  EXPECT_DOUBLE_EQ(src.near, 1.5);
  EXPECT_DOUBLE_EQ(src.far, 33.0);
  for (size_t i = 0; i < 4; ++i) {
    const scene::Camera& a = d.cameras[i];
    const scene::Camera& b = src.cameras[i];
    EXPECT_EQ(b.R, a.R) << i; // a pure permutation and negation of entries: bit-exact
    EXPECT_LT((b.t - a.t).cwiseAbs().maxCoeff(), 1e-14) << i;
    EXPECT_DOUBLE_EQ(b.fx, a.fx);
    EXPECT_DOUBLE_EQ(b.fy, a.fy);
    EXPECT_EQ(b.cx, 0.5);
    EXPECT_EQ(b.cy, 0.5);
    EXPECT_EQ(b.width, 24);
    EXPECT_EQ(b.height, 16);
    EXPECT_EQ(std::filesystem::path(src.imagePaths[i]).filename().string(),
              scene::llffViewName(i, 4) + ".png");
  }
  // readScene without normalisation: images come back value for value.
  scene::SceneReadOptions options;
  options.normalisation.mode = scene::NormalisationMode::None;
  options.sizeMultiple = 1; // keep 24 x 16
  const scene::Scene scene = scene::readScene(dir.str(), options);
  ASSERT_EQ(scene.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(scene.views[i].image.data, d.images[i].data) << i;
    EXPECT_LT((scene.views[i].camera.t - d.cameras[i].t).cwiseAbs().maxCoeff(), 1e-14);
  }
}

TEST(LlffWriter, DepthPngRoundTrip) {
  TempDir dir;
  std::vector<float> depth = {0.0f, 1.2345f, 65.535f, 17.0f, 0.0004f, 3.0f};
  scene::writeDepthPng(dir.str("d.png"), depth, 3, 2, 0.001);
  int w = 0, h = 0;
  const std::vector<float> back = scene::readDepthPng(dir.str("d.png"), 0.001, &w, &h);
  EXPECT_EQ(w, 3);
  EXPECT_EQ(h, 2);
  ASSERT_EQ(back.size(), depth.size());
  for (size_t i = 0; i < depth.size(); ++i)
    EXPECT_NEAR(back[i], depth[i], 0.0005 + 1e-6) << i;
  EXPECT_EQ(back[0], 0.0f);
  const cv::Mat raw = cv::imread(dir.str("d.png"), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(raw.type(), CV_16UC1);
  EXPECT_EQ(raw.at<uint16_t>(0, 1), 1235);
}

TEST(LlffWriter, ViewNamesSortInViewOrder) {
  EXPECT_EQ(scene::llffViewName(0, 12), "000");
  EXPECT_EQ(scene::llffViewName(11, 12), "011");
  EXPECT_EQ(scene::llffViewName(999, 1000), "999");
  EXPECT_EQ(scene::llffViewName(5, 1001), "0005");
  EXPECT_EQ(scene::llffViewName(0, 0), "000");
}

TEST(LlffWriter, RejectsWhatLlffCannotHold) {
  scene::Camera c = someCamera(0);
  c.fy *= 1.01;
  expectError([&] { scene::llffPoseRow(c, 1, 2, "7"); }, {"view 7", "differ", "square pixels"});
  c = someCamera(0);
  c.cx = 0.52;
  expectError([&] { scene::llffPoseRow(c, 1, 2, "3"); }, {"view 3", "principal point", "0.52"});
  c = someCamera(0);
  c.width = 0;
  expectError([&] { scene::llffPoseRow(c, 1, 2); }, {"image size 0 x 16"});
  c = someCamera(0);
  c.R(0, 0) += 0.1;
  expectError([&] { scene::llffPoseRow(c, 1, 2); }, {"rotation is not orthonormal"});
  expectError([&] { scene::llffPoseRow(someCamera(0), 0, 2); }, {"near bound 0"});
  expectError([&] { scene::llffPoseRow(someCamera(0), 3, 2); }, {"far bound 2", "near bound 3"});
  expectError([&] { scene::llffPoseRow(someCamera(0), 1, std::nan("")); }, {"far bound nan"});
}

TEST(LlffWriter, RejectsInconsistentInputWithoutWritingAnything) {
  TempDir dir;
  scene::LlffSceneData d = someScene(2);
  d.images.pop_back();
  expectError([&] { scene::writeLlffScene(dir.str(), d); }, {"2 cameras but 1 images"});
  d = someScene(2);
  d.images[1] = someImage(20, 16, 0);
  expectError([&] { scene::writeLlffScene(dir.str(), d); }, {"view 1", "20 x 16", "24 x 16"});
  d = someScene(2);
  d.far[1] = 1.0;
  expectError([&] { scene::writeLlffScene(dir.str(), d); }, {"view 1", "far bound 1"});
  d = someScene(2);
  d.near.pop_back();
  expectError([&] { scene::writeLlffScene(dir.str(), d); }, {"1 near"});
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
  expectError([&] { scene::writeLlffScene(dir.str("missing"), someScene(1)); },
              {"missing", "does not exist"});
  expectError([&] { scene::writePosesBounds(dir.str("p.npy"), {}, {}, {}); },
              {"p.npy", "no cameras"});
}

TEST(LlffWriter, RejectsDepthsItCannotStore) {
  TempDir dir;
  expectError(
      [&] {
        scene::writeDepthPng(dir.str("d.png"), {1.0f, 70.0f}, 2, 1, 0.001);
      },
      {"d.png", "pixel (1, 0)", "depth 70", "65.535"});
  expectError(
      [&] {
        scene::writeDepthPng(dir.str("d.png"), {1.0f, -1.0f}, 2, 1, 0.001);
      },
      {"pixel (1, 0)", "depth -1"});
  expectError([&] { scene::writeDepthPng(dir.str("d.png"), {std::nanf("")}, 1, 1, 0.001); },
              {"depth nan"});
  expectError([&] { scene::writeDepthPng(dir.str("d.png"), {1.0f}, 2, 1, 0.001); },
              {"1 values for 2 x 1"});
  expectError([&] { scene::writeDepthPng(dir.str("d.png"), {1.0f}, 1, 1, 0.0); },
              {"depth scale 0"});
  EXPECT_FALSE(std::filesystem::exists(dir.str("d.png")));
  // Reading: missing file, not 16-bit.
  expectError([&] { scene::readDepthPng(dir.str("none.png"), 0.001); },
              {"none.png", "does not exist"});
  cv::imwrite(dir.str("rgb.png"), cv::Mat(2, 2, CV_8UC3, cv::Scalar(1, 2, 3)));
  expectError([&] { scene::readDepthPng(dir.str("rgb.png"), 0.001); },
              {"rgb.png", "3 channel(s)", "one 16-bit channel"});
}

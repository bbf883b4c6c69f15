// simpli::Image reading / writing: value mapping, channel handling, resize, errors.
#include "support/expect_error.h"
#include "support/scene_fixtures.h"

#include "simpli/error.h"
#include "simpli/model/io/image.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>

using namespace simpli;
using simpli::test::TempDir;

using simpli::test::expectError;

TEST(Image, EightBitValuesAndRgbOrder) {
  TempDir dir;
  cv::Mat bgr(2, 3, CV_8UC3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      bgr.at<cv::Vec3b>(y, x) = cv::Vec3b(uchar(10 * x), uchar(100 + y), uchar(255 - x));
  const std::string path = dir / "a.png";
  ASSERT_TRUE(cv::imwrite(path, bgr));
  const io::Image im = io::readImage(path);
  ASSERT_EQ(im.width, 3);
  ASSERT_EQ(im.height, 2);
  ASSERT_EQ(im.data.size(), 18u);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x) {
      EXPECT_FLOAT_EQ(im.at(0, y, x), float((255 - x) / 127.5 - 1)); // R
      EXPECT_FLOAT_EQ(im.at(1, y, x), float((100 + y) / 127.5 - 1)); // G
      EXPECT_FLOAT_EQ(im.at(2, y, x), float(10 * x / 127.5 - 1));    // B
    }
  EXPECT_FLOAT_EQ(im.at(0, 0, 0), 1.0f);
  EXPECT_FLOAT_EQ(im.at(2, 0, 0), -1.0f);
}

TEST(Image, SixteenBit) {
  TempDir dir;
  cv::Mat m(1, 3, CV_16UC3);
  m.at<cv::Vec<uint16_t, 3>>(0, 0) = {0, 65535, 32768};
  m.at<cv::Vec<uint16_t, 3>>(0, 1) = {1000, 2000, 3000};
  m.at<cv::Vec<uint16_t, 3>>(0, 2) = {65535, 65535, 65535};
  const std::string path = dir / "a16.png";
  ASSERT_TRUE(cv::imwrite(path, m));
  const io::Image im = io::readImage(path);
  EXPECT_FLOAT_EQ(im.at(2, 0, 0), -1.0f); // B = 0
  EXPECT_FLOAT_EQ(im.at(1, 0, 0), 1.0f);
  EXPECT_FLOAT_EQ(im.at(0, 0, 0), float(32768 / 32767.5 - 1));
  EXPECT_FLOAT_EQ(im.at(0, 0, 1), float(3000 / 32767.5 - 1));
  EXPECT_FLOAT_EQ(im.at(2, 0, 1), float(1000 / 32767.5 - 1));
}

TEST(Image, GreyIsReplicatedAndAlphaDropped) {
  TempDir dir;
  cv::Mat grey(2, 2, CV_8UC1, cv::Scalar(51));
  ASSERT_TRUE(cv::imwrite(dir / "g.png", grey));
  const io::Image g = io::readImage(dir / "g.png");
  for (int c = 0; c < 3; ++c)
    EXPECT_FLOAT_EQ(g.at(c, 1, 1), float(51 / 127.5 - 1));

  cv::Mat bgra(2, 2, CV_8UC4, cv::Scalar(10, 20, 30, 0)); // fully transparent
  ASSERT_TRUE(cv::imwrite(dir / "a.png", bgra));
  const io::Image a = io::readImage(dir / "a.png");
  EXPECT_FLOAT_EQ(a.at(0, 0, 0), float(30 / 127.5 - 1));
  EXPECT_FLOAT_EQ(a.at(1, 0, 0), float(20 / 127.5 - 1));
  EXPECT_FLOAT_EQ(a.at(2, 0, 0), float(10 / 127.5 - 1));

  cv::Mat grey16(2, 2, CV_16UC1, cv::Scalar(65535));
  ASSERT_TRUE(cv::imwrite(dir / "g16.png", grey16));
  EXPECT_FLOAT_EQ(io::readImage(dir / "g16.png").at(2, 1, 0), 1.0f);
}

TEST(Image, Jpeg) {
  TempDir dir;
  cv::Mat bgr(16, 16, CV_8UC3, cv::Scalar(200, 100, 50));
  ASSERT_TRUE(cv::imwrite(dir / "a.jpg", bgr));
  const io::Image im = io::readImage(dir / "a.jpg");
  EXPECT_EQ(im.width, 16);
  EXPECT_NEAR(im.at(0, 8, 8), 50 / 127.5 - 1, 0.03);
  EXPECT_NEAR(im.at(2, 8, 8), 200 / 127.5 - 1, 0.03);
}

// A JPEG whose EXIF orientation says "rotate 90°": the stored pixel array is used as is.
TEST(Image, ExifOrientationIsIgnored) {
  TempDir dir;
  cv::Mat bgr(16, 32, CV_8UC3, cv::Scalar(0, 0, 0));
  bgr(cv::Rect(0, 0, 8, 16)).setTo(cv::Scalar(255, 255, 255)); // white left strip
  std::vector<uchar> jpg;
  ASSERT_TRUE(cv::imencode(".jpg", bgr, jpg));
  // APP1 Exif segment: little-endian TIFF with one IFD entry, Orientation (0x0112) = 6.
  const std::vector<uchar> app1 = {0xFF, 0xE1, 0x00, 0x22, 'E',  'x',  'i',  'f',  0,
                                   0,    'I',  'I',  0x2A, 0x00, 0x08, 0x00, 0x00, 0x00,
                                   0x01, 0x00, 0x12, 0x01, 0x03, 0x00, 0x01, 0x00, 0x00,
                                   0x00, 0x06, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
  jpg.insert(jpg.begin() + 2, app1.begin(), app1.end());
  const std::string path = dir / "exif.jpg";
  test::writeText(path, std::string(jpg.begin(), jpg.end()));
  // Sanity: OpenCV's default read honours the tag (so this test can fail).
  const cv::Mat rotated = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_EQ(rotated.cols, 16) << "EXIF fixture not recognised by OpenCV";
  const io::Image im = io::readImage(path);
  EXPECT_EQ(im.width, 32);
  EXPECT_EQ(im.height, 16);
  EXPECT_GT(im.at(0, 8, 2), 0.9f);
  EXPECT_LT(im.at(0, 8, 30), -0.9f);
}

TEST(Image, ResizeDownToMultiple) {
  TempDir dir;
  cv::Mat bgr(35, 50, CV_8UC3, cv::Scalar(0, 127, 255));
  ASSERT_TRUE(cv::imwrite(dir / "a.png", bgr));
  io::ImageSize original;
  const io::Image im = io::readImage(dir / "a.png", 16, &original);
  EXPECT_EQ(original.width, 50);
  EXPECT_EQ(original.height, 35);
  EXPECT_EQ(im.width, 48);
  EXPECT_EQ(im.height, 32);
  EXPECT_NEAR(im.at(0, 10, 10), 1.0, 1e-5); // constant image stays constant under INTER_AREA
  EXPECT_NEAR(im.at(2, 31, 47), -1.0, 1e-5);
  const io::Image same = io::readImage(dir / "a.png", 1);
  EXPECT_EQ(same.width, 50);
  EXPECT_EQ(io::floorToMultiple(47, 16), 32);
  EXPECT_EQ(io::floorToMultiple(48, 16), 48);
  EXPECT_EQ(io::floorToMultiple(7, 0), 7);
}

TEST(Image, TooSmallForMultiple) {
  TempDir dir;
  ASSERT_TRUE(cv::imwrite(dir / "tiny.png", cv::Mat(10, 40, CV_8UC3, cv::Scalar(0))));
  expectError([&] { io::readImage(dir / "tiny.png", 16); }, {"tiny.png", "40 x 10", "16"});
}

TEST(Image, ResizeImageArea) {
  io::Image im(4, 2);
  for (int c = 0; c < 3; ++c)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 4; ++x)
        im.at(c, y, x) = float(x + 4 * y + c);
  const io::Image half = io::resizeImage(im, 2, 1);
  ASSERT_EQ(half.width, 2);
  // 2x2 box means: (0+1+4+5)/4 = 2.5, (2+3+6+7)/4 = 4.5, plus the channel offset.
  EXPECT_FLOAT_EQ(half.at(0, 0, 0), 2.5f);
  EXPECT_FLOAT_EQ(half.at(1, 0, 1), 5.5f);
  expectError([&] { io::resizeImage(im, 0, 3); }, {"0 x 3"});
}

TEST(Image, WritePngRoundTrip) {
  TempDir dir;
  io::Image im(5, 3);
  for (size_t i = 0; i < im.data.size(); ++i)
    im.data[i] = float(int(i * 7 % 256) / 127.5 - 1.0);
  im.data[0] = 3.0f;  // clamped to 255
  im.data[1] = -2.0f; // clamped to 0
  const std::string path = dir / "out.png";
  io::writeImagePng(im, path);
  const io::Image back = io::readImage(path);
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 3);
  EXPECT_FLOAT_EQ(back.data[0], 1.0f);
  EXPECT_FLOAT_EQ(back.data[1], -1.0f);
  for (size_t i = 2; i < im.data.size(); ++i)
    EXPECT_FLOAT_EQ(back.data[i], im.data[i]) << i;
  // Nothing but the output is left in the folder (the temporary was renamed).
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1);
  expectError([&] { io::writeImagePng(io::Image(), dir / "empty.png"); }, {"empty.png", "empty"});
  expectError([&] { io::writeImagePng(im, dir / "no_such_dir/x.png"); }, {"no_such_dir"});
}

TEST(Image, Errors) {
  TempDir dir;
  expectError([&] { io::readImage(dir / "missing.png"); }, {"missing.png", "does not exist"});
  expectError([&] { io::readImage(dir.path().string()); }, {"directory"});
  test::writeText(dir / "empty.png", "");
  expectError([&] { io::readImage(dir / "empty.png"); }, {"empty.png", "empty"});
  test::writeText(dir / "garbage.png", "this is not an image at all, just some text");
  expectError([&] { io::readImage(dir / "garbage.png"); }, {"garbage.png", "cannot decode"});
  // A PNG cut in half.
  test::writePatternImage(dir / "full.png", 64, 64, 3);
  const std::string png = test::readText(dir / "full.png");
  test::writeText(dir / "cut.png", png.substr(0, png.size() / 2));
  expectError([&] { io::readImage(dir / "cut.png"); }, {"cut.png"});
  expectError([] { io::Image(-1, 2); }, {"-1"});
}

// libjpeg decodes a truncated JPEG with a warning only; readImage must reject it.
TEST(Image, TruncatedJpeg) {
  TempDir dir;
  cv::Mat bgr(64, 64, CV_8UC3);
  cv::randu(bgr, 0, 255);
  std::vector<uchar> jpg;
  ASSERT_TRUE(cv::imencode(".jpg", bgr, jpg));
  const std::string full(jpg.begin(), jpg.end());
  test::writeText(dir / "cut.jpg", full.substr(0, full.size() / 2));
  ASSERT_FALSE(cv::imread(dir / "cut.jpg").empty()) << "OpenCV rejects it by itself now";
  expectError([&] { io::readImage(dir / "cut.jpg"); }, {"cut.jpg", "truncated"});
  test::writeText(dir / "cut2.jpg", full.substr(0, full.size() - 1)); // only EOI's last byte
  expectError([&] { io::readImage(dir / "cut2.jpg"); }, {"cut2.jpg", "truncated"});
  // Complete files, also with bytes appended after the end-of-image marker, are accepted.
  test::writeText(dir / "ok.jpg", full);
  EXPECT_EQ(io::readImage(dir / "ok.jpg").width, 64);
  test::writeText(dir / "trailer.jpg", full + std::string("\0\0trailing data", 15));
  EXPECT_EQ(io::readImage(dir / "trailer.jpg").width, 64);
  // Progressive JPEG (several scans).
  std::vector<uchar> prog;
  ASSERT_TRUE(cv::imencode(".jpg", bgr, prog, {cv::IMWRITE_JPEG_PROGRESSIVE, 1}));
  test::writeText(dir / "prog.jpg", std::string(prog.begin(), prog.end()));
  EXPECT_EQ(io::readImage(dir / "prog.jpg").height, 64);
  test::writeText(dir / "progcut.jpg",
                  std::string(prog.begin(), prog.begin() + long(prog.size() * 2 / 3)));
  expectError([&] { io::readImage(dir / "progcut.jpg"); }, {"progcut.jpg"});
}

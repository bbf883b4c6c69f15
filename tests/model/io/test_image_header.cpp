// Image sizes from file headers (io/image_header.h): PNG, JPEG and TIFF as OpenCV writes them,
// and a small file that declares a huge image is refused before it is decoded.
#include "simpli/model/io/image_header.h"

#include "support/expect_error.h"
#include "support/temp_dir.h"

#include "simpli/error.h"
#include "simpli/model/io/image.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace simpli::test {
namespace {

std::vector<uchar> encode(const std::string& ext, const cv::Mat& image) {
  std::vector<uchar> bytes;
  EXPECT_TRUE(cv::imencode(ext, image, bytes));
  return bytes;
}

void writeBytes(const std::filesystem::path& path, const std::vector<uchar>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// The CRC-32 of PNG chunks (ISO 3309), so that a patched IHDR is valid to libpng.
uint32_t crc32(const uchar* p, std::size_t n) {
  uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k)
      c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return c ^ 0xFFFFFFFFu;
}

void putBe32(uchar* p, uint32_t v) {
  p[0] = uchar(v >> 24);
  p[1] = uchar(v >> 16);
  p[2] = uchar(v >> 8);
  p[3] = uchar(v);
}

TEST(ImageHeader, SizesOfTheThreeFormats) {
  const cv::Mat rgb(37, 53, CV_8UC3, cv::Scalar(1, 2, 3));
  const cv::Mat rgba(7, 9, CV_32FC4, cv::Scalar::all(0.5));
  for (const auto& [ext, image, format] : {std::tuple{".png", rgb, "PNG"},
                                           {".jpg", rgb, "JPEG"},
                                           {".tiff", rgba, "TIFF"},
                                           {".tiff", rgb, "TIFF"}}) {
    const std::vector<uchar> bytes = encode(ext, image);
    const auto h = io::parseImageHeader(bytes.data(), bytes.size());
    ASSERT_TRUE(h) << ext;
    EXPECT_EQ(h->format, format);
    EXPECT_EQ(h->width, image.cols) << ext;
    EXPECT_EQ(h->height, image.rows) << ext;
  }
  // A large float TIFF (libtiff puts its IFD after the pixels, beyond the first MiB) from a file.
  TempDir dir;
  const cv::Mat big(600, 700, CV_32FC1, cv::Scalar(1));
  writeBytes(dir / "big.tiff", encode(".tiff", big));
  const auto h = io::readImageHeader((dir / "big.tiff").string());
  ASSERT_TRUE(h);
  EXPECT_EQ(h->width, 700);
  EXPECT_EQ(h->height, 600);
}

TEST(ImageHeader, TruncatedOrForeignBytesHaveNoHeader) {
  const std::vector<uchar> png = encode(".png", cv::Mat(4, 4, CV_8UC1, cv::Scalar(0)));
  for (std::size_t n = 0; n < 24; ++n)
    EXPECT_FALSE(io::parseImageHeader(png.data(), n)) << n;
  const std::string text = "not an image at all";
  EXPECT_FALSE(io::parseImageHeader(reinterpret_cast<const uchar*>(text.data()), text.size()));
  EXPECT_FALSE(io::parseImageHeader(nullptr, 100));
}

TEST(ImageHeader, HugeDeclaredSizeIsRefusedBeforeDecoding) {
  TempDir dir;
  // A 2 x 2 PNG whose IHDR (with a valid CRC) declares 10000 x 10000.
  std::vector<uchar> png = encode(".png", cv::Mat(2, 2, CV_8UC3, cv::Scalar(9, 9, 9)));
  putBe32(&png[16], 10000);
  putBe32(&png[20], 10000);
  putBe32(&png[29], crc32(&png[12], 17));
  writeBytes(dir / "huge.png", png);
  expectError([&] { io::readImage((dir / "huge.png").string()); },
              {"huge.png", "PNG header declares 10000 x 10000", "limit of 67108864"});
  // The same for a JPEG frame header (SOF0: height at +5, width at +7 from the marker).
  std::vector<uchar> jpg = encode(".jpg", cv::Mat(8, 8, CV_8UC3, cv::Scalar(9, 9, 9)));
  for (std::size_t p = 2; p + 9 < jpg.size(); ++p)
    if (jpg[p] == 0xFF && jpg[p + 1] == 0xC0) {
      jpg[p + 5] = jpg[p + 7] = 0xFF;
      jpg[p + 6] = jpg[p + 8] = 0xF0;
      break;
    }
  writeBytes(dir / "huge.jpg", jpg);
  expectError([&] { io::readImage((dir / "huge.jpg").string()); },
              {"huge.jpg", "JPEG header declares 65520 x 65520", "limit of"});
  expectError([&] { io::checkImageHeader((dir / "huge.jpg").string(), "layer", 8, 8); },
              {"layer", "huge.jpg", "65520 x 65520"});
  // Within the limit, a wrong size is named too.
  writeBytes(dir / "small.png", encode(".png", cv::Mat(3, 5, CV_8UC1, cv::Scalar(0))));
  expectError([&] { io::checkImageHeader((dir / "small.png").string(), "layer", 4, 4); },
              {"small.png", "declares 5 x 3 (W x H), expected 4 x 4"});
  EXPECT_NO_THROW(io::checkImageHeader((dir / "small.png").string(), "layer", 5, 3));
}

} // namespace
} // namespace simpli::test

// Mutation test of the image reader (io::readImage; support/mutator.h): every mutant of small
// PNG, JPEG and TIFF files is read to an image with values in [-1, 1] or rejected with a
// simpli::Error.
#include "support/mutator.h"
#include "support/temp_dir.h"

#include "simpli/model/io/image.h"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdint>

using namespace simpli;

namespace {

std::string encode(const char* ext, const cv::Mat& image, const std::vector<int>& params = {}) {
  std::vector<unsigned char> bytes;
  EXPECT_TRUE(cv::imencode(ext, image, bytes, params)) << ext;
  return std::string(bytes.begin(), bytes.end());
}

// A baseline TIFF as many tools write it (the directory first, then one uncompressed strip),
// unlike libtiff, which writes the directory last.
std::string directoryFirstTiff(int width, int height) {
  std::string b = "II";
  auto u16 = [&](uint32_t v) {
    b.push_back(static_cast<char>(v & 0xff));
    b.push_back(static_cast<char>(v >> 8 & 0xff));
  };
  auto u32 = [&](uint32_t v) {
    for (int k = 0; k < 4; ++k)
      b.push_back(static_cast<char>(v >> (8 * k) & 0xff));
  };
  u16(42);
  u32(8);
  const uint32_t entries = 10, bitsAt = 8 + 2 + 12 * entries + 4, dataAt = bitsAt + 6;
  u16(entries);
  auto entry = [&](uint32_t tag, uint32_t type, uint32_t count, uint32_t value) {
    u16(tag);
    u16(type);
    u32(count);
    if (type == 3 && count == 1) {
      u16(value);
      u16(0);
    } else {
      u32(value);
    }
  };
  entry(256, 3, 1, uint32_t(width));
  entry(257, 3, 1, uint32_t(height));
  entry(258, 3, 3, bitsAt);           // BitsPerSample 8, 8, 8
  entry(259, 3, 1, 1);                // no compression
  entry(262, 3, 1, 2);                // RGB
  entry(273, 4, 1, dataAt);           // StripOffsets
  entry(277, 3, 1, 3);                // SamplesPerPixel
  entry(278, 3, 1, uint32_t(height)); // RowsPerStrip
  entry(279, 4, 1, uint32_t(width * height * 3));
  entry(284, 3, 1, 1); // contiguous
  u32(0);
  u16(8);
  u16(8);
  u16(8);
  for (int k = 0; k < width * height * 3; ++k)
    b.push_back(static_cast<char>(k * 7));
  return b;
}

std::vector<std::string> imageCorpus() {
  cv::Mat colour(16, 24, CV_8UC3), grey16(16, 24, CV_16UC1), rgba(16, 24, CV_8UC4);
  cv::randu(colour, 0, 255);
  cv::randu(grey16, 0, 65535);
  cv::randu(rgba, 0, 255);
  return {encode(".png", colour),
          encode(".png", grey16),
          encode(".png", rgba),
          encode(".jpg", colour),
          encode(".jpg", colour, {cv::IMWRITE_JPEG_PROGRESSIVE, 1}),
          encode(".jpg", grey16 / 256),
          encode(".tiff", colour),
          directoryFirstTiff(24, 16)};
}

} // namespace

TEST(ImageMutants, ReadOrNamedError) {
  // OpenCV's own warnings about the broken files would only clutter the log.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  test::TempDir dir;
  const std::vector<std::string> corpus = imageCorpus();
  const std::string path = dir.str("mutant");
  for (const std::string& file : corpus) {
    test::writeText(path, file);
    EXPECT_EQ(io::readImage(path).width, 24);
  }
  const test::MutationCounts counts = test::runMutants(
      "image", 4, 2400, test::MutantKind::Binary, corpus, [&](const std::string& mutant) {
        test::writeText(path, mutant);
        const io::Image image = io::readImage(path);
        ASSERT_EQ(image.data.size(), size_t(3) * image.width * image.height);
        for (float v : image.data)
          ASSERT_TRUE(v >= -1.0f && v <= 1.0f) << v;
      });
  EXPECT_GT(counts.rejected, 600);
  EXPECT_GT(counts.parsed, 100);
}

// The cut files every format can become, named as truncated before a decoder sees them.
TEST(ImageMutants, TruncatedFilesAreNamed) {
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  test::TempDir dir;
  const std::string path = dir.str("cut");
  const std::vector<std::string> corpus = imageCorpus();
  for (size_t k = 0; k < corpus.size(); ++k) {
    const std::string& file = corpus[k];
    for (const size_t keep : {file.size() / 3, file.size() * 2 / 3, file.size() - 1}) {
      test::writeText(path, file.substr(0, keep));
      try {
        io::readImage(path);
        ADD_FAILURE() << "no error for a file cut to " << keep << " of " << file.size();
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos)
            << e.what() << " (corpus file " << k << ", cut to " << keep << ")";
      }
    }
  }
}

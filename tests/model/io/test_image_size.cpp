// "WIDTHxHEIGHT" (io/image_size.h): what every --size option and config size field accepts, and
// the named error for each way it can be wrong.
#include "simpli/model/io/image_size.h"

#include "support/expect_error.h"

#include <gtest/gtest.h>

namespace simpli::test {
namespace {

TEST(ImageSize, ParsesWidthThenHeight) {
  const io::ImageSize s = io::parseImageSize("512x384", "--size");
  EXPECT_EQ(s.width, 512);
  EXPECT_EQ(s.height, 384);
  const io::ImageSize t = io::parseImageSize(" 48 X 32 ", "--size");
  EXPECT_EQ(t.width, 48);
  EXPECT_EQ(t.height, 32);
}

TEST(ImageSize, AcceptsTheLimitsThemselves) {
  const io::ImageSizeLimits limits{16, 8192, 16};
  const io::ImageSize low = io::parseImageSize("16x16", "--size", limits);
  EXPECT_EQ(low.width, 16);
  const io::ImageSize high = io::parseImageSize("8192x16", "--size", limits);
  EXPECT_EQ(high.width, 8192);
  EXPECT_EQ(high.height, 16);
}

TEST(ImageSize, NamesTextThatIsNotASize) {
  for (const char* text :
       {"", "big", "512", "512x", "x384", "512x384x3", "512*384", "5.5x4", "0x10x", "512 384"})
    expectError([&] { io::parseImageSize(text, "--size"); },
                {"--size '" + std::string(text) + "'", "expected WIDTHxHEIGHT"});
}

TEST(ImageSize, NamesEachSideOutsideItsLimits) {
  const io::ImageSizeLimits limits{16, 8192, 1};
  for (const char* text : {"8x64", "64x8", "0x64", "-16x64", "64x-16", "8193x64", "64x8193",
                           "99999999999999999999x64", "-99999999999999999999x64"})
    expectError([&] { io::parseImageSize(text, "--size", limits); },
                {"--size '" + std::string(text) + "'", "width and height must be in 16..8192"});
}

TEST(ImageSize, NamesSidesThatAreNotMultiples) {
  const io::ImageSizeLimits limits{16, 16384, 16};
  for (const char* text : {"48x30", "50x32", "24x24"})
    expectError([&] { io::parseImageSize(text, "synthetic.size", limits); },
                {"synthetic.size '" + std::string(text) + "'",
                 "width and height must be multiples of 16 in 16..16384"});
  EXPECT_EQ(io::parseImageSize("48x32", "synthetic.size", limits).height, 32);
}

TEST(ImageSize, DefaultLimitsAreOneTo16384) {
  EXPECT_EQ(io::parseImageSize("1x16384", "--size").height, 16384);
  expectError([&] { io::parseImageSize("16385x1", "--size"); },
              {"width and height must be in 1..16384"});
}

} // namespace
} // namespace simpli::test

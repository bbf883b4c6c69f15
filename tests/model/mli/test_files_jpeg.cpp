// The reference JPEG MLI form (spec §10.2): layout, meta.json, 8-bit encodings,
// JPEG parameters, round-trip accuracy.
#include <cmath>
#include <fstream>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "mli_test_util.h"
#include "simpli/model/mli/files.h"

namespace simpli::test {
namespace {

// Fills 8x8 (grey) or 16x16 (4:2:0 colour MCU) blocks with constants: JPEG then keeps only DC
// coefficients, which quality 75's DC quantiser (8 = the 8x DC gain) and quality 100 store
// exactly for grey values, so the decoded 8-bit codes are the encoder's codes.
float blockValue(int i, int j, const std::vector<float>& values, int block, int W) {
  const int blocksPerRow = W / block;
  return values[static_cast<std::size_t>((i / block) * blocksPerRow + j / block) % values.size()];
}

struct JpegInfo {
  std::vector<std::pair<int, int>> sampling; // (h, v) per component
  std::vector<std::vector<int>> quant;       // tables in file (zigzag) order
};

// Minimal marker walk: DQT (8-bit tables) and SOF0/SOF2 component sampling factors.
JpegInfo parseJpeg(const fs::path& file) {
  const std::string s = readText(file);
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s.at(i)); };
  JpegInfo info;
  std::size_t i = 2; // after SOI
  while (i + 4 <= s.size() && byte(i) == 0xFF) {
    const int marker = byte(i + 1);
    const std::size_t len = (byte(i + 2) << 8) | byte(i + 3);
    const std::size_t body = i + 4, end = i + 2 + len;
    if (marker == 0xDB) {
      for (std::size_t p = body; p < end; p += 65) {
        EXPECT_EQ(byte(p) >> 4, 0) << "8-bit quantisers expected";
        std::vector<int> table;
        for (int e = 0; e < 64; ++e)
          table.push_back(byte(p + 1 + e));
        info.quant.push_back(table);
      }
    } else if (marker == 0xC0 || marker == 0xC2) {
      const int n = byte(body + 5);
      for (int c = 0; c < n; ++c) {
        const int hv = byte(body + 6 + 3 * c + 1);
        info.sampling.emplace_back(hv >> 4, hv & 15);
      }
    } else if (marker == 0xDA) {
      break; // entropy-coded data follows
    }
    i = end;
  }
  return info;
}

TEST(MLIJpeg, TwoLayersGiveExactlyTheReferenceFilesAndMetaKeys) {
  TempDir dir;
  const mli::MLI mli = randomMLI(2, 8, 12, 31);
  const auto path = dir / "scene";
  mli::writeMLI(path.string(), mli, mli::MLIFormat::Jpeg);
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"scene"});
  EXPECT_EQ(listDir(path),
            (std::vector<std::string>{"layer_00.jpg", "layer_01.jpg", "layer_alpha_00.jpg",
                                      "layer_alpha_01.jpg", "layer_depth_00.jpg",
                                      "layer_depth_01.jpg", "meta.json"}));
  EXPECT_EQ(mli::detectMLIFormat(path.string()), mli::MLIFormat::Jpeg);

  const auto meta = nlohmann::json::parse(readText(path / "meta.json"));
  std::set<std::string> keys;
  for (auto it = meta.begin(); it != meta.end(); ++it)
    keys.insert(it.key());
  // The reference's keys, plus simpli's mark (which lets a later write replace the folder).
  EXPECT_EQ(keys, (std::set<std::string>{"layer_depth_00", "layer_depth_01", "frame_size",
                                         "extrinsic_re", "intrinsics_re", "written_by"}));
  EXPECT_TRUE(meta["frame_size"][0].is_number_integer());
  EXPECT_EQ(meta["frame_size"], nlohmann::json({8, 12})) << "[H, W]";
  const scene::Camera& c = mli.camera;
  ASSERT_EQ(meta["extrinsic_re"].size(), 12u);
  for (int r = 0; r < 3; ++r) {
    for (int col = 0; col < 3; ++col)
      EXPECT_EQ(meta["extrinsic_re"][4 * r + col].get<double>(), c.R(r, col));
    EXPECT_EQ(meta["extrinsic_re"][4 * r + 3].get<double>(), c.t(r));
  }
  EXPECT_EQ(meta["intrinsics_re"], nlohmann::json({c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0, 0, 1}));
  for (int k = 0; k < 2; ++k) {
    const auto& d = mli.layers[static_cast<std::size_t>(k)].depth;
    const auto& range = meta[k == 0 ? "layer_depth_00" : "layer_depth_01"];
    ASSERT_EQ(range.size(), 2u);
    EXPECT_EQ(range[0].get<double>(), *std::min_element(d.begin(), d.end()));
    EXPECT_EQ(range[1].get<double>(), *std::max_element(d.begin(), d.end()));
  }
}

TEST(MLIJpeg, ImagesHaveTheReferenceJpegParameters) {
  TempDir dir;
  mli::writeMLI((dir / "s").string(), randomMLI(1, 32, 32, 32), mli::MLIFormat::Jpeg);
  for (const char* name : {"layer_00.jpg", "layer_alpha_00.jpg"}) {
    const JpegInfo info = parseJpeg(dir / "s" / name);
    ASSERT_EQ(info.sampling.size(), 3u) << name;
    EXPECT_EQ(info.sampling[0], std::make_pair(2, 2)) << name << ": 4:2:0 luma";
    EXPECT_EQ(info.sampling[1], std::make_pair(1, 1)) << name;
    EXPECT_EQ(info.sampling[2], std::make_pair(1, 1)) << name;
    ASSERT_GE(info.quant.size(), 1u);
    // libjpeg/PIL quality 75: standard luminance table halved, zigzag order 16 11 12 14 -> ...
    EXPECT_EQ(std::vector<int>(info.quant[0].begin(), info.quant[0].begin() + 4),
              (std::vector<int>{8, 6, 6, 7}))
        << name;
  }
  const JpegInfo depth = parseJpeg(dir / "s" / "layer_depth_00.jpg");
  ASSERT_EQ(depth.sampling.size(), 1u) << "depth is single channel";
  ASSERT_EQ(depth.quant.size(), 1u);
  EXPECT_EQ(depth.quant[0], std::vector<int>(64, 1)) << "quality 100";
  EXPECT_EQ(
      cv::imread((dir / "s" / "layer_depth_00.jpg").string(), cv::IMREAD_UNCHANGED).channels(), 1);
}

TEST(MLIJpeg, ColourAndAlphaAreTruncatedNotRounded) {
  const int H = 32, W = 32;
  mli::MLI mli = mli::MLI::allocate(generalCamera(W, H), 1);
  // Grey levels x.9/255: truncation gives x, rounding would give x + 1.
  const std::vector<float> grey = {100.9f / 255, 17.9f / 255, 254.9f / 255, 1.0f};
  const std::vector<float> alpha = {0.9f / 255, 200.9f / 255, 1.0f, 63.5f / 255};
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      float* rgba = &mli.layers[0].rgba[4 * static_cast<std::size_t>(i * W + j)];
      rgba[0] = rgba[1] = rgba[2] = blockValue(i, j, grey, 16, W);
      rgba[3] = blockValue(i, j, alpha, 16, W);
    }
  TempDir dir;
  mli::writeMLI((dir / "s").string(), mli, mli::MLIFormat::Jpeg);
  const mli::MLI back = mli::readMLI((dir / "s").string());
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      const float* rgba = &back.layers[0].rgba[4 * static_cast<std::size_t>(i * W + j)];
      const float g = std::floor(255 * blockValue(i, j, grey, 16, W)) / 255;
      const float a = std::floor(255 * blockValue(i, j, alpha, 16, W)) / 255;
      for (int ch = 0; ch < 3; ++ch)
        ASSERT_FLOAT_EQ(rgba[ch], g) << i << "," << j;
      ASSERT_FLOAT_EQ(rgba[3], a) << i << "," << j;
    }
}

TEST(MLIJpeg, ChannelOrderIsRGB) {
  const int H = 16, W = 48;
  mli::MLI mli = mli::MLI::allocate(generalCamera(W, H), 1);
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j) {
      float* rgba = &mli.layers[0].rgba[4 * static_cast<std::size_t>(i * W + j)];
      rgba[j / 16] = 1.0f; // pure red, green, blue blocks
      rgba[3] = 1.0f;
    }
  TempDir dir;
  mli::writeMLI((dir / "s").string(), mli, mli::MLIFormat::Jpeg);
  const mli::MLI back = mli::readMLI((dir / "s").string());
  for (int b = 0; b < 3; ++b) {
    const float* rgba = &back.layers[0].rgba[4 * static_cast<std::size_t>(8 * W + 16 * b + 8)];
    for (int ch = 0; ch < 3; ++ch)
      if (ch == b)
        EXPECT_GT(rgba[ch], 0.9f) << "block " << b;
      else
        EXPECT_LT(rgba[ch], 0.1f) << "block " << b << " channel " << ch;
  }
  // And in the file itself, read with OpenCV (BGR): the first block is red.
  const cv::Mat file = cv::imread((dir / "s" / "layer_00.jpg").string(), cv::IMREAD_COLOR);
  EXPECT_GT(file.at<cv::Vec3b>(8, 8)[2], 230);
  EXPECT_LT(file.at<cv::Vec3b>(8, 8)[0], 25);
}

TEST(MLIJpeg, DepthCodesAndBothDecodings) {
  const int H = 16, W = 16;
  mli::MLI mli = mli::MLI::allocate(generalCamera(W, H), 1);
  // lo = 2, hi = 4: codes floor(256 (D - 2)/2) clipped: 2 -> 0, 3 -> 128, 4 -> 255 (not 256),
  // 2.5 -> 64.
  const std::vector<float> depths = {2.0f, 3.0f, 4.0f, 2.5f};
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < W; ++j)
      mli.layers[0].depth[static_cast<std::size_t>(i * W + j)] = blockValue(i, j, depths, 8, W);
  TempDir dir;
  const auto path = dir / "s";
  mli::writeMLI(path.string(), mli, mli::MLIFormat::Jpeg);

  const cv::Mat codes = cv::imread((path / "layer_depth_00.jpg").string(), cv::IMREAD_GRAYSCALE);
  const int expected[4] = {0, 128, 255, 64};
  for (int b = 0; b < 4; ++b)
    EXPECT_EQ(codes.at<unsigned char>(8 * (b / 2) + 3, 8 * (b % 2) + 3), expected[b]);

  const mli::MLI viewer = mli::readMLI(path.string());
  mli::MLIReadOptions centre;
  centre.depthDecoding = mli::MLIDepthDecoding::BinCentre;
  const mli::MLI binCentre = mli::readMLI(path.string(), centre);
  for (int b = 0; b < 4; ++b) {
    const std::size_t p = static_cast<std::size_t>((8 * (b / 2) + 3) * W + 8 * (b % 2) + 3);
    EXPECT_FLOAT_EQ(viewer.layers[0].depth[p], static_cast<float>(2.0 + expected[b] * 2.0 / 255));
    EXPECT_FLOAT_EQ(binCentre.layers[0].depth[p],
                    static_cast<float>(2.0 + (expected[b] + 0.5) * 2.0 / 256));
  }
  EXPECT_EQ(viewer.layers[0].depth[0], 2.0f) << "viewer decoding reaches lo exactly";
}

TEST(MLIJpeg, ConstantDepthLayerNeedsNoRange) {
  mli::MLI mli = smoothMLI(2, 16, 16);
  for (float& d : mli.layers[1].depth)
    d = 7.25f; // hi == lo
  TempDir dir;
  mli::writeMLI((dir / "s").string(), mli, mli::MLIFormat::Jpeg);
  const auto meta = nlohmann::json::parse(readText(dir / "s" / "meta.json"));
  EXPECT_EQ(meta["layer_depth_01"], nlohmann::json({7.25, 7.25}));
  for (const mli::MLIDepthDecoding mode :
       {mli::MLIDepthDecoding::Viewer, mli::MLIDepthDecoding::BinCentre}) {
    mli::MLIReadOptions options;
    options.depthDecoding = mode;
    const mli::MLI back = mli::readMLI((dir / "s").string(), options);
    for (float d : back.layers[1].depth)
      ASSERT_EQ(d, 7.25f);
  }
}

TEST(MLIJpeg, RoundTripIsWithinEightBitQuantisation) {
  const int L = 2, H = 48, W = 64;
  const mli::MLI mli = smoothMLI(L, H, W);
  TempDir dir;
  mli::writeMLI((dir / "s").string(), mli, mli::MLIFormat::Jpeg);
  const mli::MLI back = mli::readMLI((dir / "s").string());
  ASSERT_EQ(back.numLayers(), L);
  EXPECT_NEAR((back.camera.R - mli.camera.R).norm(), 0.0, 1e-12);
  EXPECT_NEAR((back.camera.t - mli.camera.t).norm(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(back.camera.cy, mli.camera.cy);
  for (int k = 0; k < L; ++k) {
    const mli::MLILayer &a = mli.layers[static_cast<std::size_t>(k)],
                        &b = back.layers[static_cast<std::size_t>(k)];
    double colourErr = 0, alphaErr = 0, depthErr = 0, depthMax = 0;
    for (std::size_t p = 0; p < a.depth.size(); ++p) {
      for (int ch = 0; ch < 3; ++ch)
        colourErr += std::abs(a.rgba[4 * p + ch] - b.rgba[4 * p + ch]);
      alphaErr += std::abs(a.rgba[4 * p + 3] - b.rgba[4 * p + 3]);
      const double e = std::abs(a.depth[p] - b.depth[p]);
      depthErr += e;
      depthMax = std::max(depthMax, e);
    }
    const double n = static_cast<double>(a.depth.size());
    const auto [lo, hi] = std::minmax_element(a.depth.begin(), a.depth.end());
    const double step = (*hi - *lo) / 255.0;
    EXPECT_LT(colourErr / (3 * n), 3.0 / 255) << "layer " << k;
    EXPECT_LT(alphaErr / n, 3.0 / 255) << "layer " << k;
    EXPECT_LT(depthErr / n, step) << "layer " << k;
    EXPECT_LT(depthMax, 2 * step) << "layer " << k << ": one step plus JPEG error";
    // The viewer decoding maps codes 0..255 onto [lo, hi].
    const auto [blo, bhi] = std::minmax_element(b.depth.begin(), b.depth.end());
    EXPECT_GE(*blo, *lo);
    EXPECT_LE(*bhi, *hi);
    EXPECT_NEAR(*blo, *lo, step);
    EXPECT_NEAR(*bhi, *hi, step);
  }
}

TEST(MLIJpeg, BackLayerAlphaMayBeForcedOrNot) {
  // The reference render script forces layer 00's alpha to 1, its colab does not: both read.
  for (const bool forced : {true, false}) {
    mli::MLI mli = smoothMLI(2, 16, 16);
    if (forced)
      for (std::size_t e = 3; e < mli.layers[0].rgba.size(); e += 4)
        mli.layers[0].rgba[e] = 1.0f;
    TempDir dir;
    mli::writeMLI((dir / "s").string(), mli, mli::MLIFormat::Jpeg);
    const mli::MLI back = mli::readMLI((dir / "s").string());
    float minAlpha = 1.0f;
    for (std::size_t e = 3; e < back.layers[0].rgba.size(); e += 4)
      minAlpha = std::min(minAlpha, back.layers[0].rgba[e]);
    if (forced)
      EXPECT_EQ(minAlpha, 1.0f);
    else
      EXPECT_LT(minAlpha, 0.5f);
  }
}

} // namespace
} // namespace simpli::test

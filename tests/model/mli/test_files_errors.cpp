// Bad MLI folders and failed writes: every error names the file and the field or value, and a
// failed write leaves nothing behind.
#include <cmath>
#include <cstdio>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "mli_test_util.h"
#include "simpli/model/mli/files.h"
#include "support/captured_warnings.h"

namespace simpli::test {
namespace {

using json = nlohmann::json;

// A valid 3-layer MLI folder to break, in either form.
class MLIReadErrors : public ::testing::Test {
protected:
  void SetUp() override {
    mli::writeMLI(scene().string(), smoothMLI(3, 16, 24), mli::MLIFormat::Jpeg);
    original_ = json::parse(readText(scene() / "meta.json"));
  }

  fs::path scene() const { return dir_ / "scene"; }
  std::string metaFile() const { return (scene() / "meta.json").string(); }
  /// The valid meta.json as written (each case breaks a fresh copy).
  json meta() const { return original_; }
  void setMeta(const json& m) const { writeText(scene() / "meta.json", m.dump()); }
  void expectReadError(const std::vector<std::string>& parts) const {
    expectError([&] { mli::readMLI(scene().string()); }, parts);
  }

  TempDir dir_;
  json original_;
};

TEST_F(MLIReadErrors, MetaIsNotJson) {
  writeText(scene() / "meta.json", "{\"frame_size\": [16, 24],");
  expectReadError({metaFile(), "not valid JSON"});
  writeText(scene() / "meta.json", "[16, 24]");
  expectReadError({metaFile(), "expected a JSON object"});
}

TEST_F(MLIReadErrors, MetaMissing) {
  fs::remove(scene() / "meta.json");
  expectReadError({metaFile(), "missing"});
  expectError([&] { mli::readMLI((dir_ / "nowhere").string()); }, {"nowhere", "does not exist"});
  writeText(dir_ / "file", "x");
  expectError([&] { mli::readMLI((dir_ / "file").string()); }, {"file", "is not a folder"});
}

TEST_F(MLIReadErrors, MissingKeys) {
  for (const char* key : {"frame_size", "extrinsic_re", "intrinsics_re"}) {
    json m = meta();
    m.erase(key);
    setMeta(m);
    expectReadError({metaFile(), "missing key", key});
  }
}

TEST_F(MLIReadErrors, WrongArrayLengths) {
  json m = meta();
  m["extrinsic_re"].erase(11);
  setMeta(m);
  expectReadError({metaFile(), "\"extrinsic_re\" has 11 values, expected 12"});
  m = meta();
  m["intrinsics_re"].push_back(0);
  setMeta(m);
  expectReadError({metaFile(), "\"intrinsics_re\" has 10 values, expected 9"});
  m = meta();
  m["layer_depth_01"] = {1.0};
  setMeta(m);
  expectReadError({metaFile(), "\"layer_depth_01\" has 1 values, expected 2"});
  m = meta();
  m["frame_size"] = {16, 24, 3};
  setMeta(m);
  expectReadError({metaFile(), "frame_size", "expected [H, W]"});
}

TEST_F(MLIReadErrors, NonNumericValues) {
  json m = meta();
  m["intrinsics_re"][2] = "abc";
  setMeta(m);
  expectReadError({metaFile(), "\"intrinsics_re\"[2] is \"abc\"", "expected a number"});
  m = meta();
  m["extrinsic_re"] = "identity";
  setMeta(m);
  expectReadError({metaFile(), "\"extrinsic_re\" is \"identity\"", "array of 12 numbers"});
  m = meta();
  m["layer_depth_02"][1] = nullptr;
  setMeta(m);
  expectReadError({metaFile(), "\"layer_depth_02\"[1] is null"});
  m = meta();
  m["frame_size"][1] = 24.5;
  setMeta(m);
  expectReadError({metaFile(), "frame_size\"[1] (W) = 24.5", "integer"});
  m = meta();
  m["frame_size"][0] = -16;
  setMeta(m);
  expectReadError({metaFile(), "frame_size\"[0] (H) = -16"});
}

TEST_F(MLIReadErrors, DepthRanges) {
  json m = meta();
  m["layer_depth_01"] = {5.0, 3.0};
  setMeta(m);
  expectReadError({metaFile(), "\"layer_depth_01\" = [5, 3]", "lo > hi"});
  m["layer_depth_01"] = {0.0, 3.0};
  setMeta(m);
  expectReadError({metaFile(), "\"layer_depth_01\" = [0, 3]", "lo must be > 0"});
}

TEST_F(MLIReadErrors, LayerKeys) {
  json m = meta();
  m.erase("layer_depth_01");
  setMeta(m);
  expectReadError({metaFile(), "missing key \"layer_depth_01\""});
  m = meta();
  m["layer_depth_3"] = {1.0, 2.0};
  setMeta(m);
  expectReadError({metaFile(), "\"layer_depth_3\" is not of the form layer_depth_XX"});
  m = meta();
  for (const char* k : {"layer_depth_00", "layer_depth_01", "layer_depth_02"})
    m.erase(k);
  setMeta(m);
  expectReadError({metaFile(), "no layer_depth_XX keys"});
}

TEST_F(MLIReadErrors, CameraThatIsNotAPinholeOrNotARotation) {
  json m = meta();
  m["intrinsics_re"][1] = 0.1; // skew
  setMeta(m);
  expectReadError({metaFile(), "\"intrinsics_re\"[1] = 0.1", "expected 0"});
  m = meta();
  m["intrinsics_re"][0] = -0.9;
  setMeta(m);
  expectReadError({metaFile(), "intrinsics_re", "focal", "> 0"});
  m = meta();
  for (int e = 0; e < 12; ++e)
    m["extrinsic_re"][e] = m["extrinsic_re"][e].get<double>() * 2;
  setMeta(m);
  expectReadError({metaFile(), "extrinsic_re", "not a rotation"});
}

TEST_F(MLIReadErrors, UnknownFormatTag) {
  json m = meta();
  m["format"] = "something-else";
  setMeta(m);
  expectReadError({metaFile(), "\"format\" is \"something-else\""});
  expectError([&] { mli::detectMLIFormat(scene().string()); }, {"something-else"});
}

TEST_F(MLIReadErrors, MissingLayerFile) {
  fs::remove(scene() / "layer_alpha_01.jpg");
  expectReadError({(scene() / "layer_alpha_01.jpg").string(), "missing layer file"});
  fs::remove(scene() / "layer_02.jpg");
  expectError([&] { mli::readMLI(scene().string()); }, {"layer_alpha_01.jpg"}); // first in order
}

TEST_F(MLIReadErrors, UndecodableLayerFile) {
  writeText(scene() / "layer_depth_02.jpg", "definitely not a JPEG");
  expectReadError({(scene() / "layer_depth_02.jpg").string(), "not a readable image"});
}

// A cut layer file is a named error before libjpeg decodes it (which would only warn and
// render the missing rows grey); the same for the lossless form's TIFFs.
TEST_F(MLIReadErrors, TruncatedLayerFiles) {
  const fs::path layer = scene() / "layer_alpha_01.jpg";
  const std::string bytes = readText(layer);
  for (const size_t keep : {bytes.size() / 2, bytes.size() - 2}) {
    writeText(layer, bytes.substr(0, keep));
    expectReadError({layer.string(), "truncated", "before the end-of-image marker"});
  }
  TempDir dir;
  const fs::path lossless = dir / "lossless";
  mli::writeMLI(lossless.string(), smoothMLI(2, 16, 24), mli::MLIFormat::Lossless);
  const fs::path rgba = lossless / "layer_rgba_01.tiff";
  const std::string tiff = readText(rgba);
  writeText(rgba, tiff.substr(0, tiff.size() / 2));
  expectError([&] { mli::readMLI(lossless.string()); }, {rgba.string(), "truncated", "TIFF"});
}

// A focal length no pinhole camera has (fx = 1e-30 rendered black) is an error; a valid but
// extreme one is read with a warning naming the file, the field and the value.
TEST_F(MLIReadErrors, DegenerateCamera) {
  json m = meta();
  m["intrinsics_re"][0] = 1e-30;
  setMeta(m);
  expectReadError({metaFile(), "focal length fx = 1e-30", "outside [0.001, 1000]"});
  m = meta();
  m["intrinsics_re"][4] = 1e300;
  setMeta(m);
  expectReadError({metaFile(), "focal length fy = 1e+300"});
  {
    m = meta();
    m["intrinsics_re"][0] = 0.05;
    setMeta(m);
    CapturedWarnings warnings;
    EXPECT_EQ(mli::readMLI(scene().string()).numLayers(), 3);
    EXPECT_EQ(warnings.count({"meta.json", "\"intrinsics_re\" fx = 0.05", "result will be poor"}),
              1)
        << warnings.text();
  }
  {
    setMeta(meta());
    CapturedWarnings warnings;
    mli::readMLI(scene().string());
    EXPECT_TRUE(warnings.messages().empty()) << warnings.text();
  }
}

TEST_F(MLIReadErrors, LayerImagesOfMismatchedSizes) {
  cv::imwrite((scene() / "layer_depth_01.jpg").string(), cv::Mat(16, 20, CV_8UC1, cv::Scalar(9)));
  expectReadError({(scene() / "layer_depth_01.jpg").string(), "image is 20 x 16 (W x H)",
                   "frame_size is [H, W] = [16, 24]"});
}

TEST_F(MLIReadErrors, FrameSizeNotMatchingTheImages) {
  json m = meta();
  m["frame_size"] = {24, 16}; // transposed
  setMeta(m);
  expectReadError(
      {(scene() / "layer_00.jpg").string(), "image is 24 x 16", "frame_size is [H, W] = [24, 16]"});
}

// Sizes and counts are checked against named limits before anything is allocated: a corrupt
// frame_size or thousands of layer keys are refused, never turned into gigabytes.
TEST_F(MLIReadErrors, SizesAboveTheLimits) {
  for (const int side : {20000, 65535}) {
    json m = meta();
    m["frame_size"] = {side, side};
    setMeta(m);
    expectReadError({metaFile(), "\"frame_size\" [" + std::to_string(side), "kMaxMLITexels"});
  }
  json m = meta();
  for (int k = 0; k < 20000; ++k) {
    char key[32];
    std::snprintf(key, sizeof key, "layer_depth_%02d", k);
    m[key] = {1.0, 2.0};
  }
  setMeta(m);
  expectReadError({metaFile(), "key \"layer_depth_", "limit of 64 layers", "kMaxMLILayers"});
  // Within the limits but with a layer file missing: refused before the layers are allocated.
  m = meta();
  m["frame_size"] = {4096, 4096};
  setMeta(m);
  expectReadError({(scene() / "layer_00.jpg").string(),
                   "image is 24 x 16 (W x H) by its JPEG "
                   "header",
                   "frame_size is [H, W] = [4096, 4096]"});
}

TEST(MLILosslessReadErrors, BadFilesAndMeta) {
  TempDir dir;
  const auto scene = dir / "scene";
  mli::writeMLI(scene.string(), randomMLI(2, 4, 5, 41), mli::MLIFormat::Lossless);

  json m = json::parse(readText(scene / "meta.json"));
  m["num_layers"] = 3;
  writeText(scene / "meta.json", m.dump());
  expectError([&] { mli::readMLI(scene.string()); },
              {"meta.json", "\"num_layers\" = 3 but there are 2 layer_depth_XX keys"});
  m.erase("num_layers");
  writeText(scene / "meta.json", m.dump());
  expectError([&] { mli::readMLI(scene.string()); }, {"meta.json", "missing key \"num_layers\""});
  m["num_layers"] = 2;
  writeText(scene / "meta.json", m.dump());
  EXPECT_NO_THROW(mli::readMLI(scene.string()));

  // An 8-bit image where a float one belongs.
  cv::imwrite((scene / "layer_rgba_01.tiff").string(), cv::Mat(4, 5, CV_8UC4, cv::Scalar::all(1)));
  expectError([&] { mli::readMLI(scene.string()); },
              {"layer_rgba_01.tiff", "expected a 32-bit float image with 4 channels", "CV_8UC4"});

  // Floats that break the MLI's contract are reported with the file.
  cv::Mat depth(4, 5, CV_32FC1, cv::Scalar(2.0f));
  depth.at<float>(3, 1) = std::numeric_limits<float>::quiet_NaN();
  cv::imwrite((scene / "layer_depth_00.tiff").string(), depth);
  expectError([&] { mli::readMLI(scene.string()); },
              {"layer_depth_00.tiff", "depth at (row 3, col 1) = nan"});
}

// -------------------------------------------------------------------------------------------
// Failed writes leave nothing behind.

TEST(MLIWriteErrors, NaNDepthWritesNothing) {
  TempDir dir;
  mli::MLI mli = randomMLI(2, 4, 5, 51);
  mli.layers[1].depth[7] = std::numeric_limits<float>::quiet_NaN();
  for (const mli::MLIFormat format : {mli::MLIFormat::Jpeg, mli::MLIFormat::Lossless}) {
    expectError([&] { mli::writeMLI((dir / "scene").string(), mli, format); },
                {"writeMLI", "scene", "layer 1", "depth at (row 1, col 2) = nan"});
    EXPECT_TRUE(listDir(dir.path()).empty()) << "no folder, no temporary";
  }
}

TEST(MLIWriteErrors, FailedWriteKeepsTheOldMLI) {
  TempDir dir;
  const auto path = (dir / "scene").string();
  const mli::MLI old = randomMLI(2, 4, 5, 52);
  mli::writeMLI(path, old, mli::MLIFormat::Lossless);
  mli::MLI bad = randomMLI(1, 4, 5, 53);
  bad.layers[0].rgba[2] = 1.5f;
  expectError([&] { mli::writeMLI(path, bad, mli::MLIFormat::Jpeg); },
              {"rgba B at (row 0, col 0) = 1.5"});
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"scene"});
  const mli::MLI back = mli::readMLI(path);
  EXPECT_EQ(back.layers[1].depth, old.layers[1].depth);
}

TEST(MLIWriteErrors, FailureWhileWritingFilesRemovesTheTemporaryFolder) {
  // A valid MLI that the JPEG encoder cannot store (libjpeg's limit is 65500 pixels a side):
  // the failure comes after the temporary folder was created, from inside the encoder.
  TempDir dir;
  const auto path = (dir / "scene").string();
  const mli::MLI old = randomMLI(1, 4, 5, 55);
  mli::writeMLI(path, old, mli::MLIFormat::Jpeg);
  mli::MLI wide = mli::MLI::allocate(generalCamera(70000, 2), 1);
  expectError([&] { mli::writeMLI(path, wide, mli::MLIFormat::Jpeg); },
              {"layer_00.jpg", "write failed"});
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"scene"}) << "temporary removed";
  EXPECT_EQ(mli::readMLI(path).width(), 5) << "old MLI untouched";
  expectError([&] { mli::writeMLI((dir / "new").string(), wide, mli::MLIFormat::Jpeg); },
              {"layer_00.jpg"});
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"scene"});
}

TEST(MLIWriteErrors, RefusesToReplaceWhatIsNotAnMLI) {
  TempDir dir;
  const mli::MLI mli = randomMLI(1, 4, 5, 54);
  fs::create_directories(dir / "photos");
  writeText(dir / "photos" / "IMG_0001.jpg", "precious");
  expectError([&] { mli::writeMLI((dir / "photos").string(), mli); },
              {"photos", "is not an MLI folder (no meta.json)", "refusing"});
  EXPECT_EQ(listDir(dir / "photos"), std::vector<std::string>{"IMG_0001.jpg"});
  EXPECT_EQ(readText(dir / "photos" / "IMG_0001.jpg"), "precious");

  writeText(dir / "plain_file", "keep me");
  expectError([&] { mli::writeMLI((dir / "plain_file").string(), mli); },
              {"plain_file", "is not a folder", "refusing"});
  EXPECT_EQ(readText(dir / "plain_file"), "keep me");

  expectError([&] { mli::writeMLI((dir / "missing" / "scene").string(), mli); },
              {"parent folder", "missing", "does not exist"});
  EXPECT_EQ(listDir(dir.path()), (std::vector<std::string>{"photos", "plain_file"}));

  // An empty folder is fine to fill.
  fs::create_directories(dir / "empty");
  EXPECT_NO_THROW(mli::writeMLI((dir / "empty").string(), mli));
  EXPECT_NO_THROW(mli::readMLI((dir / "empty").string()));
}

} // namespace
} // namespace simpli::test

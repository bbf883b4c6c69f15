// The lossless (32-bit float TIFF) MLI form: bit-exact round trip, layout, atomic replace.
#include <cstring>
#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mli_test_util.h"
#include "simpli/model/mli/files.h"
#include "support/mli_compare.h"

namespace simpli::test {
namespace {

TEST(MLILossless, RoundTripIsBitExact) {
  TempDir dir;
  mli::MLI mli = randomMLI(3, 5, 7, 21, 0.5f, 120.0f);
  // Awkward but valid floats: denormals, extremes, exact 0 and 1, values near 1.
  mli.layers[0].depth[0] = std::numeric_limits<float>::denorm_min();
  mli.layers[0].depth[1] = std::numeric_limits<float>::max();
  mli.layers[1].depth[2] = 1e-30f;
  mli.layers[2].rgba[0] = 0.0f;
  mli.layers[2].rgba[1] = 1.0f;
  mli.layers[2].rgba[2] = std::numeric_limits<float>::denorm_min();
  mli.layers[2].rgba[3] = 0.99999994f;
  const auto path = (dir / "scene").string();
  mli::writeMLI(path, mli, mli::MLIFormat::Lossless);
  EXPECT_EQ(mli::detectMLIFormat(path), mli::MLIFormat::Lossless);
  expectSameMLI(mli, mli::readMLI(path));
}

TEST(MLILossless, LayoutAndMeta) {
  TempDir dir;
  const mli::MLI mli = randomMLI(2, 4, 6, 22);
  mli::writeMLI((dir / "out").string(), mli, mli::MLIFormat::Lossless);
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"out"});
  EXPECT_EQ(listDir(dir / "out"),
            (std::vector<std::string>{"layer_depth_00.tiff", "layer_depth_01.tiff",
                                      "layer_rgba_00.tiff", "layer_rgba_01.tiff", "meta.json"}));
  const auto meta = nlohmann::json::parse(readText(dir / "out" / "meta.json"));
  EXPECT_EQ(meta.at("format"), "simpli-mli-float");
  EXPECT_EQ(meta.at("num_layers"), 2);
  EXPECT_EQ(meta.at("frame_size"), nlohmann::json({4, 6}));
  for (int k = 0; k < 2; ++k) {
    const auto& d = mli.layers[static_cast<std::size_t>(k)].depth;
    const auto range = meta.at(k == 0 ? "layer_depth_00" : "layer_depth_01");
    EXPECT_EQ(range[0].get<double>(), *std::min_element(d.begin(), d.end()));
    EXPECT_EQ(range[1].get<double>(), *std::max_element(d.begin(), d.end()));
  }
}

TEST(MLILossless, ReplacingAnExistingMLILeavesOnlyTheNewOne) {
  TempDir dir;
  const auto path = (dir / "scene").string();
  mli::writeMLI(path, randomMLI(3, 4, 4, 23), mli::MLIFormat::Lossless);
  const mli::MLI smaller = randomMLI(1, 3, 5, 24);
  mli::writeMLI(path + "/", smaller,
                mli::MLIFormat::Lossless); // trailing slash names the same folder
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"scene"}) << "no temporary left";
  EXPECT_EQ(listDir(dir / "scene"),
            (std::vector<std::string>{"layer_depth_00.tiff", "layer_rgba_00.tiff", "meta.json"}));
  expectSameMLI(smaller, mli::readMLI(path));
}

TEST(MLILossless, ConvertsBetweenForms) {
  TempDir dir;
  const mli::MLI mli = smoothMLI(2, 16, 16);
  mli::writeMLI((dir / "a").string(), mli, mli::MLIFormat::Jpeg);
  const mli::MLI fromJpeg = mli::readMLI((dir / "a").string());
  mli::writeMLI((dir / "a").string(), fromJpeg,
                mli::MLIFormat::Lossless); // JPEG folder -> lossless
  EXPECT_EQ(mli::detectMLIFormat((dir / "a").string()), mli::MLIFormat::Lossless);
  expectSameMLI(fromJpeg, mli::readMLI((dir / "a").string()));
}

} // namespace
} // namespace simpli::test

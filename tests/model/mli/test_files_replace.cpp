// The replace rule of writeMLI (mli/files.h): an existing folder is replaced only when it is an
// MLI that simpli wrote, holding nothing else; everything else is refused with an error naming
// the folder and the entry, and left exactly as it was.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mli_test_util.h"
#include "simpli/model/mli/files.h"
#include "support/mli_compare.h"

namespace simpli::test {
namespace {

using json = nlohmann::json;

// Every entry of `folder` (recursively) with its contents, to show that nothing changed.
std::vector<std::pair<std::string, std::string>> snapshot(const fs::path& folder) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(folder))
    out.emplace_back(fs::relative(e.path(), folder).string(),
                     e.is_regular_file() ? readText(e.path()) : std::string("<dir>"));
  std::sort(out.begin(), out.end());
  return out;
}

class MLIReplace : public ::testing::TestWithParam<mli::MLIFormat> {
protected:
  mli::MLIFormat format() const { return GetParam(); }
  fs::path folder() const { return dir_ / "scene"; }
  /// writeMLI into folder() must be refused with `parts` in the message and change nothing.
  void expectRefused(const std::vector<std::string>& parts) const {
    const auto before = snapshot(dir_.path());
    std::vector<std::string> all{"writeMLI: refusing to replace", folder().string()};
    all.insert(all.end(), parts.begin(), parts.end());
    expectError([&] { mli::writeMLI(folder().string(), randomMLI(1, 4, 4, 7), format()); }, all);
    EXPECT_EQ(snapshot(dir_.path()), before) << "the refused folder was changed";
  }

  TempDir dir_;
};

TEST_P(MLIReplace, WritesTheSimpliMarkAndReplacesItsOwnMLI) {
  mli::writeMLI(folder().string(), randomMLI(3, 4, 6, 1), format());
  EXPECT_EQ(json::parse(readText(folder() / "meta.json")).at("written_by"), "simpli");
  EXPECT_EQ(mli::mliReplaceRefusal(folder().string()), "");
  const mli::MLI smaller = randomMLI(1, 5, 3, 2);
  mli::writeMLI(folder().string(), smaller, format());
  EXPECT_EQ(listDir(dir_.path()), std::vector<std::string>{"scene"}) << "no temporary left";
  EXPECT_EQ(listDir(folder()).size(), format() == mli::MLIFormat::Jpeg ? 4u : 3u);
  if (format() == mli::MLIFormat::Lossless)
    expectSameMLI(smaller, mli::readMLI(folder().string()));
}

TEST_P(MLIReplace, RefusesAnyJsonCalledMetaJson) {
  // The probe: a folder of the user's with an unrelated meta.json was emptied.
  fs::create_directories(folder() / "photos");
  writeText(folder() / "photos" / "IMG_0001.jpg", "precious");
  writeText(folder() / "meta.json", R"({"p": 1})");
  writeText(folder() / "thesis.tex", "\\documentclass{article}");
  expectRefused({"not a valid MLI", "meta.json", "missing key"});
}

TEST_P(MLIReplace, RefusesAnMLIThatSimpliDidNotWrite) {
  // A valid MLI without the mark (the reference's, or one edited by hand).
  mli::writeMLI(folder().string(), randomMLI(2, 4, 4, 3), format());
  json meta = json::parse(readText(folder() / "meta.json"));
  meta.erase("written_by");
  writeText(folder() / "meta.json", meta.dump());
  expectRefused({"no \"written_by\": \"simpli\"", "not an MLI written by simpli"});
  meta["written_by"] = "someone else";
  writeText(folder() / "meta.json", meta.dump());
  expectRefused({"not an MLI written by simpli"});
}

TEST_P(MLIReplace, RefusesAnMLIWithAnythingAdded) {
  mli::writeMLI(folder().string(), randomMLI(2, 4, 4, 4), format());
  writeText(folder() / "notes.txt", "the user's notes");
  expectRefused({"holds \"notes.txt\"", "move it away"});
  fs::remove(folder() / "notes.txt");

  // A layer file beyond the MLI's layer count is not the MLI's either.
  const std::string extra =
      format() == mli::MLIFormat::Jpeg ? "layer_05.jpg" : "layer_rgba_05.tiff";
  writeText(folder() / extra, "x");
  expectRefused({"holds \"" + extra + "\""});
  fs::remove(folder() / extra);

  // Nor a folder under one of its file names, or any subfolder.
  fs::create_directories(folder() / "lossless");
  expectRefused({"holds \"lossless\""});
  fs::remove(folder() / "lossless");
  EXPECT_EQ(mli::mliReplaceRefusal(folder().string()), "") << "back to a plain MLI";
}

INSTANTIATE_TEST_SUITE_P(Forms, MLIReplace,
                         ::testing::Values(mli::MLIFormat::Jpeg, mli::MLIFormat::Lossless),
                         [](const ::testing::TestParamInfo<mli::MLIFormat>& i) {
                           return i.param == mli::MLIFormat::Jpeg ? "Jpeg" : "Lossless";
                         });

TEST(MLIReplaceExtras, AcceptsTheCommandsOwnExtrasOnly) {
  // `simpli infer`'s folder: the JPEG MLI, the lossless MLI in lossless/, rendered views.
  TempDir dir;
  const fs::path out = dir / "out";
  const mli::MLI mli = randomMLI(2, 4, 4, 5);
  mli::writeMLI(out.string(), mli, mli::MLIFormat::Jpeg);
  mli::writeMLI((out / "lossless").string(), mli, mli::MLIFormat::Lossless);
  writeText(out / "render_001.png", "png");
  mli::MLIFolderExtras extras;
  extras.mliFolders = {"lossless"};
  extras.isExtraFile = [](const std::string& name) { return name == "render_001.png"; };
  EXPECT_EQ(mli::mliReplaceRefusal(out.string(), extras), "");
  EXPECT_NE(mli::mliReplaceRefusal(out.string()), "") << "without the extras: refused";

  writeText(out / "lossless" / "notes.txt", "mine");
  EXPECT_EQ(mli::mliReplaceRefusal(out.string(), extras),
            "its subfolder \"lossless\" is not replaceable: it holds \"notes.txt\", which is not "
            "a file of the MLI simpli wrote there");
  fs::remove(out / "lossless" / "notes.txt");

  fs::remove_all(out / "lossless");
  fs::create_directories(out / "lossless" / "photos");
  EXPECT_NE(mli::mliReplaceRefusal(out.string(), extras).find("no meta.json"), std::string::npos);
  fs::remove_all(out / "lossless");
  writeText(out / "lossless", "a file where the folder belongs");
  EXPECT_NE(mli::mliReplaceRefusal(out.string(), extras).find("holds \"lossless\""),
            std::string::npos);
}

TEST(MLIReplaceExtras, WriteMLIFilesWritesIntoAFolderAsIs) {
  TempDir dir;
  const mli::MLI mli = randomMLI(2, 4, 4, 6);
  mli::writeMLIFiles(dir.str(), mli, mli::MLIFormat::Lossless);
  expectSameMLI(mli, mli::readMLI(dir.str()));
  EXPECT_EQ(listDir(dir.path()).size(), 5u);
}

} // namespace
} // namespace simpli::test

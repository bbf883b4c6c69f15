// Mutation test of the MLI reader (support/mutator.h): every mutant of meta.json, or of a layer
// file, is read to a valid MLI or rejected with a simpli::Error.
#include "mli_test_util.h"
#include "support/captured_warnings.h"
#include "support/mutator.h"

#include "simpli/model/mli/files.h"

#include <gtest/gtest.h>
#include <opencv2/core/utils/logger.hpp>

namespace simpli::test {
namespace {

// readMLI's result must satisfy the MLI contract (validateMLI throws otherwise).
void readValid(const fs::path& folder) {
  const mli::MLI m = mli::readMLI(folder.string());
  mli::validateMLI(m, "mutant MLI");
  EXPECT_GE(m.numLayers(), 1);
}

TEST(MLIFilesMutants, MetaJsonReadOrNamedError) {
  TempDir dir;
  CapturedWarnings warnings; // extreme but valid intrinsics only warn
  int rejected = 0, parsed = 0;
  for (const mli::MLIFormat format : {mli::MLIFormat::Jpeg, mli::MLIFormat::Lossless}) {
    const fs::path folder = dir / (format == mli::MLIFormat::Jpeg ? "jpeg" : "lossless");
    mli::writeMLI(folder.string(), randomMLI(2, 6, 8, 5), format);
    const fs::path meta = folder / "meta.json";
    const std::string original = readText(meta);
    const MutationCounts counts = runMutants(
        format == mli::MLIFormat::Jpeg ? "meta.json (JPEG form)" : "meta.json (lossless form)",
        30 + static_cast<uint64_t>(format), 1500, MutantKind::Json, {original},
        [&](const std::string& mutant) {
          writeText(meta, mutant);
          readValid(folder);
        });
    rejected += counts.rejected;
    parsed += counts.parsed;
  }
  EXPECT_GT(rejected, 1500);
  EXPECT_GT(parsed, 100);
}

TEST(MLIFilesMutants, LayerFilesReadOrNamedError) {
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  TempDir dir;
  int rejected = 0;
  for (const mli::MLIFormat format : {mli::MLIFormat::Jpeg, mli::MLIFormat::Lossless}) {
    const fs::path folder = dir / (format == mli::MLIFormat::Jpeg ? "jpeg" : "lossless");
    mli::writeMLI(folder.string(), smoothMLI(2, 16, 24), format);
    for (const char* name : {"layer_depth_01", "layer_00", "layer_alpha_01", "layer_rgba_00"}) {
      const fs::path file =
          folder / (std::string(name) + (format == mli::MLIFormat::Jpeg ? ".jpg" : ".tiff"));
      if (!fs::exists(file))
        continue;
      const std::string original = readText(file);
      rejected += runMutants(file.filename().string(), 40 + original.size() % 7, 250,
                             MutantKind::Binary, {original},
                             [&](const std::string& mutant) {
                               writeText(file, mutant);
                               readValid(folder);
                             })
                      .rejected;
      writeText(file, original);
    }
  }
  EXPECT_GT(rejected, 500);
}

} // namespace
} // namespace simpli::test

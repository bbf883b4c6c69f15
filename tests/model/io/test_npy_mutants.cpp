// Mutation test of the .npy reader (support/mutator.h): every mutant of a small corpus is parsed
// to a consistent array or rejected with a simpli::Error.
#include "support/mutator.h"
#include "support/temp_dir.h"

#include "simpli/model/io/npy.h"

#include <gtest/gtest.h>

using namespace simpli;

namespace {

// Version 1.0 files from writeNpy, and a hand-made float32, Fortran-order version 2.0 one.
std::vector<std::string> npyCorpus() {
  test::TempDir dir;
  std::vector<std::string> corpus;
  const std::vector<std::pair<std::vector<double>, std::vector<size_t>>> arrays = {
      {std::vector<double>(3 * 17, 0.25), {3, 17}},
      {{1.0, -2.0, 3.5}, {3}},
      {{}, {0, 17}},
      {{7.0}, {}}};
  for (const auto& [data, shape] : arrays) {
    io::writeNpy(dir.str("a.npy"), data, shape);
    corpus.push_back(test::readText(dir / "a.npy"));
  }
  std::string header = "{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3), }";
  while ((12 + header.size() + 1) % 64 != 0)
    header.push_back(' ');
  header.push_back('\n');
  std::string v2 = std::string("\x93NUMPY\x02\x00", 8);
  for (int k = 0; k < 4; ++k)
    v2.push_back(static_cast<char>((header.size() >> (8 * k)) & 0xff));
  v2 += header;
  for (int k = 0; k < 6; ++k) {
    const float f = 0.5f * static_cast<float>(k);
    v2.append(reinterpret_cast<const char*>(&f), 4);
  }
  corpus.push_back(v2);
  return corpus;
}

} // namespace

TEST(NpyMutants, ParsedOrNamedError) {
  const std::vector<std::string> corpus = npyCorpus();
  for (const std::string& file : corpus) // the corpus itself is valid
    io::parseNpy(reinterpret_cast<const unsigned char*>(file.data()), file.size(), "corpus");
  const test::MutationCounts counts = test::runMutants(
      "npy", 1, 6000, test::MutantKind::Binary, corpus, [](const std::string& mutant) {
        const io::NpyArray a = io::parseNpy(reinterpret_cast<const unsigned char*>(mutant.data()),
                                            mutant.size(), "mutant.npy");
        size_t count = 1;
        for (size_t d : a.shape)
          count *= d;
        EXPECT_EQ(a.data.size(), count);
        EXPECT_TRUE(a.descr == "<f8" || a.descr == "<f4") << a.descr;
      });
  EXPECT_GT(counts.rejected, 3000);
  EXPECT_GT(counts.parsed, 100);
}

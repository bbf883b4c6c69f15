// Mutation test of the safetensors reader (support/mutator.h): every mutant of a small corpus
// is read to tensors of consistent sizes or rejected with a simpli::Error.
#include "support/mutator.h"
#include "support/temp_dir.h"

#include "simpli/model/io/safetensors.h"

#include <gtest/gtest.h>

using namespace simpli;

namespace {

std::vector<std::string> safetensorsCorpus(const test::TempDir& dir) {
  std::vector<std::string> corpus;
  io::HostTensor<float> f{{2, 3}, {1, 2, 3, 4, 5, 6}};
  io::HostTensor<double> d{{4}, {0.5, -1, 1e300, 0}};
  io::HostTensor<int64_t> i{{1, 1, 2}, {7, -9}};
  io::HostTensor<float> empty{{0, 5}, {}};
  io::writeSafeTensors(dir.str("a.safetensors"),
                       {{"w.weight", io::makeEntry(f)},
                        {"w.bias", io::makeEntry(d)},
                        {"step", io::makeEntry(i)},
                        {"none", io::makeEntry(empty)}},
                       {{"config", "{\"name\": \"tiny\"}"}, {"format", "pt"}});
  corpus.push_back(test::readText(dir / "a.safetensors"));
  io::writeSafeTensors(dir.str("b.safetensors"), {{"x", io::makeEntry(f)}});
  corpus.push_back(test::readText(dir / "b.safetensors"));
  return corpus;
}

// Every tensor of the file read as its dtype: the sizes match the shapes.
void readAll(const std::string& path) {
  const io::SafeTensorsReader r(path);
  for (const std::string& key : r.keys()) {
    const io::SafeTensorInfo& info = r.info(key);
    int64_t numel = 1;
    for (int64_t dim : info.shape)
      numel *= dim;
    size_t size = 0;
    if (info.dtype == "F32")
      size = r.readF32(key).data.size();
    else if (info.dtype == "F64")
      size = r.readF64(key).data.size();
    else if (info.dtype == "I64")
      size = r.readI64(key).data.size();
    else
      continue; // valid in the format, not readable into host tensors
    EXPECT_EQ(static_cast<int64_t>(size), numel) << key;
  }
}

} // namespace

TEST(SafeTensorsMutants, ReadOrNamedError) {
  test::TempDir dir;
  const std::vector<std::string> corpus = safetensorsCorpus(dir);
  const std::string path = dir.str("mutant.safetensors");
  for (const std::string& file : corpus) {
    test::writeText(path, file);
    readAll(path);
  }
  const test::MutationCounts counts = test::runMutants(
      "safetensors", 2, 4000, test::MutantKind::Binary, corpus, [&](const std::string& mutant) {
        test::writeText(path, mutant);
        readAll(path);
      });
  EXPECT_GT(counts.rejected, 1000);
  EXPECT_GT(counts.parsed, 100);
}

// The header's JSON mutated as JSON (wrong types, huge numbers, missing keys), with a correct
// length field in front of it: the reader's type and range checks, not its length check.
TEST(SafeTensorsMutants, HeaderJsonReadOrNamedError) {
  test::TempDir dir;
  const std::string path = dir.str("mutant.safetensors");
  const std::string file = safetensorsCorpus(dir).front();
  uint64_t length = 0;
  for (int k = 7; k >= 0; --k)
    length = length << 8 | static_cast<unsigned char>(file[static_cast<size_t>(k)]);
  const std::string header = file.substr(8, length), data = file.substr(8 + length);
  const test::MutationCounts counts =
      test::runMutants("safetensors header", 3, 3000, test::MutantKind::Json, {header},
                       [&](const std::string& mutant) {
                         std::string bytes;
                         for (int k = 0; k < 8; ++k)
                           bytes.push_back(static_cast<char>((mutant.size() >> (8 * k)) & 0xff));
                         test::writeText(path, bytes + mutant + data);
                         readAll(path);
                       });
  EXPECT_GT(counts.rejected, 1000);
  EXPECT_GT(counts.parsed, 100);
}

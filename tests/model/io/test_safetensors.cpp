// safetensors: round trip, dtype rules, malformed files, and the golden inputs when present.
#include "support/expect_error.h"
#include "support/scene_fixtures.h"

#include "simpli/model/io/safetensors.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>

using namespace simpli;
using simpli::test::expectError;
using simpli::test::TempDir;

namespace {

std::string withHeader(const std::string& json, const std::string& data) {
  std::string out(8, '\0');
  const uint64_t n = json.size();
  std::memcpy(out.data(), &n, 8); // little-endian host
  return out + json + data;
}

} // namespace

TEST(SafeTensors, RoundTrip) {
  TempDir dir;
  io::HostTensor<float> f{{2, 3}, {1, 2, 3, 4, 5, 6.5f}};
  io::HostTensor<double> d{{3}, {1e-300, -2.5, 1e300}};
  io::HostTensor<int64_t> i{{2, 1}, {-7, int64_t(1) << 40}};
  io::HostTensor<float> scalar{{}, {42.0f}};
  io::HostTensor<float> empty{{0, 4}, {}};
  const std::string path = dir / "t.safetensors";
  io::writeSafeTensors(path,
                       {{"f", io::makeEntry(f)},
                        {"d", io::makeEntry(d)},
                        {"i", io::makeEntry(i)},
                        {"s", io::makeEntry(scalar)},
                        {"e", io::makeEntry(empty)}},
                       {{"config", "test"}});
  const io::SafeTensorsReader r(path);
  EXPECT_EQ(r.keys(), (std::vector<std::string>{"d", "e", "f", "i", "s"}));
  EXPECT_TRUE(r.contains("f"));
  EXPECT_FALSE(r.contains("__metadata__"));
  EXPECT_EQ(r.metadata().at("config"), "test");
  EXPECT_EQ(r.info("f").dtype, "F32");
  const auto f2 = r.readF32("f");
  EXPECT_EQ(f2.shape, f.shape);
  EXPECT_EQ(f2.data, f.data);
  EXPECT_EQ(r.readF64("d").data, d.data);
  EXPECT_EQ(r.readF64("f").data, (std::vector<double>{1, 2, 3, 4, 5, 6.5})); // widened
  EXPECT_EQ(r.readI64("i").data, i.data);
  EXPECT_EQ(r.readF32("s").data, scalar.data);
  EXPECT_TRUE(r.readF32("s").shape.empty());
  EXPECT_EQ(r.readF32("e").shape, (std::vector<int64_t>{0, 4}));
  // The header is padded to a multiple of 8.
  const std::string bytes = test::readText(path);
  uint64_t n;
  std::memcpy(&n, bytes.data(), 8);
  EXPECT_EQ(n % 8, 0u);

  expectError([&] { r.readF32("d"); }, {"t.safetensors", "'d'", "F64", "expected F32"});
  expectError([&] { r.readI64("f"); }, {"'f'", "F32", "expected I64"});
  expectError([&] { r.readF64("i"); }, {"'i'", "I64"});
  expectError([&] { r.readF32("nope"); }, {"t.safetensors", "'nope'"});
  expectError(
      [&] {
        io::writeSafeTensors(dir / "bad.safetensors", {{"x", {"F32", {3}, {1, 2}}}});
      },
      {"bad.safetensors", "'x'", "2 bytes"});
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.safetensors"));
}

TEST(SafeTensors, RejectsMalformedFiles) {
  TempDir dir;
  const std::string data(24, '\0');
  auto check = [&](const std::string& name, const std::string& bytes,
                   std::initializer_list<std::string> parts) {
    SCOPED_TRACE(name);
    test::writeText(dir / name, bytes);
    const std::string msg = expectError([&] { io::SafeTensorsReader r(dir / name); }, parts);
    EXPECT_NE(msg.find(name), std::string::npos) << msg;
  };
  check("short.safetensors", "abc", {"truncated"});
  check("hugeheader.safetensors", withHeader("{}", "").replace(0, 8, "\xff\xff\xff\xff\0\0\0\0", 8),
        {"header length 4294967295"});
  check("json.safetensors", withHeader("{not json", data), {"not valid JSON"});
  check("array.safetensors", withHeader("[1,2]", data), {"not a JSON object"});
  check("dtype.safetensors",
        withHeader(R"({"a":{"dtype":"Q7","shape":[2],"data_offsets":[0,8]}})", data),
        {"'a'", "dtype", "Q7"});
  check("shape.safetensors",
        withHeader(R"({"a":{"dtype":"F32","shape":[-2],"data_offsets":[0,8]}})", data),
        {"'a'", "shape", "-2"});
  check("offsets.safetensors",
        withHeader(R"({"a":{"dtype":"F32","shape":[2],"data_offsets":[0]}})", data),
        {"'a'", "data_offsets"});
  check("range.safetensors",
        withHeader(R"({"a":{"dtype":"F32","shape":[10],"data_offsets":[0,40]}})", data),
        {"'a'", "[0, 40]", "24 bytes"});
  check("count.safetensors",
        withHeader(R"({"a":{"dtype":"F32","shape":[3],"data_offsets":[0,8]}})", data),
        {"'a'", "needs 12"});
  check("meta.safetensors", withHeader(R"({"__metadata__":{"k":1}})", data), {"'k'"});
  expectError([&] { io::SafeTensorsReader r(dir / "missing.safetensors"); },
              {"missing.safetensors", "does not exist"});
}

TEST(SafeTensors, GoldenInputs) {
  const std::string path = std::string(SIMPLI_GOLDEN_DIR) + "/inputs.safetensors";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << "golden data not found at " << path << " (set SIMPLI_GOLDEN_DIR)";
  const io::SafeTensorsReader r(path);
  const auto ext = r.readF32("src_extrinsics");
  EXPECT_EQ(ext.shape, (std::vector<int64_t>{3, 3, 4}));
  EXPECT_EQ(ext.data.size(), 36u);
  const auto depths = r.readF32("plane_depths");
  ASSERT_EQ(depths.shape, (std::vector<int64_t>{41}));
  EXPECT_NEAR(depths.data[0], 100.0f, 1e-3);
  EXPECT_NEAR(depths.data[40], 1.0f, 1e-6);
  EXPECT_EQ(r.readF32("images").shape, (std::vector<int64_t>{3, 3, 64, 96}));
}

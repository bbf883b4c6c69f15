// .npy reading: versions, orders, dtypes, and every kind of malformed file.
#include "support/expect_error.h"
#include "support/scene_fixtures.h"

#include "simpli/model/io/npy.h"

#include <gtest/gtest.h>

#include <cstring>

using namespace simpli;
using simpli::test::expectError;
using simpli::test::TempDir;

namespace {

// A .npy file with the given version, header text (padded to 64) and raw data bytes.
std::string npyBytes(int major, const std::string& header, const std::string& data,
                     bool pad = true) {
  std::string h = header;
  const size_t prefix = major == 1 ? 10 : 12;
  if (pad) {
    while ((prefix + h.size() + 1) % 64 != 0)
      h.push_back(' ');
    h.push_back('\n');
  }
  std::string out = "\x93NUMPY";
  out.push_back(char(major));
  out.push_back(0);
  const size_t n = h.size();
  out.push_back(char(n & 0xff));
  out.push_back(char((n >> 8) & 0xff));
  if (major != 1) {
    out.push_back(char((n >> 16) & 0xff));
    out.push_back(char((n >> 24) & 0xff));
  }
  return out + h + data;
}

template <typename T> std::string raw(std::initializer_list<T> values) {
  std::string s;
  for (T v : values)
    s.append(reinterpret_cast<const char*>(&v), sizeof(T)); // tests run on little-endian hosts
  return s;
}

} // namespace

TEST(Npy, WriteReadRoundTrip) {
  TempDir dir;
  const std::vector<double> data = {1.5, -2.25, 3e10, 0.0, 1e-300, 7.0};
  io::writeNpy(dir / "a.npy", data, {2, 3});
  const io::NpyArray a = io::readNpy(dir / "a.npy");
  EXPECT_EQ(a.shape, (std::vector<size_t>{2, 3}));
  EXPECT_EQ(a.data, data);
  EXPECT_EQ(a.descr, "<f8");
  EXPECT_DOUBLE_EQ(a.at(1, 0), 0.0);
  // Header + magic is a multiple of 64 bytes, as numpy writes it.
  EXPECT_EQ((test::readText(dir / "a.npy").size() - 48) % 64, 0u);
  expectError([&] { io::writeNpy(dir / "b.npy", data, {4, 2}); }, {"b.npy", "(4, 2)", "6"});
}

TEST(Npy, VersionsOrdersAndFloat32) {
  TempDir dir;
  const std::string c23 = raw<double>({1, 2, 3, 4, 5, 6});
  test::writeText(dir / "v2.npy",
                  npyBytes(2, "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }", c23));
  test::writeText(
      dir / "v3.npy",
      npyBytes(3, "{\"descr\": \"<f8\", \"fortran_order\": False, \"shape\": (6,)}", c23));
  // Fortran order: columns stored one after the other.
  test::writeText(dir / "f.npy",
                  npyBytes(1, "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3), }",
                           raw<double>({1, 4, 2, 5, 3, 6})));
  test::writeText(dir / "f4.npy",
                  npyBytes(1, "{'shape': (2L, 3L), 'fortran_order': False, 'descr': '<f4'}",
                           raw<float>({1, 2, 3, 4, 5, 6.5f})));
  // 3-D Fortran order: element (i, j, k) at i + 2 j + 4 k.
  std::string f3;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        f3 += raw<double>({double(100 * i + 10 * j + k)});
  test::writeText(dir / "f3.npy",
                  npyBytes(1, "{'descr': '<f8', 'fortran_order': True, 'shape': (2, 2, 2), }", f3));

  const std::vector<double> expected = {1, 2, 3, 4, 5, 6};
  EXPECT_EQ(io::readNpy(dir / "v2.npy").data, expected);
  const io::NpyArray v3 = io::readNpy(dir / "v3.npy");
  EXPECT_EQ(v3.data, expected);
  EXPECT_EQ(v3.shape, (std::vector<size_t>{6}));
  EXPECT_EQ(io::readNpy(dir / "f.npy").data, expected);
  const io::NpyArray f4 = io::readNpy(dir / "f4.npy");
  EXPECT_EQ(f4.descr, "<f4");
  EXPECT_EQ(f4.data, (std::vector<double>{1, 2, 3, 4, 5, 6.5}));
  const io::NpyArray a3 = io::readNpy(dir / "f3.npy");
  EXPECT_EQ(a3.data, (std::vector<double>{0, 1, 10, 11, 100, 101, 110, 111}));
}

TEST(Npy, RejectsBadFiles) {
  TempDir dir;
  const std::string d6 = raw<double>({1, 2, 3, 4, 5, 6});
  const std::string good = "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }";
  auto check = [&](const std::string& name, const std::string& bytes,
                   std::initializer_list<std::string> parts) {
    const std::string path = dir / name;
    test::writeText(path, bytes);
    SCOPED_TRACE(name);
    std::vector<std::string> all(parts);
    all.push_back(name);
    try {
      io::readNpy(path);
      ADD_FAILURE() << name << ": no error";
    } catch (const Error& e) {
      for (const auto& p : all)
        EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what() << " / " << p;
    }
  };
  check("magic.npy", "NUMPY not really", {"magic"});
  check("short.npy", "\x93NUM", {"magic"});
  check("version.npy", npyBytes(1, good, d6).replace(6, 1, "\x04"), {"version 4.0"});
  check("hdrlen.npy", npyBytes(1, good, d6).replace(8, 2, "\xff\x7f"),
        {"header is truncated", "32767"});
  check("bigendian.npy",
        npyBytes(1, "{'descr': '>f8', 'fortran_order': False, 'shape': (2, 3), }", d6), {"'>f8'"});
  check("int.npy", npyBytes(1, "{'descr': '<i8', 'fortran_order': False, 'shape': (2, 3), }", d6),
        {"'<i8'"});
  check("object.npy", npyBytes(1, "{'descr': '|O', 'fortran_order': False, 'shape': (2, 3), }", d6),
        {"'|O'"});
  check("structured.npy",
        npyBytes(1, "{'descr': [('a', '<f8')], 'fortran_order': False, 'shape': (2, 3), }", d6),
        {"malformed", "'descr'"});
  check("truncdata.npy", npyBytes(1, good, d6.substr(0, 40)), {"truncated", "(2, 3)", "48", "40"});
  check("nokey.npy", npyBytes(1, "{'descr': '<f8', 'shape': (2, 3), }", d6), {"'fortran_order'"});
  check("extrakey.npy",
        npyBytes(1, "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), 'x': 1}", d6),
        {"'x'"});
  check("badbool.npy",
        npyBytes(1, "{'descr': '<f8', 'fortran_order': maybe, 'shape': (2, 3), }", d6),
        {"fortran_order"});
  check("badshape.npy",
        npyBytes(1, "{'descr': '<f8', 'fortran_order': False, 'shape': (2, -3), }", d6),
        {"'shape'"});
  check("notdict.npy", npyBytes(1, "[1, 2, 3]", d6), {"malformed"});
  check("unterminated.npy", npyBytes(1, "{'descr': '<f8", d6), {"malformed"});
  check("huge.npy",
        npyBytes(1,
                 "{'descr': '<f8', 'fortran_order': False, 'shape': (99999999999, 99999999999), }",
                 d6),
        {"truncated", "larger than any file"});
  expectError([&] { io::readNpy(dir / "missing.npy"); }, {"missing.npy", "does not exist"});
}

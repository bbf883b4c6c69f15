// ParameterStore: registration, initialisation, safetensors round trips and load errors.
#include "support/expect_error.h"
#include "support/temp_dir.h"

#include "simpli/model/io/safetensors.h"
#include "simpli/model/network/layers.h"
#include "simpli/model/network/network.h"
#include "simpli/model/network/parameter_store.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>

namespace simpli::network {
namespace {

namespace fs = std::filesystem;
using ocl::Dtype;
using ocl::Tensor;
using test::expectError;

using test::TempDir;

io::HostTensor<float> host(const std::vector<int64_t>& shape, float start) {
  io::HostTensor<float> t;
  t.shape = shape;
  t.data.resize(static_cast<std::size_t>(t.numel()));
  std::iota(t.data.begin(), t.data.end(), start);
  return t;
}

void fillStore(ParameterStore& s) {
  s.add("a.conv.weight", {4, 3, 3, 3}, {InitKind::FanInUniform, 27});
  s.add("a.conv.bias", {4}, {InitKind::FanInUniform, 27});
  s.add("a.norm.gamma", {4}, {InitKind::Uniform01});
  s.add("a.norm.beta", {4}, {InitKind::Zeros});
  s.add("b.layer_norm.weight", {5}, {InitKind::Ones});
  s.add("b.anchor", {2, 5}, {InitKind::Normal01});
}

TEST(NetParameterStore, RegistrationAndCount) {
  ParameterStore s;
  fillStore(s);
  EXPECT_EQ(s.size(), 6u);
  EXPECT_EQ(s.count(), 108 + 4 + 4 + 4 + 5 + 10);
  EXPECT_EQ(s.names().front(), "a.conv.weight");
  EXPECT_TRUE(s.get("a.conv.bias").requiresGrad());
  EXPECT_EQ(s.parameters().size(), 6u);
  expectError([&] { s.add("a.conv.bias", {4}, {}); }, {"a.conv.bias", "twice"});
  expectError([&] { s.add("c", {4, 0}, {}); }, {"\"c\"", "[4, 0]"});
  expectError([&] { s.add("", {4}, {}); }, {"empty"});
  expectError([&] { s.add("d", {4}, {InitKind::FanInUniform, 0}); }, {"\"d\"", "fan-in"});
  expectError([&] { s.get("nope"); }, {"nope"});
  // A config's huge channel counts are refused before anything is allocated.
  expectError(
      [&] {
        s.add("huge", {65536, 65536, 65536, 65536}, {});
      },
      {"\"huge\"", "[65536, 65536, 65536, 65536]", "kMaxParameters"});
  EXPECT_FALSE(s.contains("huge"));
  // Also through a config: 65536 channels everywhere would be tens of billions of weights.
  NetworkConfig big = officialConfig(4);
  for (BlockDims& b : big.sampiLvl0.blocks)
    b = {65536, 65536};
  expectError([&] { SimpliNetwork(big, ocl::Dtype::F32, 0); },
              {"sampi_block_lvl0", "kMaxParameters"});
}

TEST(NetParameterStore, PyTorchDefaultInitialisation) {
  ParameterStore s(Dtype::F64, 7);
  const Tensor w = s.add("w", {64, 64, 3, 3}, {InitKind::FanInUniform, 64 * 9});
  const Tensor g = s.add("g", {4096}, {InitKind::Uniform01});
  const Tensor z = s.add("z", {7}, {InitKind::Zeros});
  const Tensor o = s.add("o", {7}, {InitKind::Ones});
  const Tensor n = s.add("n", {4096}, {InitKind::Normal01});
  const double bound = 1.0 / std::sqrt(64.0 * 9.0);
  const std::vector<double> wv = w.toVector();
  EXPECT_LE(*std::max_element(wv.begin(), wv.end()), bound);
  EXPECT_GE(*std::min_element(wv.begin(), wv.end()), -bound);
  EXPECT_GT(*std::max_element(wv.begin(), wv.end()), 0.99 * bound); // fills the interval
  const std::vector<double> gv = g.toVector();
  EXPECT_GE(*std::min_element(gv.begin(), gv.end()), 0.0);
  EXPECT_LT(*std::max_element(gv.begin(), gv.end()), 1.0);
  EXPECT_NEAR(std::accumulate(gv.begin(), gv.end(), 0.0) / gv.size(), 0.5, 0.03);
  for (double v : z.toVector())
    EXPECT_EQ(v, 0.0);
  for (double v : o.toVector())
    EXPECT_EQ(v, 1.0);
  const std::vector<double> nv = n.toVector();
  const double mean = std::accumulate(nv.begin(), nv.end(), 0.0) / nv.size();
  double var = 0;
  for (double v : nv)
    var += (v - mean) * (v - mean) / nv.size();
  EXPECT_NEAR(mean, 0.0, 0.05);
  EXPECT_NEAR(std::sqrt(var), 1.0, 0.05);
}

TEST(NetParameterStore, SeedsAreReproducibleAndInitialiseWritesInPlace) {
  ParameterStore a(Dtype::F32, 3), b(Dtype::F32, 3), c(Dtype::F32, 4);
  fillStore(a);
  fillStore(b);
  fillStore(c);
  EXPECT_EQ(a.get("a.conv.weight").toVector(), b.get("a.conv.weight").toVector());
  EXPECT_NE(a.get("a.conv.weight").toVector(), c.get("a.conv.weight").toVector());
  // Different parameters get different streams even with equal shapes and kinds.
  EXPECT_NE(a.get("a.conv.bias").toVector(), a.get("a.norm.gamma").toVector());
  const Tensor handle = a.get("a.conv.weight");
  a.initialise(4);
  EXPECT_EQ(handle.toVector(), c.get("a.conv.weight").toVector());
}

TEST(NetParameterStore, SaveLoadRoundTripInBothPrecisions) {
  TempDir dir;
  ParameterStore a(Dtype::F32, 1);
  fillStore(a);
  a.save(dir.str("a.safetensors"), {{"config", "test"}});
  const io::SafeTensorsReader r(dir.str("a.safetensors"));
  EXPECT_EQ(r.metadata().at("config"), "test");
  EXPECT_EQ(r.info("a.conv.weight").dtype, "F32");

  ParameterStore f32(Dtype::F32, 2), f64(Dtype::F64, 2);
  fillStore(f32);
  fillStore(f64);
  const Tensor handle = f32.get("b.anchor");
  const LoadReport report = f32.load(dir.str("a.safetensors"));
  EXPECT_EQ(report.loaded, 6u);
  EXPECT_TRUE(report.unexpected.empty());
  EXPECT_FALSE(report.strippedModulePrefix);
  f64.load(dir.str("a.safetensors"));
  for (const std::string& name : a.names()) {
    EXPECT_EQ(f32.get(name).toVector(), a.get(name).toVector()) << name;
    EXPECT_EQ(f64.get(name).toVector(), a.get(name).toVector()) << name; // float widens exactly
  }
  EXPECT_EQ(handle.toVector(), a.get("b.anchor").toVector()); // module handles see the load

  f64.save(dir.str("b.safetensors"));
  EXPECT_EQ(io::SafeTensorsReader(dir.str("b.safetensors")).info("b.anchor").dtype, "F64");
  ParameterStore back(Dtype::F32, 9);
  fillStore(back);
  back.load(dir.str("b.safetensors"));
  EXPECT_EQ(back.get("a.conv.weight").toVector(), a.get("a.conv.weight").toVector());
}

TEST(NetParameterStore, ModulePrefixAndUnexpectedKeys) {
  TempDir dir;
  ParameterStore s;
  fillStore(s);
  std::map<std::string, io::SafeTensorEntry> entries;
  for (const std::string& name : s.names()) {
    io::HostTensor<float> t = host(s.get(name).shape(), 1.0f);
    entries.emplace("module." + name, io::makeEntry(t));
  }
  entries.emplace("module.extra.buffer", io::makeEntry(host({2}, 0.0f)));
  entries.emplace("other", io::makeEntry(host({1}, 0.0f)));
  io::writeSafeTensors(dir.str("m.safetensors"), entries);
  const LoadReport r = s.load(dir.str("m.safetensors"));
  EXPECT_TRUE(r.strippedModulePrefix);
  EXPECT_EQ(r.loaded, 6u);
  EXPECT_EQ(r.unexpected, (std::vector<std::string>{"module.extra.buffer", "other"}));
  EXPECT_EQ(s.get("a.conv.bias").toVector(), (std::vector<double>{1, 2, 3, 4}));
}

TEST(NetParameterStore, LoadErrorsNameFileKeyAndShapes) {
  TempDir dir;
  ParameterStore s(Dtype::F32, 5);
  fillStore(s);
  const std::vector<double> before = s.get("a.conv.weight").toVector();
  auto write = [&](const std::string& file, auto mutate) {
    std::map<std::string, io::SafeTensorEntry> entries;
    for (const std::string& name : s.names())
      entries.emplace(name, io::makeEntry(host(s.get(name).shape(), 0.5f)));
    mutate(entries);
    io::writeSafeTensors(dir.str(file), entries);
    return dir.str(file);
  };
  const std::string missing = write("missing.safetensors", [](auto& e) { e.erase("a.norm.beta"); });
  expectError([&] { s.load(missing); }, {missing, "1 of 6", "a.norm.beta", "missing"});
  const std::string shape = write("shape.safetensors", [](auto& e) {
    e["a.conv.weight"] = io::makeEntry(host({4, 3, 1, 1}, 0.0f));
  });
  expectError([&] { s.load(shape); },
              {shape, "a.conv.weight", "expected shape [4, 3, 3, 3]", "found [4, 3, 1, 1]"});
  const std::string twice = write("twice.safetensors", [](auto& e) {
    e["module.a.norm.beta"] = io::makeEntry(host({4}, 0.0f));
  });
  expectError([&] { s.load(twice); }, {twice, "a.norm.beta", "twice"});
  const std::string ints = write("ints.safetensors", [](auto& e) {
    io::HostTensor<int64_t> t;
    t.shape = {4};
    t.data = {1, 2, 3, 4};
    e["a.conv.bias"] = io::makeEntry(t);
  });
  expectError([&] { s.load(ints); }, {ints, "a.conv.bias", "I64"});
  const std::string nan = write("nan.safetensors", [](auto& e) {
    io::HostTensor<float> t = host({4}, 0.0f);
    t.data[2] = NAN;
    e["a.norm.gamma"] = io::makeEntry(t);
  });
  expectError([&] { s.load(nan); }, {nan, "a.norm.gamma", "non-finite"});
  expectError([&] { s.load(dir.str("absent.safetensors")); }, {"absent.safetensors"});
  // No failed load wrote anything.
  EXPECT_EQ(s.get("a.conv.weight").toVector(), before);
}

TEST(NetParameterStore, ModulesRegisterReferenceNames) {
  ParameterStore s;
  const DoubleConvBlock block(s, "x.model.0", 2, 5, 4, 3, false);
  const std::vector<std::string> expected = {
      "x.model.0.residual_conv.conv.weight", "x.model.0.residual_conv.conv.bias",
      "x.model.0.double_conv.0.conv.weight", "x.model.0.double_conv.0.conv.bias",
      "x.model.0.double_conv.0.norm.gamma",  "x.model.0.double_conv.0.norm.beta",
      "x.model.0.double_conv.1.conv.weight", "x.model.0.double_conv.1.conv.bias",
      "x.model.0.double_conv.1.norm.gamma",  "x.model.0.double_conv.1.norm.beta"};
  EXPECT_EQ(s.names(), expected);
  EXPECT_EQ(s.get("x.model.0.double_conv.0.conv.weight").shape(), (ocl::Shape{4, 5, 3, 3}));
  EXPECT_EQ(s.get("x.model.0.residual_conv.conv.weight").shape(), (ocl::Shape{3, 5, 1, 1}));
  // Identity residual: no residual conv.
  ParameterStore t;
  const DoubleConvBlock same(t, "y", 3, 4, 6, 4, true);
  EXPECT_FALSE(t.contains("y.residual_conv.conv.weight"));
  EXPECT_EQ(t.get("y.double_conv.0.conv.weight").shape(), (ocl::Shape{6, 4, 3, 3, 3}));
}

} // namespace
} // namespace simpli::network

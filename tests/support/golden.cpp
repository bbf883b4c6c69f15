#include "support/golden.h"

#include "simpli/error.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>

namespace simpli::test {

scene::Camera goldenCamera(const double* e, const double* k, int width, int height) {
  scene::Camera c;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      c.R(i, j) = e[4 * i + j];
    c.t[i] = e[4 * i + 3];
  }
  c.fx = k[0];
  c.cx = k[2];
  c.fy = k[4];
  c.cy = k[5];
  c.width = width;
  c.height = height;
  return c;
}

std::string goldenDir() {
  return SIMPLI_GOLDEN_DIR;
}

bool goldenAvailable() {
  for (const char* f : {"micro.safetensors", "stages.safetensors", "inputs.safetensors",
                        "weights.safetensors", "tolerances.json"})
    if (!std::filesystem::exists(std::filesystem::path(goldenDir()) / f))
      return false;
  return true;
}

const io::SafeTensorsReader& goldenFile(const std::string& name) {
  static std::map<std::string, std::unique_ptr<io::SafeTensorsReader>> readers;
  auto it = readers.find(name);
  if (it == readers.end())
    it = readers
             .emplace(name, std::make_unique<io::SafeTensorsReader>(goldenDir() + "/" + name +
                                                                    ".safetensors"))
             .first;
  return *it->second;
}

ocl::Tensor goldenTensor(const std::string& file, const std::string& key, ocl::Dtype dtype) {
  const io::HostTensor<double> t = goldenFile(file).readF64(key);
  return ocl::Tensor::fromHost(t.data, t.shape, dtype);
}

double measuredError(const std::string& section, const std::string& name) {
  static nlohmann::json tolerances = [] {
    std::ifstream in(goldenDir() + "/tolerances.json");
    if (!in)
      fail(goldenDir(), "/tolerances.json: cannot open");
    return nlohmann::json::parse(in);
  }();
  const auto& s = tolerances.at(section);
  if (!s.contains(name))
    fail("tolerances.json: no entry \"", name, "\" in section \"", section, "\"");
  return s.at(name).at("rel_to_max").get<double>();
}

double relToMax(const ocl::Tensor& got, const ocl::Tensor& ref) {
  if (got.shape() != ref.shape())
    fail("relToMax: shape ", got.describe(), " vs reference ", ref.describe());
  const std::vector<double> a = got.toVector(), b = ref.toVector();
  double err = 0, mag = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double e = std::abs(a[i] - b[i]);
    err = std::isnan(e) ? INFINITY : std::max(err, e);
    mag = std::max(mag, std::abs(b[i]));
  }
  return mag > 0 ? err / mag : err;
}

void expectGoldenClose(const std::string& what, const ocl::Tensor& got, const ocl::Tensor& ref,
                       double tol) {
  ASSERT_EQ(got.shape(), ref.shape())
      << what << ": " << got.describe() << " vs golden " << ref.describe();
  const double rel = relToMax(got, ref);
  std::cout << "[golden] " << what << " " << ocl::toString(got.dtype()) << " rel=" << rel
            << " tol=" << tol << std::endl;
  EXPECT_LE(rel, tol) << what << " (" << ocl::toString(got.dtype()) << ")";
}

} // namespace simpli::test

// ParameterStore: registration, PyTorch-style initialisation, safetensors load / save.
#include "simpli/model/network/parameter_store.h"

#include "simpli/error.h"
#include "simpli/model/io/safetensors.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace simpli::network {
namespace {

// FNV-1a: a name hash that is the same on every platform and standard library (std::hash is
// not), so a seed gives the same initial weights everywhere.
uint64_t fnv1a(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

uint64_t splitmix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

ocl::Tensor drawTensor(const ocl::Shape& shape, const ParamInit& init, uint64_t seed,
                       ocl::Dtype dtype) {
  switch (init.kind) {
  case InitKind::FanInUniform: {
    const double bound = 1.0 / std::sqrt(static_cast<double>(init.fanIn));
    return ocl::Tensor::uniform(shape, -bound, bound, seed, dtype);
  }
  case InitKind::Uniform01:
    return ocl::Tensor::uniform(shape, 0.0, 1.0, seed, dtype);
  case InitKind::Zeros:
    return ocl::Tensor::zeros(shape, dtype);
  case InitKind::Ones:
    return ocl::Tensor::ones(shape, dtype);
  case InitKind::Normal01:
    return ocl::Tensor::normal(shape, 0.0, 1.0, seed, dtype);
  }
  fail("ParameterStore: unknown initialisation kind");
}

const char* const kModulePrefix = "module.";

} // namespace

ParameterStore::ParameterStore(ocl::Dtype dtype, uint64_t seed) : dtype_(dtype), seed_(seed) {}

ocl::Tensor ParameterStore::add(const std::string& name, const ocl::Shape& shape, ParamInit init) {
  if (name.empty())
    fail("ParameterStore: empty parameter name");
  if (contains(name))
    fail("ParameterStore: parameter \"", name, "\" is registered twice");
  if (shape.empty() || std::any_of(shape.begin(), shape.end(), [](int64_t d) { return d <= 0; }))
    fail("ParameterStore: parameter \"", name, "\" has invalid shape ", ocl::toString(shape));
  double numel = 1; // in double: four dimensions of 65536 overflow int64
  for (int64_t d : shape)
    numel *= static_cast<double>(d);
  if (numel + static_cast<double>(count()) > static_cast<double>(kMaxParameters))
    fail("ParameterStore: parameter \"", name, "\" of shape ", ocl::toString(shape),
         " would bring the network to more than the limit of ", kMaxParameters,
         " parameters (kMaxParameters, 1 GiB in float32; the reference's 4-layer network has "
         "1,879,343): the network config's channel counts are too large");
  if (init.kind == InitKind::FanInUniform && init.fanIn <= 0)
    fail("ParameterStore: parameter \"", name, "\" has fan-in ", init.fanIn);
  Entry entry;
  entry.init = init;
  entry.tensor = drawTensor(shape, init, splitmix64(seed_ ^ fnv1a(name)), dtype_);
  entry.tensor.setRequiresGrad(true);
  names_.push_back(name);
  auto it = index_.emplace(name, std::move(entry)).first;
  return it->second.tensor;
}

const ocl::Tensor& ParameterStore::get(const std::string& name) const {
  auto it = index_.find(name);
  if (it == index_.end())
    fail("ParameterStore: no parameter \"", name, "\"");
  return it->second.tensor;
}

std::vector<ocl::Tensor> ParameterStore::parameters() const {
  std::vector<ocl::Tensor> out;
  out.reserve(names_.size());
  for (const std::string& n : names_)
    out.push_back(index_.at(n).tensor);
  return out;
}

std::map<std::string, ocl::Shape> ParameterStore::shapes() const {
  std::map<std::string, ocl::Shape> out;
  for (const auto& [name, entry] : index_)
    out.emplace(name, entry.tensor.shape());
  return out;
}

int64_t ParameterStore::count() const {
  int64_t n = 0;
  for (const auto& [name, entry] : index_)
    n += entry.tensor.numel();
  return n;
}

void ParameterStore::draw(const std::string& name, Entry& entry, uint64_t seed) {
  const ocl::Tensor fresh =
      drawTensor(entry.tensor.shape(), entry.init, splitmix64(seed ^ fnv1a(name)), dtype_);
  // In place: modules hold handles to this buffer.
  entry.tensor.fill(0.0);
  entry.tensor.addInPlace(fresh);
}

void ParameterStore::initialise(uint64_t seed) {
  seed_ = seed;
  for (auto& [name, entry] : index_)
    draw(name, entry, seed);
}

LoadReport ParameterStore::load(const std::string& path) {
  const io::SafeTensorsReader reader(path);
  return load(reader);
}

LoadReport ParameterStore::load(const io::SafeTensorsReader& reader) {
  const std::string& file = reader.path();
  LoadReport report;
  std::map<std::string, std::string> keyOf; // parameter name -> key in the file
  const std::string prefix = kModulePrefix;
  for (const std::string& key : reader.keys()) {
    const bool prefixed = key.compare(0, prefix.size(), prefix) == 0;
    const std::string name = prefixed ? key.substr(prefix.size()) : key;
    if (!contains(name)) {
      report.unexpected.push_back(key);
      continue;
    }
    if (keyOf.count(name))
      fail(file, ": parameter \"", name, "\" is stored twice (keys \"", keyOf[name], "\" and \"",
           key, "\")");
    keyOf[name] = key;
    report.strippedModulePrefix = report.strippedModulePrefix || prefixed;
  }
  std::vector<std::string> missing;
  for (const std::string& name : names_)
    if (!keyOf.count(name))
      missing.push_back(name);
  if (!missing.empty()) {
    std::ostringstream list;
    for (std::size_t i = 0; i < missing.size() && i < 5; ++i)
      list << (i ? ", " : "") << '"' << missing[i] << '"';
    if (missing.size() > 5)
      list << ", ...";
    fail(file, ": ", missing.size(), " of ", names_.size(), " parameters missing: ", list.str());
  }
  // Check everything before writing anything, so a bad file leaves the weights untouched.
  for (const auto& [name, key] : keyOf) {
    const io::SafeTensorInfo& info = reader.info(key);
    const ocl::Shape& expected = index_.at(name).tensor.shape();
    if (info.shape != expected)
      fail(file, ": parameter \"", key, "\": expected shape ", ocl::toString(expected), ", found ",
           ocl::toString(info.shape));
    if (info.dtype != "F32" && info.dtype != "F64")
      fail(file, ": parameter \"", key, "\": dtype ", info.dtype, ", expected F32 or F64");
  }
  std::vector<std::pair<std::string, std::vector<double>>> values;
  for (const auto& [name, key] : keyOf) {
    io::HostTensor<double> t = reader.readF64(key);
    for (double v : t.data)
      if (!std::isfinite(v))
        fail(file, ": parameter \"", key, "\" holds a non-finite value (", v, ")");
    values.emplace_back(name, std::move(t.data));
  }
  for (const auto& [name, data] : values)
    index_.at(name).tensor.copyFromHost(data);
  report.loaded = values.size();
  return report;
}

void ParameterStore::save(const std::string& path,
                          const std::map<std::string, std::string>& metadata) const {
  std::map<std::string, io::SafeTensorEntry> entries;
  for (const auto& [name, entry] : index_) {
    const ocl::Tensor& t = entry.tensor;
    if (dtype_ == ocl::Dtype::F64) {
      io::HostTensor<double> h;
      h.shape = t.shape();
      h.data = t.toVector();
      entries.emplace(name, io::makeEntry(h));
    } else {
      io::HostTensor<float> h;
      h.shape = t.shape();
      h.data = t.toVectorF32();
      entries.emplace(name, io::makeEntry(h));
    }
  }
  io::writeSafeTensors(path, entries, metadata);
}

void ParameterStore::zeroGrad() {
  for (auto& [name, entry] : index_)
    entry.tensor.zeroGrad();
}

} // namespace simpli::network

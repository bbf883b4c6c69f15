#include "simpli/model/io/safetensors.h"

#include "io/json_text.h"
#include "simpli/error.h"
#include "simpli/model/io/files.h"

#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace simpli::io {

namespace {

// Element sizes of the dtypes the format defines; a file may hold any of them, but only
// F32 / F64 / I64 can be read into host tensors.
int dtypeSize(const std::string& dtype) {
  if (dtype == "F64" || dtype == "I64" || dtype == "U64")
    return 8;
  if (dtype == "F32" || dtype == "I32" || dtype == "U32")
    return 4;
  if (dtype == "F16" || dtype == "BF16" || dtype == "I16" || dtype == "U16")
    return 2;
  if (dtype == "I8" || dtype == "U8" || dtype == "BOOL" || dtype == "F8_E4M3" || dtype == "F8_E5M2")
    return 1;
  return 0;
}

uint64_t readU64(const unsigned char* p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i)
    v = (v << 8) | p[i];
  return v;
}

// Little-endian decoding without assuming the host's byte order.
template <typename T> T decode(const unsigned char* p) {
  uint64_t bits = 0;
  for (int i = int(sizeof(T)) - 1; i >= 0; --i)
    bits = (bits << 8) | p[i];
  T value;
  if constexpr (sizeof(T) == 4) {
    const uint32_t b32 = uint32_t(bits);
    std::memcpy(&value, &b32, 4);
  } else {
    std::memcpy(&value, &bits, 8);
  }
  return value;
}

template <typename T> void encode(T value, std::vector<unsigned char>& out) {
  uint64_t bits = 0;
  if constexpr (sizeof(T) == 4) {
    uint32_t b32;
    std::memcpy(&b32, &value, 4);
    bits = b32;
  } else {
    std::memcpy(&bits, &value, 8);
  }
  for (size_t i = 0; i < sizeof(T); ++i)
    out.push_back(static_cast<unsigned char>(bits >> (8 * i)));
}

} // namespace

SafeTensorsReader::SafeTensorsReader(const std::string& path) : path_(path) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    fail("safetensors file '", path, "' does not exist");
  if (fs::is_directory(path, ec))
    fail("safetensors file '", path, "' is a directory, expected a file");
  const uint64_t fileSize = fs::file_size(path, ec);
  if (ec)
    fail("cannot read safetensors file '", path, "': ", ec.message());
  std::ifstream in(path, std::ios::binary);
  if (!in)
    fail("cannot open safetensors file '", path, "'");
  unsigned char lenBytes[8];
  if (fileSize < 8 || !in.read(reinterpret_cast<char*>(lenBytes), 8))
    fail("safetensors file '", path, "' is truncated: ", fileSize,
         " bytes, too short for the 8-byte header length");
  const uint64_t headerSize = readU64(lenBytes);
  if (headerSize > fileSize - 8)
    fail("safetensors file '", path, "' is truncated or corrupt: header length ", headerSize,
         " exceeds the ", fileSize - 8, " bytes that follow");
  std::string header(size_t(headerSize), '\0');
  if (headerSize > 0 && !in.read(header.data(), std::streamsize(headerSize)))
    fail("cannot read the header of safetensors file '", path, "'");
  dataStart_ = 8 + headerSize;
  const uint64_t dataSize = fileSize - dataStart_;

  const nlohmann::json json = parseJson(header, "safetensors file '" + path + "': header");
  if (!json.is_object())
    fail("safetensors file '", path, "': header is not a JSON object");

  for (auto it = json.begin(); it != json.end(); ++it) {
    const std::string& key = it.key();
    const nlohmann::json& entry = it.value();
    if (key == "__metadata__") {
      if (!entry.is_object())
        fail("safetensors file '", path, "': '__metadata__' is not an object");
      for (auto m = entry.begin(); m != entry.end(); ++m) {
        if (!m.value().is_string())
          fail("safetensors file '", path, "': '__metadata__' value of '", m.key(),
               "' is not a string");
        metadata_[m.key()] = m.value().get<std::string>();
      }
      continue;
    }
    auto bad = [&](const char* field, const nlohmann::json& value) {
      fail("safetensors file '", path, "', tensor '", key, "': invalid '", field, "' ",
           jsonExcerpt(value));
    };
    if (!entry.is_object())
      bad("entry", entry);
    SafeTensorInfo info;
    const auto dtype = entry.find("dtype");
    if (dtype == entry.end() || !dtype->is_string())
      bad("dtype", dtype == entry.end() ? nlohmann::json() : *dtype);
    info.dtype = dtype->get<std::string>();
    const int elementSize = dtypeSize(info.dtype);
    if (elementSize == 0)
      bad("dtype", *dtype);
    const auto shape = entry.find("shape");
    if (shape == entry.end() || !shape->is_array())
      bad("shape", shape == entry.end() ? nlohmann::json() : *shape);
    uint64_t numel = 1;
    for (const auto& d : *shape) {
      if (!d.is_number_integer() || d.get<int64_t>() < 0)
        bad("shape", *shape);
      const uint64_t dim = d.get<uint64_t>();
      if (dim != 0 && numel > dataSize / dim)
        bad("shape (larger than the file)", *shape);
      numel *= dim;
      info.shape.push_back(int64_t(dim));
    }
    const auto offsets = entry.find("data_offsets");
    if (offsets == entry.end() || !offsets->is_array() || offsets->size() != 2 ||
        !(*offsets)[0].is_number_unsigned() || !(*offsets)[1].is_number_unsigned())
      bad("data_offsets", offsets == entry.end() ? nlohmann::json() : *offsets);
    info.begin = (*offsets)[0].get<uint64_t>();
    info.end = (*offsets)[1].get<uint64_t>();
    if (info.begin > info.end || info.end > dataSize)
      fail("safetensors file '", path, "', tensor '", key, "': data_offsets [", info.begin, ", ",
           info.end, "] outside the data section of ", dataSize, " bytes (file truncated?)");
    if (info.end - info.begin != numel * uint64_t(elementSize))
      fail("safetensors file '", path, "', tensor '", key, "': data_offsets [", info.begin, ", ",
           info.end, "] span ", info.end - info.begin, " bytes, but shape ", shape->dump(), " of ",
           info.dtype, " needs ", numel * uint64_t(elementSize));
    tensors_.emplace(key, std::move(info));
  }
}

std::vector<std::string> SafeTensorsReader::keys() const {
  std::vector<std::string> out;
  for (const auto& kv : tensors_)
    out.push_back(kv.first);
  return out;
}

const SafeTensorInfo& SafeTensorsReader::info(const std::string& key) const {
  const auto it = tensors_.find(key);
  if (it == tensors_.end())
    fail("safetensors file '", path_, "' has no tensor '", key, "'");
  return it->second;
}

std::vector<unsigned char> SafeTensorsReader::readRaw(const std::string& key,
                                                      const SafeTensorInfo& info) const {
  std::ifstream in(path_, std::ios::binary);
  if (!in)
    fail("cannot open safetensors file '", path_, "' to read tensor '", key, "'");
  std::vector<unsigned char> bytes(size_t(info.end - info.begin));
  in.seekg(std::streamoff(dataStart_ + info.begin));
  if (!bytes.empty() &&
      !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size())))
    fail("cannot read tensor '", key, "' from safetensors file '", path_, "'");
  return bytes;
}

namespace {
// Little-endian values of one tensor's raw bytes (sizes were checked against the shape when
// the header was parsed).
template <typename T>
HostTensor<T> decodeTensor(const SafeTensorInfo& info, const std::vector<unsigned char>& raw) {
  HostTensor<T> t;
  t.shape = info.shape;
  t.data.resize(raw.size() / sizeof(T));
  for (size_t k = 0; k < t.data.size(); ++k)
    t.data[k] = decode<T>(raw.data() + sizeof(T) * k);
  return t;
}
} // namespace

HostTensor<float> SafeTensorsReader::readF32(const std::string& key) const {
  const SafeTensorInfo& i = info(key);
  if (i.dtype != "F32")
    fail("safetensors file '", path_, "', tensor '", key, "': dtype ", i.dtype, ", expected F32");
  return decodeTensor<float>(i, readRaw(key, i));
}

HostTensor<double> SafeTensorsReader::readF64(const std::string& key) const {
  const SafeTensorInfo& i = info(key);
  HostTensor<double> t;
  t.shape = i.shape;
  if (i.dtype == "F32") {
    const HostTensor<float> f = readF32(key);
    t.data.assign(f.data.begin(), f.data.end());
    return t;
  }
  if (i.dtype != "F64")
    fail("safetensors file '", path_, "', tensor '", key, "': dtype ", i.dtype,
         ", expected F64 or F32");
  return decodeTensor<double>(i, readRaw(key, i));
}

HostTensor<int64_t> SafeTensorsReader::readI64(const std::string& key) const {
  const SafeTensorInfo& i = info(key);
  if (i.dtype != "I64")
    fail("safetensors file '", path_, "', tensor '", key, "': dtype ", i.dtype, ", expected I64");
  return decodeTensor<int64_t>(i, readRaw(key, i));
}

namespace {
template <typename T> SafeTensorEntry makeEntryImpl(const HostTensor<T>& t, const char* dtype) {
  if (int64_t(t.data.size()) != t.numel())
    fail("safetensors entry: shape has ", t.numel(), " elements, data has ", t.data.size());
  SafeTensorEntry e;
  e.dtype = dtype;
  e.shape = t.shape;
  e.bytes.reserve(t.data.size() * sizeof(T));
  for (T v : t.data)
    encode(v, e.bytes);
  return e;
}
} // namespace

SafeTensorEntry makeEntry(const HostTensor<float>& t) {
  return makeEntryImpl(t, "F32");
}
SafeTensorEntry makeEntry(const HostTensor<double>& t) {
  return makeEntryImpl(t, "F64");
}
SafeTensorEntry makeEntry(const HostTensor<int64_t>& t) {
  return makeEntryImpl(t, "I64");
}

void writeSafeTensors(const std::string& path,
                      const std::map<std::string, SafeTensorEntry>& tensors,
                      const std::map<std::string, std::string>& metadata) {
  nlohmann::json header = nlohmann::json::object();
  if (!metadata.empty())
    header["__metadata__"] = metadata;
  uint64_t offset = 0;
  for (const auto& [key, entry] : tensors) {
    if (key == "__metadata__")
      fail("writeSafeTensors '", path, "': '__metadata__' is reserved, not a tensor name");
    const int size = dtypeSize(entry.dtype);
    uint64_t numel = 1;
    for (int64_t d : entry.shape) {
      if (d < 0)
        fail("writeSafeTensors '", path, "': tensor '", key, "' has a negative dimension");
      numel *= uint64_t(d);
    }
    if (size == 0 || numel * uint64_t(size) != entry.bytes.size())
      fail("writeSafeTensors '", path, "': tensor '", key, "' (", entry.dtype, ") has ",
           entry.bytes.size(), " bytes, expected ", numel * uint64_t(size));
    header[key] = {{"dtype", entry.dtype},
                   {"shape", entry.shape},
                   {"data_offsets", {offset, offset + entry.bytes.size()}}};
    offset += entry.bytes.size();
  }
  std::string text = header.dump();
  text.append((8 - text.size() % 8) % 8, ' ');
  std::vector<unsigned char> bytes;
  bytes.reserve(8 + text.size() + offset);
  encode<uint64_t>(text.size(), bytes);
  bytes.insert(bytes.end(), text.begin(), text.end());
  for (const auto& kv : tensors)
    bytes.insert(bytes.end(), kv.second.bytes.begin(), kv.second.bytes.end());
  writeFileAtomically(path, bytes.data(), bytes.size());
}

} // namespace simpli::io

#pragma once
// safetensors files (https://huggingface.co/docs/safetensors): 8-byte little-endian header
// length N, N bytes of JSON {name: {"dtype", "shape", "data_offsets": [begin, end]}, optional
// "__metadata__": {string: string}}, then the raw little-endian, C-contiguous data.
// Used for the golden conformance tensors and for network weights (reference key names).
//
// The header is read and fully validated when the file is opened (dtype known, shape
// non-negative, offsets inside the data section and equal to the element count times the
// element size); tensor data are read on demand. Errors name the file and the key.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace simpli::io {

template <typename T> struct HostTensor {
  std::vector<int64_t> shape;
  std::vector<T> data; ///< row-major

  int64_t numel() const {
    int64_t n = 1;
    for (int64_t d : shape)
      n *= d;
    return n;
  }
};

struct SafeTensorInfo {
  std::string dtype;           ///< as stored: "F32", "F64", "I64", "F16", ...
  std::vector<int64_t> shape;  ///< PyTorch dimension order
  uint64_t begin = 0, end = 0; ///< byte range relative to the start of the data section
};

class SafeTensorsReader {
public:
  /// Opens the file and parses its header; throws simpli::Error naming the file on any problem.
  explicit SafeTensorsReader(const std::string& path);

  const std::string& path() const { return path_; }
  std::vector<std::string> keys() const; ///< sorted
  bool contains(const std::string& key) const { return tensors_.count(key) != 0; }
  const SafeTensorInfo& info(const std::string& key) const; ///< throws for an unknown key
  const std::map<std::string, std::string>& metadata() const { return metadata_; }

  HostTensor<float> readF32(const std::string& key) const;   ///< dtype must be F32
  HostTensor<double> readF64(const std::string& key) const;  ///< F64, or F32 widened exactly
  HostTensor<int64_t> readI64(const std::string& key) const; ///< dtype must be I64

private:
  std::vector<unsigned char> readRaw(const std::string& key, const SafeTensorInfo& info) const;

  std::string path_;
  uint64_t dataStart_ = 0;
  std::map<std::string, SafeTensorInfo> tensors_;
  std::map<std::string, std::string> metadata_;
};

/// A tensor to write: dtype "F32", "F64" or "I64" and the raw little-endian bytes.
struct SafeTensorEntry {
  std::string dtype;
  std::vector<int64_t> shape;
  std::vector<unsigned char> bytes;
};
SafeTensorEntry makeEntry(const HostTensor<float>& t);
SafeTensorEntry makeEntry(const HostTensor<double>& t);
SafeTensorEntry makeEntry(const HostTensor<int64_t>& t);

/// Writes a safetensors file atomically (temporary file, then rename). Tensors are stored in
/// key order; the header is padded with spaces to a multiple of 8 bytes.
void writeSafeTensors(const std::string& path,
                      const std::map<std::string, SafeTensorEntry>& tensors,
                      const std::map<std::string, std::string>& metadata = {});

} // namespace simpli::io

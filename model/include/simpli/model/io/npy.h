#pragma once
// NumPy .npy files (format versions 1.0, 2.0 and 3.0) holding little-endian float64 ('<f8') or
// float32 ('<f4') arrays in C or Fortran order. Everything else (big-endian, integers, objects,
// structured dtypes, truncated data, malformed headers) is rejected with a simpli::Error naming
// the file, the field and the value.
#include <cstddef>
#include <string>
#include <vector>

namespace simpli::io {

struct NpyArray {
  std::vector<size_t> shape;
  std::vector<double> data; ///< row-major (C order) regardless of the file's order
  std::string descr;        ///< dtype as stored: "<f8" or "<f4"

  size_t size() const { return data.size(); }
  /// Element of a 2-D array (row-major).
  double at(size_t row, size_t col) const { return data[row * shape[1] + col]; }
};

/// Reads a .npy file into doubles (float32 values are widened exactly).
NpyArray readNpy(const std::string& path);

/// Parses .npy file contents; `path` is only used in error messages.
NpyArray parseNpy(const unsigned char* bytes, size_t size, const std::string& path);

/// Writes a row-major float64 array as a version 1.0 .npy file ('<f8', C order), atomically.
void writeNpy(const std::string& path, const std::vector<double>& data,
              const std::vector<size_t>& shape);

} // namespace simpli::io

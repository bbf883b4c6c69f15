#pragma once
// The element types of the engine: float32 for work, float64 for reference runs of the same
// kernels (every kernel compiles for both; kernels/common.cl defines REAL accordingly).
#include <cstddef>
#include <string>

namespace simpli::ocl {

enum class Dtype { F32, F64 };

/// "f32" or "f64".
inline std::string toString(Dtype dtype) {
  return dtype == Dtype::F32 ? "f32" : "f64";
}

/// Bytes per element: 4 or 8.
constexpr std::size_t sizeOf(Dtype dtype) {
  return dtype == Dtype::F32 ? 4 : 8;
}

} // namespace simpli::ocl

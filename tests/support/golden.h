#pragma once
// Access to the golden conformance tensors (SIMPLI_GOLDEN_DIR, default ../shared/golden outside
// the repository: tensors of the reference implementation with random weights, see its
// README.md), the conversion of their cameras, and the comparison metric they were measured
// with: rel = max|x - ref| / max|ref| per tensor.
#include "simpli/model/io/safetensors.h"
#include "simpli/model/scene/camera.h"
#include "simpli/ocl/tensor.h"

#include <gtest/gtest.h>

#include <ostream>
#include <string>

namespace simpli::test {

std::string goldenDir();
/// True when every golden file the network tests read is present.
bool goldenAvailable();

/// Skips the current test (with the reason) when the golden folder is absent.
#define SIMPLI_REQUIRE_GOLDEN()                                                                    \
  do {                                                                                             \
    if (!::simpli::test::goldenAvailable())                                                        \
      GTEST_SKIP() << "golden data not found in " << ::simpli::test::goldenDir();                  \
  } while (0)

/// A camera in the golden files' layout: `extrinsics` a row-major [3, 4] world-to-camera
/// [R | t], `intrinsics` a row-major [3, 3] K relative to the image size (fx, cx / fy, cy at
/// 0, 2 / 4, 5); width x height as given (0 x 0: unset, for geometry that ignores them).
scene::Camera goldenCamera(const double* extrinsics, const double* intrinsics, int width = 0,
                           int height = 0);

/// Readers of the golden files (opened once).
const io::SafeTensorsReader& goldenFile(const std::string& name); ///< "micro", "stages", ...

/// A golden tensor on the device in `dtype` (float32 values widened exactly for F64).
ocl::Tensor goldenTensor(const std::string& file, const std::string& key, ocl::Dtype dtype);

/// The measured float32-vs-float64 error (rel_to_max) of a stage in tolerances.json, section
/// "micro" or "module_level".
double measuredError(const std::string& section, const std::string& name);

/// max|got - ref| / max|ref| over all elements; shapes must be equal.
double relToMax(const ocl::Tensor& got, const ocl::Tensor& ref);

/// Expects relToMax(got, ref) <= tol, printing the error (for the conformance report).
void expectGoldenClose(const std::string& what, const ocl::Tensor& got, const ocl::Tensor& ref,
                       double tol);

/// The reference's suggested tolerance: 10 x the measured float32 error of the stage (an
/// independent float32 implementation has its own rounding of the same size as the golden's).
inline double goldenTolerance(const std::string& section, const std::string& name) {
  return 10.0 * measuredError(section, name);
}

} // namespace simpli::test

namespace simpli::ocl {
/// Readable test names for dtype-parameterised tests ("... GetParam() = f32").
inline void PrintTo(Dtype dtype, std::ostream* os) {
  *os << toString(dtype);
}
} // namespace simpli::ocl

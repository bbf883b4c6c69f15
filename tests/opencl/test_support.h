#pragma once
// Small helpers shared by the engine's test files (the op harness itself is op_harness.h).
#include "op_harness.h"

#include "simpli/error.h"
#include "simpli/ocl/gemm_backend.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace simpli::test {

/// Expects `f` to throw simpli::Error whose message contains every one of `parts`.
inline void expectError(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "expected simpli::Error";
  } catch (const Error& e) {
    for (const auto& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos)
          << "message '" << e.what() << "' lacks '" << p << "'";
  }
}

/// Worst errors over a test's harness cases, printed once per test (for the logs).
struct WorstErrors {
  const char* what;
  double forward = 0.0, gradient = 0.0;
  void add(const OpReport& r) {
    forward = std::max(forward, r.forwardError);
    gradient = std::max(gradient, r.gradientError);
  }
  ~WorstErrors() {
    std::printf("%s: worst f32 forward error %.2e, worst f64 gradient error %.2e\n", what, forward,
                gradient);
  }
};

/// A test run once per GEMM backend (simpli/ocl/gemm_backend.h): derive a fixture, write
/// TEST_P(Fixture, Name) and instantiate it with SIMPLI_GEMM_BACKENDS(Fixture). The case names
/// end in /host or /clblast.
class GemmBackendTest : public ::testing::TestWithParam<ocl::GemmBackend> {
protected:
  void SetUp() override { previous_ = ocl::setGemmBackend(GetParam()); }
  void TearDown() override { ocl::setGemmBackend(previous_); }

private:
  ocl::GemmBackend previous_ = ocl::GemmBackend::Auto;
};

inline std::string gemmBackendName(const ::testing::TestParamInfo<ocl::GemmBackend>& info) {
  return ocl::toString(info.param);
}

#define SIMPLI_GEMM_BACKENDS(Fixture)                                                              \
  INSTANTIATE_TEST_SUITE_P(                                                                        \
      Backends, Fixture,                                                                           \
      ::testing::Values(::simpli::ocl::GemmBackend::Host, ::simpli::ocl::GemmBackend::Clblast),    \
      ::simpli::test::gemmBackendName)

} // namespace simpli::test

#pragma once
// Small helpers shared by the engine's test files (the op harness itself is op_harness.h).
#include "op_harness.h"

#include "simpli/error.h"

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

} // namespace simpli::test

// The harness must be able to fail: a wrong reference, a wrong gradient and an unwritten
// output element each produce a failure.
#include "op_harness.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

using namespace simpli;
using namespace simpli::test;

namespace {

OpCase squareCase() {
  OpCase c;
  c.name = "square";
  c.inputShapes = {{3, 4}};
  c.device = [](const std::vector<ocl::Tensor>& in) { return ocl::square(in[0]); };
  c.reference = [](const HostInputs& in) {
    std::vector<double> out(in[0].size());
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = in[0][i] * in[0][i];
    return out;
  };
  return c;
}

// Runs the case with failures captured; true when one of them mentions `needle`.
bool failsWith(const OpCase& c, const std::string& needle) {
  ::testing::TestPartResultArray results;
  {
    ::testing::ScopedFakeTestPartResultReporter reporter(
        ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &results);
    checkOp(c);
  }
  for (int i = 0; i < results.size(); ++i)
    if (std::string(results.GetTestPartResult(i).message()).find(needle) != std::string::npos)
      return true;
  return false;
}

} // namespace

TEST(HarnessSelfTest, CorrectCasePasses) {
  checkOp(squareCase());
}

TEST(HarnessSelfTest, WrongReferenceFails) {
  OpCase c = squareCase();
  c.reference = [](const HostInputs& in) {
    std::vector<double> out(in[0].size());
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = in[0][i] * in[0][i] * (1 + 1e-4);
    return out;
  };
  EXPECT_TRUE(failsWith(c, "float32 forward vs double reference"));
}

TEST(HarnessSelfTest, WrongGradientFails) {
  OpCase c = squareCase();
  c.device = [](const std::vector<ocl::Tensor>& in) {
    ocl::Tensor y;
    {
      ocl::NoGradGuard off;
      y = ocl::square(in[0].detach());
    }
    // Deliberately wrong backward: d(x^2)/dx = 2x, we return x.
    return ocl::record("wrongSquare", y, {in[0]}, [x = in[0].detach()](const ocl::Tensor& g) {
      return std::vector<ocl::Tensor>{ocl::mul(g, x)};
    });
  };
  EXPECT_TRUE(failsWith(c, "float64 backward vs central finite differences"));
}

TEST(HarnessSelfTest, UnwrittenElementShowsAsNaN) {
  OpCase c = squareCase();
  c.device = [](const std::vector<ocl::Tensor>& in) {
    // Returns a fresh (poisoned) buffer without writing it.
    return ocl::Tensor::empty(in[0].shape(), in[0].dtype());
  };
  c.differentiable = {false};
  EXPECT_TRUE(failsWith(c, "float32 forward vs double reference"));
}

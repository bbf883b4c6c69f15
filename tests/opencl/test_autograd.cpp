// Tape semantics: accumulation, shared subexpressions, no-grad mode, clipping, errors.
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/program_cache.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace simpli;
using ocl::Dtype;
using ocl::Tensor;

TEST(Autograd, GradientsAccumulateAcrossBackwardCalls) {
  Tensor x = Tensor::fromHost(std::vector<double>{1, -2, 3}, {3}, Dtype::F64);
  x.setRequiresGrad();
  ocl::sumAll(ocl::mulScalar(x, 3.0)).backward();
  ocl::sumAll(ocl::square(x)).backward();
  const auto g = x.grad().toVector();
  EXPECT_DOUBLE_EQ(g[0], 3 + 2 * 1);
  EXPECT_DOUBLE_EQ(g[1], 3 + 2 * -2);
  EXPECT_DOUBLE_EQ(g[2], 3 + 2 * 3);
  x.zeroGrad();
  EXPECT_DOUBLE_EQ(x.grad().toVector()[1], 0.0);
}

TEST(Autograd, SharedSubexpressionSumsBothPaths) {
  // y = a*b + a*a: dy/da = b + 2a, dy/db = a.
  Tensor a = Tensor::fromHost(std::vector<double>{0.5, -1.5}, {2}, Dtype::F64);
  Tensor b = Tensor::fromHost(std::vector<double>{2.0, 4.0}, {2}, Dtype::F64);
  a.setRequiresGrad();
  b.setRequiresGrad();
  Tensor y = ocl::add(ocl::mul(a, b), ocl::mul(a, a));
  ocl::sumAll(y).backward();
  EXPECT_DOUBLE_EQ(a.grad().toVector()[0], 2.0 + 1.0);
  EXPECT_DOUBLE_EQ(a.grad().toVector()[1], 4.0 - 3.0);
  EXPECT_DOUBLE_EQ(b.grad().toVector()[1], -1.5);
}

TEST(Autograd, NoGradModeRecordsNothing) {
  Tensor x = Tensor::ones({4}).setRequiresGrad();
  ocl::NoGradGuard off;
  Tensor y = ocl::mul(x, x);
  EXPECT_FALSE(y.requiresGrad());
  EXPECT_FALSE(y.hasGradFn());
}

TEST(Autograd, InferenceFreesIntermediates) {
  auto& pool = ocl::Device::current().pool();
  Tensor x = Tensor::uniform({256, 256}, -1, 1, 7);
  ocl::NoGradGuard off;
  pool.resetPeak();
  const auto base = pool.stats().liveBytes;
  Tensor y = x;
  for (int i = 0; i < 20; ++i)
    y = ocl::tanh(ocl::mulScalar(y, 1.1));
  // Each step keeps at most the previous and the new result alive (plus a temporary).
  EXPECT_LE(pool.stats().peakBytes - base, 3 * x.bytes());
  EXPECT_GT(pool.stats().reuses, 0u);
}

TEST(Autograd, BackwardErrorsNameTheProblem) {
  Tensor x = Tensor::ones({3}).setRequiresGrad();
  Tensor y = ocl::mulScalar(x, 2.0);
  EXPECT_THROW(y.backward(), Error); // not a scalar
  Tensor c = Tensor::ones({1});
  EXPECT_THROW(c.backward(), Error);        // nothing requires gradients
  EXPECT_THROW(y.setRequiresGrad(), Error); // not a leaf
}

TEST(Autograd, ClipGradNormScalesToMaxNorm) {
  Tensor a = Tensor::fromHost(std::vector<double>{3, 0}, {2}, Dtype::F64).setRequiresGrad();
  Tensor b = Tensor::fromHost(std::vector<double>{0, 4}, {2}, Dtype::F64).setRequiresGrad();
  ocl::sumAll(ocl::add(ocl::mul(a, a), ocl::mul(b, b))).backward(); // grads (6,0), (0,8)
  const double norm = ocl::clipGradNorm({a, b}, 5.0);
  EXPECT_NEAR(norm, 10.0, 1e-12);
  EXPECT_NEAR(a.grad().toVector()[0], 3.0, 1e-6);
  EXPECT_NEAR(b.grad().toVector()[1], 4.0, 1e-6);
  // Below the limit nothing changes.
  EXPECT_NEAR(ocl::clipGradNorm({a, b}, 100.0), 5.0, 1e-5);
  EXPECT_NEAR(a.grad().toVector()[0], 3.0, 1e-6);
}

TEST(Tensor, RandomIsReproducibleAndPrecisionIndependent) {
  Tensor u1 = Tensor::uniform({1000}, -1, 1, 42), u2 = Tensor::uniform({1000}, -1, 1, 42);
  Tensor u3 = Tensor::uniform({1000}, -1, 1, 43);
  Tensor u64 = Tensor::uniform({1000}, -1, 1, 42, Dtype::F64);
  const auto v1 = u1.toVector(), v2 = u2.toVector(), v3 = u3.toVector(), v64 = u64.toVector();
  EXPECT_EQ(v1, v2);
  EXPECT_NE(v1, v3);
  double mean = 0.0;
  for (std::size_t i = 0; i < v1.size(); ++i) {
    EXPECT_NEAR(v1[i], v64[i], 1e-6);
    EXPECT_GE(v1[i], -1.0);
    EXPECT_LT(v1[i], 1.0);
    mean += v1[i] / v1.size();
  }
  EXPECT_NEAR(mean, 0.0, 0.1);
  Tensor n = Tensor::normal({20000}, 2.0, 3.0, 5);
  double m = 0, s = 0;
  for (double x : n.toVector())
    m += x / 20000.0;
  for (double x : n.toVector())
    s += (x - m) * (x - m) / 19999.0;
  EXPECT_NEAR(m, 2.0, 0.1);
  EXPECT_NEAR(std::sqrt(s), 3.0, 0.1);
}

TEST(Tensor, HostRoundTripAndConversion) {
  std::vector<double> v = {1.5, -2.25, 1e-3, 7};
  Tensor t = Tensor::fromHost(v, {2, 2}, Dtype::F64);
  EXPECT_EQ(t.toVector(), v);
  Tensor f = t.to(Dtype::F32);
  EXPECT_EQ(f.dtype(), Dtype::F32);
  EXPECT_NEAR(f.toVector()[2], 1e-3, 1e-10);
  EXPECT_EQ(f.to(Dtype::F64).toVector()[1], -2.25);
  EXPECT_EQ(Tensor::arange(4, 1.0, 0.5).toVector(), (std::vector<double>{1, 1.5, 2, 2.5}));
  EXPECT_THROW(t.item(), Error);
  EXPECT_EQ(Tensor::full({1}, 3.0).item(), 3.0);
}

TEST(ProgramCache, BuildsEachProgramOncePerPrecision) {
  auto& programs = ocl::Device::current().programs();
  ocl::relu(Tensor::ones({3}));
  ocl::relu(Tensor::ones({3}, Dtype::F64));
  const int before = programs.builtPrograms();
  for (int i = 0; i < 3; ++i) {
    ocl::relu(Tensor::ones({5}));
    ocl::relu(Tensor::ones({5}, Dtype::F64));
  }
  EXPECT_EQ(programs.builtPrograms(), before);
  EXPECT_THROW(programs.kernel("no_such_program", "k", Dtype::F32), Error);
  EXPECT_THROW(programs.kernel("elementwise", "no_such_kernel", Dtype::F32), Error);
}

TEST(ProgramCache, BuildFailureShowsProgramKernelAndLog) {
  auto& programs = ocl::Device::current().programs();
  try {
    // A macro that turns a helper's name into a syntax error forces a compile failure.
    programs.kernel("elementwise", "fill", Dtype::F32, "-Dstable_sigmoid=@@");
    FAIL() << "expected a build failure";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("elementwise"), std::string::npos) << what;
    EXPECT_NE(what.find("fill"), std::string::npos) << what;
    EXPECT_NE(what.find("CL_BUILD_PROGRAM_FAILURE"), std::string::npos) << what;
    EXPECT_GT(what.size(), 200u) << "the compiler log should be part of the message: " << what;
  }
}

// kernels/*.h are embedded by file name and spliced in at `#include "x.h"`; line numbers after
// the include stay those of the including file; an unknown header or a cycle is a named error.
TEST(ProgramCache, SplicesEmbeddedHeadersAndNamesUnknownOnes) {
  ocl::registerKernelSources({
      {"test_include_ok", "#include \"elementwise_op_codes.h\"\n"
                          "__kernel void k(__global REAL* out) { out[0] = U_POW_SCALAR; }\n"},
      {"test_include_bad_line", "#include \"elementwise_op_codes.h\"\n"
                                "__kernel void k(__global REAL* out) { out[0] = @@; }\n"},
      {"test_include_unknown", "#include \"no_such_header.h\"\n__kernel void k() {}\n"},
      {"test_include_cycle.h", "#include \"test_include_cycle.h\"\n"},
      {"test_include_cycle", "#include \"test_include_cycle.h\"\n__kernel void k() {}\n"},
  });
  Tensor out = Tensor::zeros({1});
  ocl::Launch("test_include_ok", "k", Dtype::F32).arg(out).run(1);
  EXPECT_EQ(out.item(), 14.0) << "U_POW_SCALAR from kernels/elementwise_op_codes.h";

  auto& programs = ocl::Device::current().programs();
  const auto message = [&](const char* program) {
    try {
      programs.kernel(program, "k", Dtype::F32);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string badLine = message("test_include_bad_line");
  EXPECT_NE(badLine.find(":2:"), std::string::npos)
      << "error on line 2 of the program: " << badLine;
  const std::string unknown = message("test_include_unknown");
  EXPECT_NE(unknown.find("test_include_unknown"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("\"no_such_header.h\", which is not embedded"), std::string::npos)
      << unknown;
  const std::string cycle = message("test_include_cycle");
  EXPECT_NE(cycle.find("nested deeper than"), std::string::npos) << cycle;
}

TEST(Device, SelectorParsingAndBadIndices) {
  EXPECT_EQ(ocl::Device::parseSelector("1:2", "test"), std::make_pair(1, 2));
  EXPECT_THROW(ocl::Device::parseSelector("x", "SIMPLI_CL_DEVICE"), Error);
  EXPECT_THROW(ocl::Device::parseSelector("0:", "SIMPLI_CL_DEVICE"), Error);
  EXPECT_THROW(ocl::Device::parseSelector("0:0:1", "SIMPLI_CL_DEVICE"), Error);
  try {
    ocl::Device::parseSelector("abc", "SIMPLI_CL_DEVICE");
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("SIMPLI_CL_DEVICE"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("abc"), std::string::npos);
  }
  const auto devices = ocl::listDevices();
  ASSERT_FALSE(devices.empty());
  EXPECT_FALSE(devices[0].deviceName.empty());
}

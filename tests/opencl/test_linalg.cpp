// matmul (plain, transposed, batched, broadcast batches) and linear through the harness; the
// CLBlast tuning table parser and its device matching.
#include "op_harness.h"
#include "test_support.h"

#include "../../opencl/src/tuning.h" // internal: the tuning-table parser under test

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/gemm_backend.h"
#include "simpli/ocl/ops_linalg.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/profiler.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;

namespace {

// op(A_b) op(B_b) for row-major host data; a batch of 1 (or a rank-2 operand) is shared.
std::vector<double> matmulRef(const HostInputs& in, const Shape& sa, const Shape& sb, bool ta,
                              bool tb) {
  const int64_t ba = sa.size() == 3 ? sa[0] : 1, bb = sb.size() == 3 ? sb[0] : 1;
  const int64_t ra = sa[sa.size() - 2], ca = sa.back(), rb = sb[sb.size() - 2], cb = sb.back();
  const int64_t m = ta ? ca : ra, k = ta ? ra : ca, n = tb ? rb : cb;
  const int64_t batch = std::max(ba, bb);
  std::vector<double> out(static_cast<std::size_t>(batch * m * n), 0.0);
  for (int64_t b = 0; b < batch; ++b) {
    const double* A = in[0].data() + (ba == 1 ? 0 : b * ra * ca);
    const double* B = in[1].data() + (bb == 1 ? 0 : b * rb * cb);
    for (int64_t i = 0; i < m; ++i)
      for (int64_t j = 0; j < n; ++j) {
        double s = 0;
        for (int64_t p = 0; p < k; ++p)
          s += (ta ? A[p * ca + i] : A[i * ca + p]) * (tb ? B[j * cb + p] : B[p * cb + j]);
        out[static_cast<std::size_t>((b * m + i) * n + j)] = s;
      }
  }
  return out;
}

struct MatmulShape {
  Shape a, b;
  bool ta, tb;
};

void checkMatmul(const MatmulShape& s, int probes = 24) {
  OpCase c;
  c.name = "matmul " + ocl::toString(s.a) + (s.ta ? "^T" : "") + " x " + ocl::toString(s.b) +
           (s.tb ? "^T" : "");
  c.inputShapes = {s.a, s.b};
  c.device = [s](const std::vector<ocl::Tensor>& in) {
    return ocl::matmul(in[0], in[1], s.ta, s.tb);
  };
  c.reference = [s](const HostInputs& in) { return matmulRef(in, s.a, s.b, s.ta, s.tb); };
  c.maxGradientProbes = probes;
  checkOp(c);
}

// Every GEMM test runs on both backends: the host BLAS and CLBlast with the skinny kernels.
class LinalgGemm : public GemmBackendTest {};
SIMPLI_GEMM_BACKENDS(LinalgGemm);

} // namespace

TEST_P(LinalgGemm, MatmulAgainstReference) {
  const MatmulShape cases[] = {
      {{1, 1}, {1, 1}, false, false},   {{3, 5}, {5, 4}, false, false},
      {{7, 13}, {13, 1}, false, false}, {{1, 9}, {9, 11}, false, false},
      {{5, 3}, {5, 4}, true, false},    {{3, 5}, {4, 5}, false, true},
      {{5, 3}, {4, 5}, true, true},     {{17, 33}, {33, 19}, false, false},
  };
  for (const auto& s : cases)
    checkMatmul(s);
}

TEST_P(LinalgGemm, MatmulLargeEnoughForTheIndirectKernel) {
  // Sizes past CLBlast's direct/indirect switch and not multiples of any work-group tile, so
  // the padding and transposition helper kernels run too.
  checkMatmul({{130, 301}, {301, 257}, false, false}, 8);
  checkMatmul({{301, 130}, {257, 301}, true, true}, 8);
  checkMatmul({{3, 70, 129}, {3, 129, 66}, false, false}, 8);
  // Batched GEMMs past the switch point of both precisions (m n k > 256^3 in the shipped
  // table), also with a shared operand (stride 0) and transposes.
  checkMatmul({{2, 260, 257}, {2, 257, 258}, false, false}, 6);
  checkMatmul({{2, 257, 260}, {257, 258}, true, false}, 6);
  checkMatmul({{260, 257}, {2, 258, 257}, false, true}, 6);
}

TEST_P(LinalgGemm, SkinnyGemmsAgainstReference) {
  // One dimension <= 32: the engine's register-blocked kernels (gemm_skinny.cl) instead of
  // CLBlast, for every register block (4, 8, 16, 32), both kernels (few rows / few columns),
  // transposes, batches and a shared operand.
  checkMatmul({{4, 37}, {37, 700}, false, false}, 8);       // few rows, block 4
  checkMatmul({{37, 20}, {37, 300}, true, false}, 8);       // few rows, block 32, A^T
  checkMatmul({{300, 9}, {600, 300}, true, true}, 8);       // few rows, block 16, A^T B^T
  checkMatmul({{700, 37}, {31, 37}, false, true}, 8);       // few columns, block 32, B^T
  checkMatmul({{500, 7}, {7, 8}, false, false}, 8);         // few columns, block 8
  checkMatmul({{3, 6, 40}, {3, 40, 500}, false, false}, 8); // batched, few rows
  checkMatmul({{2, 400, 12}, {12, 5}, false, false}, 8);    // batched, shared B, few columns
  checkMatmul({{70, 20}, {20, 1100}, false, false}, 6);     // 70 rows in blocks of 32
  checkMatmul({{20, 70}, {20, 1100}, true, false}, 6);      // the same with A^T
  checkMatmul({{300, 40}, {9, 40}, false, true}, 6);        // few columns, vectors along k
  checkMatmul({{300, 21}, {5, 21}, false, true}, 6);        // ... with a tail
}

TEST_P(LinalgGemm, SplitKGemmsAgainstReference) {
  // Small outputs with a long inner dimension (weight gradients): k split into chunks reduced
  // in parallel (gemm_splitk.cl), as dot products (A, B^T) or outer products (any layout).
  checkMatmul({{16, 3000}, {144, 3000}, false, true}, 6);     // dot, 6 chunks
  checkMatmul({{5, 70}, {40, 70}, false, true}, 6);           // dot, one chunk with a tail
  checkMatmul({{3000, 5}, {3000, 7}, true, false}, 6);        // outer, A^T
  checkMatmul({{9, 2100}, {2100, 4}, false, false}, 6);       // outer, partial last chunk
  checkMatmul({{2, 4, 2500}, {2, 2500, 3}, false, false}, 6); // outer, batched
}

TEST_P(LinalgGemm, BatchedAndBroadcastMatmul) {
  const MatmulShape cases[] = {
      {{2, 3, 5}, {2, 5, 4}, false, false}, // plain batch
      {{1, 3, 5}, {4, 5, 2}, false, false}, // a shared (batch 1)
      {{3, 5}, {4, 5, 2}, false, false},    // a shared (rank 2)
      {{4, 3, 5}, {5, 2}, false, false},    // b shared: folded into one GEMM
      {{4, 3, 5}, {1, 5, 2}, false, false}, // b shared (batch 1)
      {{4, 5, 3}, {5, 2}, true, false},     // b shared, a transposed: strided batched
      {{2, 5, 3}, {2, 4, 5}, true, true},   // both transposed, batched
      {{3, 1, 7}, {3, 7, 1}, false, false}, // size-1 rows and columns
      {{1, 2, 3}, {1, 3, 4}, false, false}, // batch of one
  };
  for (const auto& s : cases)
    checkMatmul(s);
}

TEST_P(LinalgGemm, LinearAgainstReference) {
  struct L {
    Shape x;
    int64_t out;
    bool bias;
  };
  const L cases[] = {{{5}, 3, true},
                     {{2, 5}, 4, false},
                     {{2, 3, 5}, 4, true},
                     {{1, 1, 1}, 1, true},
                     {{3, 2, 7}, 1, false}};
  for (const auto& l : cases) {
    const int64_t in = l.x.back();
    OpCase c;
    c.name =
        "linear " + ocl::toString(l.x) + " -> " + std::to_string(l.out) + (l.bias ? " +bias" : "");
    c.inputShapes = {l.x, {l.out, in}};
    if (l.bias)
      c.inputShapes.push_back({l.out});
    c.device = [l](const std::vector<ocl::Tensor>& t) {
      return ocl::linear(t[0], t[1], l.bias ? t[2] : ocl::Tensor());
    };
    c.reference = [l, in](const HostInputs& h) {
      const int64_t rows = ocl::numelOf(l.x) / in;
      std::vector<double> out(static_cast<std::size_t>(rows * l.out));
      for (int64_t r = 0; r < rows; ++r)
        for (int64_t o = 0; o < l.out; ++o) {
          double s = l.bias ? h[2][o] : 0.0;
          for (int64_t i = 0; i < in; ++i)
            s += h[0][r * in + i] * h[1][o * in + i];
          out[static_cast<std::size_t>(r * l.out + o)] = s;
        }
      return out;
    };
    checkOp(c);
  }
  // Output shape keeps the leading dimensions.
  auto y = ocl::linear(ocl::Tensor::zeros({2, 3, 5}), ocl::Tensor::zeros({4, 5}));
  EXPECT_EQ(y.shape(), (Shape{2, 3, 4}));
}

TEST_P(LinalgGemm, EmptyInnerDimensionGivesZeros) {
  auto y = ocl::matmul(ocl::Tensor::zeros({3, 0}), ocl::Tensor::zeros({0, 2}));
  EXPECT_EQ(y.shape(), (Shape{3, 2}));
  for (double v : y.toVector())
    EXPECT_EQ(v, 0.0);
  EXPECT_EQ(ocl::matmul(ocl::Tensor::zeros({0, 4}), ocl::Tensor::zeros({4, 2})).numel(), 0);
}

TEST(Linalg, BadUseNamesOpAndShapes) {
  using ocl::Tensor;
  expectError(
      [] {
        ocl::matmul(Tensor::zeros({2, 3}), Tensor::zeros({4, 5}));
      },
      {"matmul", "[2, 3]", "[4, 5]"});
  expectError([] { ocl::matmul(Tensor::zeros({3}), Tensor::zeros({3, 5})); }, {"matmul", "[3]"});
  expectError(
      [] {
        ocl::matmul(Tensor::zeros({1, 2, 3, 4}), Tensor::zeros({4, 5}));
      },
      {"matmul", "[1, 2, 3, 4]"});
  expectError(
      [] {
        ocl::matmul(Tensor::zeros({2, 3, 4}), Tensor::zeros({3, 4, 5}));
      },
      {"matmul", "[2, 3, 4]", "[3, 4, 5]", "batch"});
  expectError(
      [] {
        ocl::matmul(Tensor::zeros({2, 3}), Tensor::zeros({3, 5}, Dtype::F64));
      },
      {"matmul", "dtype"});
  expectError([] { ocl::matmul(Tensor(), Tensor::zeros({3, 5})); }, {"matmul", "undefined"});
  expectError(
      [] {
        ocl::matmul(Tensor::zeros({2, 3}), Tensor::zeros({2, 5}), false, true);
      },
      {"matmul", "transposed", "[2, 5]"});
  expectError(
      [] {
        ocl::linear(Tensor::zeros({2, 3}), Tensor::zeros({4, 5}));
      },
      {"linear", "[2, 3]", "[4, 5]"});
  expectError(
      [] {
        ocl::linear(Tensor::zeros({2, 5}), Tensor::zeros({4, 5}), Tensor::zeros({5}));
      },
      {"linear", "bias", "[5]"});
  expectError(
      [] {
        ocl::linear(Tensor::zeros({2, 5}), Tensor::zeros({5}));
      },
      {"linear", "weight", "[5]"});
}

TEST_P(LinalgGemm, GradientFlowsOnlyWhereRequired) {
  auto a = ocl::Tensor::uniform({3, 4}, -1, 1, 1, Dtype::F64);
  auto b = ocl::Tensor::uniform({4, 2}, -1, 1, 2, Dtype::F64);
  b.setRequiresGrad(true);
  ocl::sumAll(ocl::matmul(a, b)).backward();
  EXPECT_FALSE(a.grad().defined());
  ASSERT_TRUE(b.grad().defined());
  // d sum(A B) / dB[k, n] = sum_m A[m, k]
  const auto av = a.toVector(), gb = b.grad().toVector();
  for (int k = 0; k < 4; ++k)
    for (int n = 0; n < 2; ++n)
      EXPECT_NEAR(gb[k * 2 + n], av[k] + av[4 + k] + av[8 + k], 1e-12);
}

// ---- the GEMM backend switch --------------------------------------------------------------

TEST(GemmBackend, ParsesNamesAndRejectsOthers) {
  for (auto b : {ocl::GemmBackend::Auto, ocl::GemmBackend::Host, ocl::GemmBackend::Clblast})
    EXPECT_EQ(ocl::parseGemmBackend(ocl::toString(b), "test"), b);
  expectError([] { ocl::parseGemmBackend("blas", "SIMPLI_GEMM"); },
              {"SIMPLI_GEMM", "'blas'", "auto, host or clblast"});
}

TEST(GemmBackend, AutoIsHostExactlyOnCpuDevices) {
  const auto previous = ocl::setGemmBackend(ocl::GemmBackend::Auto);
  cl_device_type type = 0;
  clGetDeviceInfo(ocl::Device::current().id(), CL_DEVICE_TYPE, sizeof(type), &type, nullptr);
  const bool cpu = (type & CL_DEVICE_TYPE_CPU) != 0;
  EXPECT_EQ(ocl::gemmBackend(), cpu ? ocl::GemmBackend::Host : ocl::GemmBackend::Clblast);
  const std::string summary = ocl::gemmBackendSummary();
  EXPECT_NE(summary.find("SIMPLI_GEMM=auto"), std::string::npos) << summary;
  EXPECT_NE(summary.find(cpu ? "host (" : "clblast ("), std::string::npos) << summary;
  ocl::setGemmBackend(previous);
}

TEST(GemmBackend, TheSelectedBackendRunsTheGemm) {
  // The profile names the routine that ran: host.Gemm or clblast.Gemm (or a skinny kernel).
  const bool wasProfiling = ocl::Profiler::enabled();
  ocl::Profiler::setEnabled(true);
  auto a = ocl::Tensor::uniform({64, 80}, -1, 1, 5), b = ocl::Tensor::uniform({80, 72}, -1, 1, 6);
  for (auto backend : {ocl::GemmBackend::Host, ocl::GemmBackend::Clblast}) {
    const auto previous = ocl::setGemmBackend(backend);
    ocl::Profiler::reset();
    ocl::matmul(a, b);
    ocl::Device::current().finish();
    const char* want =
        backend == ocl::GemmBackend::Host ? "host.Gemm NN 64x72x80" : "clblast.Gemm NN 64x72x80";
    const auto entries = ocl::Profiler::entries();
    EXPECT_TRUE(std::any_of(entries.begin(), entries.end(),
                            [&](const ocl::ProfileEntry& e) { return e.name == want; }))
        << "no profile entry " << want;
    ocl::setGemmBackend(previous);
  }
  ocl::Profiler::reset();
  ocl::Profiler::setEnabled(wasProfiling);
}

// ---- CLBlast tuning table -------------------------------------------------------------------

namespace {
const char* kGoodTable = R"({
  "format": "simpli-clblast-tuning/1",
  "clblast_device_name": "skylake-avx512-AMD EPYC",
  "opencl_device_names": ["pthread-skylake-avx512-AMD EPYC"],
  "kernels": [
    {"kernel": "Copy", "precision": 32,
     "parameters": {"COPY_DIMX": 8, "COPY_DIMY": 8, "COPY_VW": 4, "COPY_WPT": 1}}
  ]
})";
} // namespace

TEST(ClblastTuning, ParsesAndMatchesDeviceNames) {
  const auto table = ocl::parseTuningTable(kGoodTable, "good.json");
  EXPECT_EQ(table.clblastDeviceName, "skylake-avx512-AMD EPYC");
  ASSERT_EQ(table.entries.size(), 1u);
  EXPECT_EQ(table.entries[0].kernel, "Copy");
  EXPECT_EQ(table.entries[0].parameters.at("COPY_VW"), 4u);
  EXPECT_TRUE(ocl::tableMatches(table, "pthread-skylake-avx512-AMD EPYC"));
  EXPECT_TRUE(ocl::tableMatches(table, "cpu-skylake-avx512-AMD EPYC")); // PoCL >= 4 prefix
  EXPECT_TRUE(ocl::tableMatches(table, "skylake-avx512-AMD EPYC"));
  EXPECT_FALSE(ocl::tableMatches(table, "pthread-znver3-AMD EPYC"));
  EXPECT_FALSE(ocl::tableMatches(table, "xskylake-avx512-AMD EPYC"));
}

TEST(ClblastTuning, BadTablesNameFileFieldAndValue) {
  expectError([] { ocl::parseTuningTable("{", "t.json"); }, {"t.json", "invalid JSON"});
  expectError([] { ocl::parseTuningTable(R"({"format": "v0"})", "t.json"); },
              {"t.json", "format", "v0"});
  std::string unknown = kGoodTable;
  unknown.replace(unknown.find("\"Copy\""), 6, "\"Kopy\"");
  expectError([&] { ocl::parseTuningTable(unknown, "t.json"); },
              {"t.json", "kernels[0]", "kernel", "Kopy"});
  std::string negative = kGoodTable;
  negative.replace(negative.find("\"COPY_VW\": 4"), 12, "\"COPY_VW\": -4");
  expectError([&] { ocl::parseTuningTable(negative, "t.json"); },
              {"t.json", "kernels[0]", "COPY_VW", "-4"});
  std::string precision = kGoodTable;
  precision.replace(precision.find("\"precision\": 32"), 15, "\"precision\": 16");
  expectError([&] { ocl::parseTuningTable(precision, "t.json"); }, {"t.json", "precision", "16"});
  expectError(
      [] {
        ocl::parseTuningTable(
            R"({"format": "simpli-clblast-tuning/1", "clblast_device_name": "x", "kernels": []})",
            "t.json");
      },
      {"t.json", "kernels"});
}

TEST(ClblastTuning, EmbeddedTablesAreValidAndApplyCleanly) {
  for (const auto& [stem, text] : ocl::embeddedTuningTables()) {
    SCOPED_TRACE(stem);
    const auto table = ocl::parseTuningTable(text, stem);
    // Every shipped table tunes the whole GEMM routine, in both precisions.
    for (const char* kernel : {"Xgemm", "XgemmDirect", "Copy", "Pad", "Transpose", "Padtranspose"})
      for (int precision : {32, 64})
        EXPECT_TRUE(std::any_of(table.entries.begin(), table.entries.end(),
                                [&](const ocl::TuningEntry& e) {
                                  return e.kernel == kernel && e.precision == precision;
                                }))
            << kernel << " fp" << precision << " missing";
  }
  const std::string summary = ocl::clblastTuningSummary();
  EXPECT_EQ(summary.find("not applied"), std::string::npos) << summary;
  bool known = false;
  for (const auto& [stem, text] : ocl::embeddedTuningTables())
    known |= ocl::tableMatches(ocl::parseTuningTable(text, stem),
                               ocl::Device::current().info().deviceName);
  if (known)
    EXPECT_NE(summary.find("from opencl/tuning/"), std::string::npos) << summary;
  else
    EXPECT_NE(summary.find("no table"), std::string::npos) << summary;
}

// The kernel profiler: off by default (nothing recorded), on: every launch and GEMM counted
// under its name with a non-negative time; the report lists them.
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_linalg.h"
#include "simpli/ocl/profiler.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace simpli;

TEST(Profiler, CountsKernelsAndGemmsOnlyWhenEnabled) {
  using ocl::Profiler;
  const bool previous = Profiler::enabled();
  const ocl::Tensor a = ocl::Tensor::uniform({64, 64}, -1, 1, 1);
  Profiler::setEnabled(false);
  Profiler::reset();
  ocl::add(a, a);
  EXPECT_TRUE(Profiler::entries().empty());

  Profiler::setEnabled(true);
  ocl::add(a, a);
  ocl::add(a, a);
  ocl::matmul(a, a);
  const auto entries = Profiler::entries();
  Profiler::setEnabled(previous);
  auto find = [&](const std::string& part) {
    return std::find_if(entries.begin(), entries.end(), [&](const ocl::ProfileEntry& e) {
      return e.name.find(part) != std::string::npos;
    });
  };
  // "clblast.Gemm ..." or, with the host-BLAS backend (CPU devices), "host.Gemm ...".
  const auto gemm = find(".Gemm ");
  ASSERT_NE(gemm, entries.end());
  EXPECT_GE(gemm->calls, 1);
  int64_t elementwise = 0;
  for (const auto& e : entries) {
    EXPECT_GE(e.ms, 0.0) << e.name;
    if (e.name.rfind("elementwise.", 0) == 0)
      elementwise += e.calls;
  }
  EXPECT_GE(elementwise, 2);
  for (std::size_t i = 1; i < entries.size(); ++i)
    EXPECT_GE(entries[i - 1].ms, entries[i].ms) << "sorted by time";
  const std::string report = Profiler::report();
  EXPECT_NE(report.find(".Gemm "), std::string::npos) << report;
  EXPECT_NE(report.find("total"), std::string::npos);
  Profiler::reset();
}

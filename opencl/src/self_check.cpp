#include "simpli/ocl/self_check.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/ops_conv.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_linalg.h"
#include "simpli/ocl/ops_reduce.h"

#include <chrono>
#include <cmath>
#include <functional>
#include <iomanip>
#include <string>
#include <vector>

namespace simpli::ocl {
namespace {

struct Check {
  std::string name;
  // Returns the max relative error against the host result for a dtype.
  std::function<double(Dtype)> run;
};

double maxRelError(const std::vector<double>& got, const std::vector<double>& want) {
  double diff = 0.0, ref = 1e-30;
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (!std::isfinite(got[i]))
      return INFINITY;
    diff = std::max(diff, std::fabs(got[i] - want[i]));
    ref = std::max(ref, std::fabs(want[i]));
  }
  return got.size() == want.size() ? diff / ref : INFINITY;
}

std::vector<Check> checks() {
  return {
      {"broadcast multiply-add",
       [](Dtype dt) {
         Tensor a = Tensor::uniform({7, 1, 5}, -1, 1, 1, dt);
         Tensor b = Tensor::uniform({3, 1}, -1, 1, 2, dt);
         auto av = a.toVector(), bv = b.toVector();
         auto got = add(mul(a, b), b).toVector();
         std::vector<double> want;
         for (int i = 0; i < 7; ++i)
           for (int j = 0; j < 3; ++j)
             for (int k = 0; k < 5; ++k)
               want.push_back(av[i * 5 + k] * bv[j] + bv[j]);
         return maxRelError(got, want);
       }},
      {"sigmoid/tanh at +-1e30",
       [](Dtype dt) {
         Tensor x = Tensor::fromHost(std::vector<double>{-1e30, -3, 0, 3, 1e30}, {5}, dt);
         auto got = add(sigmoid(x), tanh(x)).toVector();
         std::vector<double> want;
         for (double v : {-1e30, -3.0, 0.0, 3.0, 1e30})
           want.push_back(1 / (1 + std::exp(-v)) + std::tanh(v));
         return maxRelError(got, want);
       }},
      {"sum over an axis",
       [](Dtype dt) {
         Tensor x = Tensor::uniform({4, 1000, 3}, 0, 1, 3, dt);
         auto xv = x.toVector();
         auto got = sum(x, 1).toVector();
         std::vector<double> want(12, 0.0);
         for (int i = 0; i < 4; ++i)
           for (int j = 0; j < 1000; ++j)
             for (int k = 0; k < 3; ++k)
               want[i * 3 + k] += xv[(i * 1000 + j) * 3 + k];
         return maxRelError(got, want);
       }},
      {"matmul (CLBlast GEMM)",
       [](Dtype dt) {
         const int m = 37, k = 29, n = 41;
         Tensor a = Tensor::uniform({m, k}, -1, 1, 5, dt),
                b = Tensor::uniform({k, n}, -1, 1, 6, dt);
         auto av = a.toVector(), bv = b.toVector();
         std::vector<double> want(m * n, 0.0);
         for (int i = 0; i < m; ++i)
           for (int j = 0; j < n; ++j)
             for (int q = 0; q < k; ++q)
               want[i * n + j] += av[i * k + q] * bv[q * n + j];
         return maxRelError(matmul(a, b).toVector(), want);
       }},
      {"conv2d 3x3 zero padding",
       [](Dtype dt) {
         const int c = 3, o = 4, h = 9, w = 7;
         Tensor x = Tensor::uniform({1, c, h, w}, -1, 1, 7, dt);
         Tensor k = Tensor::uniform({o, c, 3, 3}, -1, 1, 8, dt);
         auto xv = x.toVector(), kv = k.toVector();
         std::vector<double> want(o * h * w, 0.0);
         for (int oc = 0; oc < o; ++oc)
           for (int y = 0; y < h; ++y)
             for (int xx = 0; xx < w; ++xx)
               for (int ic = 0; ic < c; ++ic)
                 for (int dy = -1; dy <= 1; ++dy)
                   for (int dx = -1; dx <= 1; ++dx) {
                     const int sy = y + dy, sx = xx + dx;
                     if (sy < 0 || sy >= h || sx < 0 || sx >= w)
                       continue;
                     want[(oc * h + y) * w + xx] +=
                         xv[(ic * h + sy) * w + sx] * kv[((oc * c + ic) * 3 + dy + 1) * 3 + dx + 1];
                   }
         return maxRelError(conv2d(x, k, Tensor(), 1, 1).toVector(), want);
       }},
      {"gradient of x*x",
       [](Dtype dt) {
         Tensor x = Tensor::uniform({33}, -2, 2, 4, dt).setRequiresGrad();
         sumAll(mul(x, x)).backward();
         auto xv = x.toVector();
         std::vector<double> want;
         for (double v : xv)
           want.push_back(2 * v);
         return maxRelError(x.grad().toVector(), want);
       }},
  };
}

} // namespace

bool runSelfCheck(std::ostream& out) {
  const auto& info = Device::current().info();
  out << "device " << info.platformIndex << ':' << info.deviceIndex << "  " << info.deviceName
      << "  (" << info.platformName << ")\n";
  bool ok = true;
  for (Dtype dt : {Dtype::F32, Dtype::F64}) {
    if (dt == Dtype::F64 && !info.hasFp64) {
      out << "  float64: skipped (device has no cl_khr_fp64)\n";
      continue;
    }
    const double tol = dt == Dtype::F32 ? 1e-5 : 1e-12;
    for (const auto& check : checks()) {
      const auto start = std::chrono::steady_clock::now();
      double err = INFINITY;
      std::string problem;
      try {
        err = check.run(dt);
      } catch (const Error& e) {
        problem = e.what();
      }
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      const bool pass = problem.empty() && err <= tol;
      ok = ok && pass;
      out << "  " << (pass ? "ok  " : "FAIL") << "  " << toString(dt) << "  " << std::left
          << std::setw(26) << check.name << " rel.err " << std::scientific << std::setprecision(2)
          << err << std::defaultfloat << "  (" << std::fixed << std::setprecision(1) << ms
          << " ms incl. kernel build)" << std::defaultfloat;
      if (!problem.empty())
        out << "  " << problem;
      out << '\n';
    }
  }
  return ok;
}

} // namespace simpli::ocl

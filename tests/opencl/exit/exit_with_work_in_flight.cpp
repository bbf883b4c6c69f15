// Ends a process with engine work still queued, in one of the ways a program ends, so that
// cold_cache_exit.sh can check the exit code with an empty PoCL kernel cache (issue 9: PoCL
// compiles each kernel at its first launch on a worker thread; a process that exited during
// that compile died with SIGSEGV after its work was done).
// Usage: exit_with_work_in_flight return|exit|quick_exit|error|sigterm [more]
//   return, exit, quick_exit: end that way, exit code 0
//   error: an engine error (bad matmul shapes) caught in main, exit code 1
//   sigterm: SIGTERM handled (recorded, then main returns 128 + 15 = 143)
//   more: launch further kernels and shapes after the first set (with a cache that holds the
//         first set: a partly warm cache)
#include "simpli/error.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_linalg.h"
#include "simpli/ocl/tensor.h"

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {

using simpli::ocl::Dtype;
using simpli::ocl::Tensor;

volatile std::sig_atomic_t g_signal = 0;

extern "C" void onSignal(int signal) {
  g_signal = signal;
}

// Elementwise kernels, then a CLBlast GEMM (64 x 64 is too large for the skinny kernels) as the
// last launch: its kernels are still queued, and PoCL compiles them at their first launch, when
// the caller ends the process (no result is read back). This covers Device::settleFirstUse.
void launchWork() {
  const Tensor x = Tensor::uniform({64, 64}, -1.0, 1.0, 7);
  const Tensor y = simpli::ocl::exp(simpli::ocl::mulScalar(simpli::ocl::relu(x), 0.1));
  const Tensor z = simpli::ocl::matmul(y, x);
  (void)z;
}

// Kernels and shapes that launchWork does not launch, ending with the engine's own kernels (in
// float64): this covers Device::settleFirstLaunch.
void launchMoreWork() {
  const Tensor x = Tensor::normal({96, 80}, 0.0, 1.0, 3);
  const Tensor z = simpli::ocl::matmul(x, x, false, true);
  const Tensor d = simpli::ocl::sqrt(simpli::ocl::abs(simpli::ocl::tanh(z.to(Dtype::F64))));
  (void)d;
}

int usage() {
  std::fprintf(stderr,
               "usage: exit_with_work_in_flight return|exit|quick_exit|error|sigterm [more]\n");
  return 2;
}

} // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3 || (argc == 3 && std::strcmp(argv[2], "more") != 0))
    return usage();
  const std::string mode = argv[1];
  std::signal(SIGTERM, onSignal);
  try {
    launchWork();
    if (argc == 3)
      launchMoreWork();
    if (mode == "return")
      return 0;
    if (mode == "exit")
      std::exit(0);
    if (mode == "quick_exit")
      std::quick_exit(0);
    if (mode == "error") {
      (void)simpli::ocl::matmul(Tensor::ones({3, 4}), Tensor::ones({5, 6}));
      std::fprintf(stderr, "exit_with_work_in_flight: the bad matmul did not throw\n");
      return 3;
    }
    if (mode == "sigterm") {
      std::raise(SIGTERM);
      return g_signal ? 128 + g_signal : 4;
    }
  } catch (const simpli::Error& e) {
    std::fprintf(stderr, "exit_with_work_in_flight: error: %s\n", e.what());
    return 1;
  }
  return usage();
}

#pragma once
// The OpenBLAS environment of a simpli process. OpenBLAS reads its environment once, when the
// library loads, so simpli sets it by re-executing itself at the start of main (before MPI and
// any thread) when it lacks something:
// - OPENBLAS_THREAD_TIMEOUT=4 (unless set): after each call OpenBLAS's worker threads otherwise
//   spin on sched_yield for 2^28 cycles (~0.1 s), and the host GEMMs of a training step come
//   between PoCL kernels that need those cores; with 2^4 cycles they sleep at once. A training
//   step is ~1.1x faster (docs/benchmarks.md).
// - `simpli bench ops|infer|train`: OPENBLAS_CORETYPE and OPENBLAS_L2_SIZE removed, so that the
//   benchmarks compare with OpenBLAS's native kernel (this kind of machine forces an older one);
//   SIMPLI_BENCH_BLAS_ENV=keep keeps them.
// In-process users (the VTK filters in ParaView or Python) keep the environment they were
// started with.

namespace simpli::app {

/// Re-executes the process with the environment above when it differs; returns when nothing
/// needs changing or the re-execution failed (then says so on stderr and runs as it is).
void reexecWithBlasEnvironment(int argc, char** argv);

/// In a re-executed benchmark: the variables that were removed ("NAME=value ..."), else null.
const char* removedBlasVariables();

} // namespace simpli::app

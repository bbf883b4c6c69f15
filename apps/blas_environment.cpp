#include "blas_environment.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

extern char** environ;

namespace simpli::app {
namespace {

constexpr const char* kThreadTimeout = "OPENBLAS_THREAD_TIMEOUT";
constexpr const char* kThreadTimeoutValue = "4"; // 2^4 cycles of spinning, OpenBLAS's minimum
// Set in a re-executed benchmark: the variables it removed ("NAME=value ...").
constexpr const char* kRemovedMarker = "SIMPLI_BENCH_NATIVE_BLAS";
constexpr const char* kForcingVariables[] = {"OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE"};

bool isForcingVariable(const char* entry) {
  for (const char* name : kForcingVariables) {
    const std::size_t n = std::strlen(name);
    if (std::strncmp(entry, name, n) == 0 && entry[n] == '=')
      return true;
  }
  return false;
}

// `simpli bench ops|infer|train`, unless SIMPLI_BENCH_BLAS_ENV=keep or already re-executed.
bool wantsNativeKernel(int argc, char** argv) {
  if (argc < 3 || std::strcmp(argv[1], "bench") != 0 ||
      (std::strcmp(argv[2], "ops") != 0 && std::strcmp(argv[2], "infer") != 0 &&
       std::strcmp(argv[2], "train") != 0))
    return false;
  const char* keep = std::getenv("SIMPLI_BENCH_BLAS_ENV");
  return !(keep && std::string(keep) == "keep") && !std::getenv(kRemovedMarker);
}

} // namespace

void reexecWithBlasEnvironment(int argc, char** argv) {
  const bool native = wantsNativeKernel(argc, argv);
  std::vector<std::string> kept;
  std::string removed;
  for (char** e = environ; *e; ++e) {
    if (native && isForcingVariable(*e))
      removed += (removed.empty() ? "" : " ") + std::string(*e);
    else
      kept.emplace_back(*e);
  }
  const bool addTimeout = !std::getenv(kThreadTimeout);
  if (removed.empty() && !addTimeout)
    return;
  if (addTimeout)
    kept.push_back(std::string(kThreadTimeout) + "=" + kThreadTimeoutValue);
  if (!removed.empty())
    kept.push_back(std::string(kRemovedMarker) + "=" + removed);
  std::vector<char*> envp;
  for (std::string& k : kept)
    envp.push_back(k.data());
  envp.push_back(nullptr);
  std::fflush(nullptr);
  execve("/proc/self/exe", argv, envp.data());
  // Not fatal: the process runs with the environment it has.
  std::string wanted = addTimeout ? std::string(kThreadTimeout) + "=" + kThreadTimeoutValue : "";
  if (!removed.empty())
    wanted += (wanted.empty() ? "without " : ", without ") + removed;
  std::fprintf(stderr, "simpli: could not re-execute with %s (%s); running as it is\n",
               wanted.c_str(), std::strerror(errno));
}

const char* removedBlasVariables() {
  return std::getenv(kRemovedMarker);
}

} // namespace simpli::app

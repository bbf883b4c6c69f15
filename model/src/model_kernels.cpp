#include "model_kernels.h"

#include "simpli/ocl/program_cache.h"

#include <map>
#include <mutex>
#include <string>

namespace simpli {

const std::map<std::string, const char*>& modelKernelSources(); // generated at build time

void ensureModelKernels() {
  static std::once_flag once;
  std::call_once(once, [] { ocl::registerKernelSources(modelKernelSources()); });
}

} // namespace simpli

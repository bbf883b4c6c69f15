#include "simpli/ocl/program_cache.h"

#include "simpli/error.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/tensor.h"

#include <cstring>

namespace simpli::ocl {

namespace {
std::map<std::string, const char*>& registeredSources() {
  static std::map<std::string, const char*> sources;
  return sources;
}
} // namespace

void registerKernelSources(const std::map<std::string, const char*>& sources) {
  auto& known = registeredSources();
  for (const auto& [name, text] : sources) {
    const auto& embedded = embeddedKernelSources();
    const char* existing = nullptr;
    if (auto it = embedded.find(name); it != embedded.end())
      existing = it->second;
    else if (auto jt = known.find(name); jt != known.end())
      existing = jt->second;
    if (existing && std::strcmp(existing, text) != 0)
      fail("registerKernelSources: program '", name, "' is already registered with other text");
    known.emplace(name, text);
  }
}

ProgramCache::ProgramCache(cl_context context, cl_device_id device, bool deviceHasFp64)
    : context_(context), device_(device), hasFp64_(deviceHasFp64) {}

ProgramCache::~ProgramCache() {
  for (auto& entry : kernels_)
    clReleaseKernel(entry.second);
  for (auto& entry : programs_)
    clReleaseProgram(entry.second);
}

cl_program ProgramCache::program(const std::string& programName, Dtype dtype,
                                 const std::string& options, const std::string& forKernel) {
  auto key = std::make_tuple(programName, dtype, options);
  if (auto it = programs_.find(key); it != programs_.end())
    return it->second;

  const auto& sources = embeddedKernelSources();
  auto common = sources.find("common");
  const char* bodyText = nullptr;
  if (auto it = sources.find(programName); it != sources.end())
    bodyText = it->second;
  else if (auto jt = registeredSources().find(programName); jt != registeredSources().end())
    bodyText = jt->second;
  if (!bodyText)
    fail("OpenCL program '", programName, "' (kernel ", forKernel, ") is not embedded: no kernels/",
         programName, ".cl");
  if (dtype == Dtype::F64 && !hasFp64_)
    fail("kernel ", programName, ".", forKernel,
         ": float64 requested but the device has no cl_khr_fp64 support");

  const char* parts[2] = {common != sources.end() ? common->second : "", bodyText};
  cl_int status = CL_SUCCESS;
  cl_program prog = clCreateProgramWithSource(context_, 2, parts, nullptr, &status);
  checkCl(status, "clCreateProgramWithSource");
  std::string flags = std::string("-cl-std=CL1.2 ") +
                      (dtype == Dtype::F64 ? "-DREAL_IS_DOUBLE=1 " : "-DREAL_IS_DOUBLE=0 ") +
                      options;
  status = clBuildProgram(prog, 1, &device_, flags.c_str(), nullptr, nullptr);
  if (status != CL_SUCCESS) {
    std::size_t n = 0;
    clGetProgramBuildInfo(prog, device_, CL_PROGRAM_BUILD_LOG, 0, nullptr, &n);
    std::string log(n, '\0');
    clGetProgramBuildInfo(prog, device_, CL_PROGRAM_BUILD_LOG, n, log.data(), nullptr);
    clReleaseProgram(prog);
    fail("building OpenCL program '", programName, "' for kernel '", forKernel, "' (",
         toString(dtype), ", options \"", flags, "\") failed with ", clErrorName(status), ":\n",
         log);
  }
  programs_.emplace(key, prog);
  return prog;
}

cl_kernel ProgramCache::kernel(const std::string& programName, const std::string& kernelName,
                               Dtype dtype, const std::string& options) {
  auto key = std::make_tuple(programName, kernelName, dtype, options);
  if (auto it = kernels_.find(key); it != kernels_.end())
    return it->second;
  cl_program prog = program(programName, dtype, options, kernelName);
  cl_int status = CL_SUCCESS;
  cl_kernel k = clCreateKernel(prog, kernelName.c_str(), &status);
  if (status != CL_SUCCESS)
    fail("OpenCL program '", programName, "' has no kernel '", kernelName, "' (",
         clErrorName(status), ")");
  kernels_.emplace(key, k);
  return k;
}

} // namespace simpli::ocl

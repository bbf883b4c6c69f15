#include "simpli/ocl/program_cache.h"

#include "simpli/error.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/tensor.h"

#include <cstring>
#include <sstream>

namespace simpli::ocl {

namespace {
std::map<std::string, const char*>& registeredSources() {
  static std::map<std::string, const char*> sources;
  return sources;
}

// An embedded or registered text by key (program stem or header file name); null when unknown.
const char* sourceText(const std::string& key) {
  const auto& embedded = embeddedKernelSources();
  if (auto it = embedded.find(key); it != embedded.end())
    return it->second;
  if (auto it = registeredSources().find(key); it != registeredSources().end())
    return it->second;
  return nullptr;
}

// The header name of a line `#include "name"` (spaces allowed around '#'), else "".
std::string quotedInclude(const std::string& line) {
  std::size_t i = line.find_first_not_of(" \t");
  if (i == std::string::npos || line[i] != '#')
    return "";
  i = line.find_first_not_of(" \t", i + 1);
  if (i == std::string::npos || line.compare(i, 7, "include") != 0)
    return "";
  i = line.find_first_not_of(" \t", i + 7);
  if (i == std::string::npos || line[i] != '"')
    return "";
  const std::size_t end = line.find('"', i + 1);
  return end == std::string::npos ? "" : line.substr(i + 1, end - i - 1);
}

// Programs are embedded, so the OpenCL compiler cannot resolve `#include "x.h"` (no files at
// run time): each such line is replaced by the embedded kernels/x.h (headers are embedded by
// file name), then a #line directive restores the includer's line numbers for build logs.
std::string spliceIncludes(const std::string& program, const std::string& text, int depth = 0) {
  constexpr int kMaxDepth = 8;
  std::istringstream in(text);
  std::string out, line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string header = quotedInclude(line);
    if (header.empty()) {
      out += line + '\n';
      continue;
    }
    const char* headerText = sourceText(header);
    if (!headerText)
      fail("OpenCL program '", program, "' includes \"", header,
           "\", which is not embedded (no kernels/", header, "; headers must be listed in ",
           "opencl/CMakeLists.txt or registered)");
    if (depth >= kMaxDepth)
      fail("OpenCL program '", program, "': includes nested deeper than ", kMaxDepth, " at \"",
           header, "\" (an include cycle?)");
    out += spliceIncludes(program, headerText, depth + 1);
    out += "#line " + std::to_string(number + 1) + '\n';
  }
  return out;
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

  const char* commonText = sourceText("common");
  const char* bodyText = sourceText(programName);
  if (!bodyText)
    fail("OpenCL program '", programName, "' (kernel ", forKernel, ") is not embedded: no kernels/",
         programName, ".cl");
  if (dtype == Dtype::F64 && !hasFp64_)
    fail("kernel ", programName, ".", forKernel,
         ": float64 requested but the device has no cl_khr_fp64 support");

  const std::string common = spliceIncludes("common", commonText ? commonText : "");
  const std::string body = spliceIncludes(programName, bodyText);
  const char* parts[2] = {common.c_str(), body.c_str()};
  cl_int status = CL_SUCCESS;
  cl_program prog = clCreateProgramWithSource(context_, 2, parts, nullptr, &status);
  checkCl(status, "clCreateProgramWithSource");
  // f64 builds are quiet (-w): a double8 is 512 bits, and on CPUs without AVX-512 PoCL's clang
  // warns (-Wpsabi, "changes the ABI") at every call that passes or returns one, on the user's
  // terminal; PoCL rejects -Wno-psabi. The f32 build of the same source keeps every warning.
  std::string flags = std::string("-cl-std=CL1.2 ") +
                      (dtype == Dtype::F64 ? "-w -DREAL_IS_DOUBLE=1 " : "-DREAL_IS_DOUBLE=0 ") +
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

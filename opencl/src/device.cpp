#include "simpli/ocl/device.h"

#include "simpli/error.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/program_cache.h"
#include "tuning.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <tuple>

namespace simpli::ocl {
namespace {

// clGetPlatformIDs returns CL_PLATFORM_NOT_FOUND_KHR (cl_ext.h) when the ICD loader finds
// no platform at all.
constexpr cl_int kPlatformNotFound = -1001;

constexpr const char* kInstallHint =
    "no OpenCL platform found. Install an OpenCL runtime: on Debian "
    "`apt-get install pocl-opencl-icd ocl-icd-libopencl1` (CPU), or your GPU vendor's ICD "
    "(e.g. nvidia-opencl-icd, mesa-opencl-icd, intel-opencl-icd); `clinfo -l` lists what the "
    "loader sees";

std::string platformString(cl_platform_id p, cl_platform_info what) {
  std::size_t n = 0;
  clGetPlatformInfo(p, what, 0, nullptr, &n);
  std::string s(n, '\0');
  clGetPlatformInfo(p, what, n, s.data(), nullptr);
  while (!s.empty() && s.back() == '\0')
    s.pop_back();
  return s;
}

std::string deviceString(cl_device_id d, cl_device_info what) {
  std::size_t n = 0;
  clGetDeviceInfo(d, what, 0, nullptr, &n);
  std::string s(n, '\0');
  clGetDeviceInfo(d, what, n, s.data(), nullptr);
  while (!s.empty() && s.back() == '\0')
    s.pop_back();
  return s;
}

template <typename T> T deviceValue(cl_device_id d, cl_device_info what) {
  T value{};
  clGetDeviceInfo(d, what, sizeof(T), &value, nullptr);
  return value;
}

std::vector<cl_platform_id> platforms() {
  cl_uint n = 0;
  cl_int status = clGetPlatformIDs(0, nullptr, &n);
  if (status == kPlatformNotFound || n == 0)
    fail(kInstallHint);
  checkCl(status, "clGetPlatformIDs");
  std::vector<cl_platform_id> ids(n);
  checkCl(clGetPlatformIDs(n, ids.data(), nullptr), "clGetPlatformIDs");
  return ids;
}

std::vector<cl_device_id> devicesOf(cl_platform_id p) {
  cl_uint n = 0;
  if (clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, 0, nullptr, &n) != CL_SUCCESS || n == 0)
    return {};
  std::vector<cl_device_id> ids(n);
  checkCl(clGetDeviceIDs(p, CL_DEVICE_TYPE_ALL, n, ids.data(), nullptr), "clGetDeviceIDs");
  return ids;
}

DeviceInfo describe(cl_platform_id p, cl_device_id d, int pi, int di) {
  DeviceInfo info;
  info.platformIndex = pi;
  info.deviceIndex = di;
  info.platformName = platformString(p, CL_PLATFORM_NAME);
  info.platformVersion = platformString(p, CL_PLATFORM_VERSION);
  info.deviceName = deviceString(d, CL_DEVICE_NAME);
  info.deviceVendor = deviceString(d, CL_DEVICE_VENDOR);
  info.deviceVersion = deviceString(d, CL_DEVICE_VERSION);
  info.driverVersion = deviceString(d, CL_DRIVER_VERSION);
  info.isGpu = (deviceValue<cl_device_type>(d, CL_DEVICE_TYPE) & CL_DEVICE_TYPE_GPU) != 0;
  info.hasFp64 = deviceValue<cl_device_fp_config>(d, CL_DEVICE_DOUBLE_FP_CONFIG) != 0;
  info.computeUnits = static_cast<int>(deviceValue<cl_uint>(d, CL_DEVICE_MAX_COMPUTE_UNITS));
  info.globalMemBytes = deviceValue<cl_ulong>(d, CL_DEVICE_GLOBAL_MEM_SIZE);
  info.maxAllocBytes = deviceValue<cl_ulong>(d, CL_DEVICE_MAX_MEM_ALLOC_SIZE);
  info.maxWorkGroupSize = deviceValue<std::size_t>(d, CL_DEVICE_MAX_WORK_GROUP_SIZE);
  return info;
}

std::unique_ptr<Device>& currentSlot() {
  static std::unique_ptr<Device> device;
  return device;
}

} // namespace

std::vector<DeviceInfo> listDevices() {
  std::vector<DeviceInfo> out;
  auto ps = platforms();
  for (std::size_t pi = 0; pi < ps.size(); ++pi) {
    auto ds = devicesOf(ps[pi]);
    for (std::size_t di = 0; di < ds.size(); ++di)
      out.push_back(describe(ps[pi], ds[di], static_cast<int>(pi), static_cast<int>(di)));
  }
  if (out.empty())
    fail(kInstallHint, " (platforms exist but expose no device)");
  return out;
}

std::pair<int, int> Device::parseSelector(const std::string& text, const std::string& origin) {
  // Two plain decimal indices; at most kMaxSelectorDigits digits each, so that no value
  // overflows (sscanf's %d is undefined beyond INT_MAX: 99999999999 became 1215752191).
  constexpr std::size_t kMaxSelectorDigits = 4;
  const std::size_t colon = text.find(':');
  auto index = [&](const std::string& digits) {
    if (digits.empty() || digits.size() > kMaxSelectorDigits ||
        digits.find_first_not_of("0123456789") != std::string::npos)
      fail(origin, ": expected \"platform:device\" with indices 0..9999 (e.g. 0:0), got \"", text,
           "\"");
    return std::stoi(digits);
  };
  if (colon == std::string::npos)
    index("");
  return {index(text.substr(0, colon)), index(text.substr(colon + 1))};
}

Device& Device::current() {
  auto& slot = currentSlot();
  if (!slot) {
    int p = -1, d = -1;
    if (const char* env = std::getenv("SIMPLI_CL_DEVICE"); env && *env) {
      std::tie(p, d) = parseSelector(env, "SIMPLI_CL_DEVICE");
    } else {
      auto all = listDevices();
      const DeviceInfo* pick = nullptr;
      for (const auto& info : all)
        if (info.isGpu) {
          pick = &info;
          break;
        }
      if (!pick)
        pick = &all.front();
      p = pick->platformIndex;
      d = pick->deviceIndex;
    }
    slot.reset(new Device(p, d));
  }
  return *slot;
}

void Device::select(int platformIndex, int deviceIndex) {
  auto& slot = currentSlot();
  slot.reset();
  slot.reset(new Device(platformIndex, deviceIndex));
}

Device::Device(int platformIndex, int deviceIndex) {
  auto ps = platforms();
  if (platformIndex < 0 || platformIndex >= static_cast<int>(ps.size()))
    fail("OpenCL device selection: platform ", platformIndex, " does not exist (", ps.size(),
         " platform(s); see `simpli devices`)");
  auto ds = devicesOf(ps[platformIndex]);
  if (deviceIndex < 0 || deviceIndex >= static_cast<int>(ds.size()))
    fail("OpenCL device selection: platform ", platformIndex, " has no device ", deviceIndex, " (",
         ds.size(), " device(s); see `simpli devices`)");
  device_ = ds[deviceIndex];
  info_ = describe(ps[platformIndex], device_, platformIndex, deviceIndex);
  cl_int status = CL_SUCCESS;
  context_ = clCreateContext(nullptr, 1, &device_, nullptr, nullptr, &status);
  checkCl(status, "clCreateContext");
  queue_ = clCreateCommandQueue(context_, device_, 0, &status);
  checkCl(status, "clCreateCommandQueue");
  programs_ = std::make_unique<ProgramCache>(context_, device_, info_.hasFp64);
  pool_ = std::make_unique<BufferPool>(context_);
  pool_->setQueue(queue_);
  applyGemmTuning(info_.deviceName, device_);
}

Device::~Device() {
  if (queue_)
    clFinish(queue_);
  programs_.reset();
  pool_.reset();
  if (queue_)
    clReleaseCommandQueue(queue_);
  if (context_)
    clReleaseContext(context_);
}

void Device::finish() {
  checkCl(clFinish(queue_), "clFinish");
}

// Exit with work in flight (issue 9). PoCL's CPU devices compile a kernel for each local size
// on a worker thread when it is first launched (pocl_check_kernel_disk_cache -> LLVM), and
// LLVM/clang create function-local statics during that compile. When the process exits while
// such a compile runs (an empty PoCL cache: a fresh machine, CI), the main thread runs static
// destructors under it and the process dies with SIGSEGV (or SIGABRT) after its work is done.
// Two measures, both needed (tests/opencl/exit/):
// - The first launch of every (kernel, work size) is made synchronous, so no compile is left in
//   flight. The key holds the whole global size, a superset of what PoCL specialises on (local
//   size, zero offset, small grid). Later launches hit PoCL's in-memory kernel cache and stay
//   asynchronous. Cost: one clFinish per distinct first launch.
// - After each such first launch, quiesce() is registered (again) with atexit and
//   at_quick_exit. Handlers run in reverse order of registration, and the statics the compile
//   constructed registered their destructors after our earlier registrations; only a
//   registration made after them runs before their destructors and drains the queue first.
// A warm-up kernel at start-up does not help: it hits the disk cache and compiles nothing, and
// forcing a recompile costs seconds per process.
void Device::settleFirstLaunch(cl_kernel kernel, cl_uint dims, const std::size_t* global,
                               const std::size_t* local) {
  LaunchKey key{reinterpret_cast<std::size_t>(kernel), dims, 1, 1, 1, 0, 0, 0};
  for (cl_uint d = 0; d < dims && d < 3; ++d) {
    key[2 + d] = global[d];
    key[5 + d] = local ? local[d] : 0;
  }
  if (launched_.insert(key).second)
    settle();
}

void Device::settleFirstUse(const std::string& key) {
  if (used_.insert(key).second)
    settle();
}

namespace {
void quiesceAtExit() {
  Device::quiesce();
}
} // namespace

void Device::settle() {
  finish();
  std::atexit(quiesceAtExit);
  std::at_quick_exit(quiesceAtExit);
}

void Device::quiesce() noexcept {
  if (const auto& device = currentSlot(); device && device->queue_)
    clFinish(device->queue_);
}

void checkCl(cl_int status, const char* what) {
  if (status != CL_SUCCESS)
    fail(what, ": OpenCL error ", clErrorName(status), " (", status, ")");
}

const char* clErrorName(cl_int status) {
  switch (status) {
#define SIMPLI_CL_CASE(x)                                                                          \
  case x:                                                                                          \
    return #x;
    SIMPLI_CL_CASE(CL_SUCCESS)
    SIMPLI_CL_CASE(CL_DEVICE_NOT_FOUND)
    SIMPLI_CL_CASE(CL_DEVICE_NOT_AVAILABLE)
    SIMPLI_CL_CASE(CL_COMPILER_NOT_AVAILABLE)
    SIMPLI_CL_CASE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    SIMPLI_CL_CASE(CL_OUT_OF_RESOURCES)
    SIMPLI_CL_CASE(CL_OUT_OF_HOST_MEMORY)
    SIMPLI_CL_CASE(CL_BUILD_PROGRAM_FAILURE)
    SIMPLI_CL_CASE(CL_INVALID_VALUE)
    SIMPLI_CL_CASE(CL_INVALID_PLATFORM)
    SIMPLI_CL_CASE(CL_INVALID_DEVICE)
    SIMPLI_CL_CASE(CL_INVALID_CONTEXT)
    SIMPLI_CL_CASE(CL_INVALID_COMMAND_QUEUE)
    SIMPLI_CL_CASE(CL_INVALID_MEM_OBJECT)
    SIMPLI_CL_CASE(CL_INVALID_BUFFER_SIZE)
    SIMPLI_CL_CASE(CL_INVALID_PROGRAM)
    SIMPLI_CL_CASE(CL_INVALID_PROGRAM_EXECUTABLE)
    SIMPLI_CL_CASE(CL_INVALID_KERNEL_NAME)
    SIMPLI_CL_CASE(CL_INVALID_KERNEL)
    SIMPLI_CL_CASE(CL_INVALID_ARG_INDEX)
    SIMPLI_CL_CASE(CL_INVALID_ARG_VALUE)
    SIMPLI_CL_CASE(CL_INVALID_ARG_SIZE)
    SIMPLI_CL_CASE(CL_INVALID_KERNEL_ARGS)
    SIMPLI_CL_CASE(CL_INVALID_WORK_DIMENSION)
    SIMPLI_CL_CASE(CL_INVALID_WORK_GROUP_SIZE)
    SIMPLI_CL_CASE(CL_INVALID_WORK_ITEM_SIZE)
    SIMPLI_CL_CASE(CL_INVALID_GLOBAL_OFFSET)
    SIMPLI_CL_CASE(CL_INVALID_EVENT_WAIT_LIST)
    SIMPLI_CL_CASE(CL_INVALID_OPERATION)
    SIMPLI_CL_CASE(CL_INVALID_BUILD_OPTIONS)
    SIMPLI_CL_CASE(CL_INVALID_GLOBAL_WORK_SIZE)
#undef SIMPLI_CL_CASE
  case kPlatformNotFound:
    return "CL_PLATFORM_NOT_FOUND_KHR";
  default:
    return "unknown";
  }
}

} // namespace simpli::ocl

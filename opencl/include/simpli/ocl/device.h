#pragma once
// OpenCL device selection and the process-wide compute context (context, in-order queue,
// program cache, buffer pool). Selection order: an explicit select(), else the environment
// variable SIMPLI_CL_DEVICE="platform:device" (indices as listed by `simpli devices`), else
// the first GPU of any platform, else the first CPU device.
#include <CL/cl.h>

#include <array>
#include <cstddef>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace simpli::ocl {

struct DeviceInfo {
  int platformIndex = 0;
  int deviceIndex = 0;
  std::string platformName;
  std::string platformVersion;
  std::string deviceName;
  std::string deviceVendor;
  std::string deviceVersion;
  std::string driverVersion;
  bool isGpu = false;
  bool hasFp64 = false;
  int computeUnits = 0;
  std::size_t globalMemBytes = 0;
  std::size_t maxAllocBytes = 0;
  std::size_t maxWorkGroupSize = 0;
};

/// Every OpenCL device on every platform. Throws simpli::Error naming the packages to install
/// when no platform is present.
std::vector<DeviceInfo> listDevices();

class ProgramCache;
class BufferPool;

/// The compute context: one device, one in-order command queue, a program cache and a buffer
/// pool. Not thread-safe; one host thread drives it.
class Device {
public:
  /// The current device, opened on first use (see the selection order above).
  static Device& current();
  /// Re-selects the current device. Tensors of the previous device must be dead.
  static void select(int platformIndex, int deviceIndex);
  /// Parses "p:d"; throws simpli::Error naming the variable and value when malformed.
  static std::pair<int, int> parseSelector(const std::string& text, const std::string& origin);

  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  const DeviceInfo& info() const { return info_; }
  cl_context context() const { return context_; }
  cl_command_queue queue() const { return queue_; }
  cl_device_id id() const { return device_; }
  ProgramCache& programs() { return *programs_; }
  BufferPool& pool() { return *pool_; }
  /// Blocks until every queued command finished.
  void finish();

  /// Called right after enqueueing `kernel` with this work size: the first time a (kernel,
  /// work size) pair is seen, waits until it ran, so that a runtime that compiles at first
  /// launch (PoCL) never compiles while the process exits (see device.cpp).
  void settleFirstLaunch(cl_kernel kernel, cl_uint dims, const std::size_t* global,
                         const std::size_t* local);
  /// The same for a library call that enqueues kernels of its own (CLBlast); `key` names the
  /// routine and everything that selects its kernels and work sizes (precision, shape, ...).
  void settleFirstUse(const std::string& key);
  /// Finishes the open device's queue, if a device is open; never opens one, never throws.
  /// Registered with atexit and at_quick_exit by the two calls above.
  static void quiesce() noexcept;

private:
  Device(int platformIndex, int deviceIndex);
  void settle();
  using LaunchKey = std::array<std::size_t, 8>; // kernel, dims, global[3], local[3]
  std::set<LaunchKey> launched_;
  std::set<std::string> used_;
  DeviceInfo info_;
  cl_device_id device_ = nullptr;
  cl_context context_ = nullptr;
  cl_command_queue queue_ = nullptr;
  std::unique_ptr<ProgramCache> programs_;
  std::unique_ptr<BufferPool> pool_;
};

/// Throws simpli::Error "<what>: OpenCL error <name> (<code>)" when status != CL_SUCCESS.
void checkCl(cl_int status, const char* what);
const char* clErrorName(cl_int status);

} // namespace simpli::ocl

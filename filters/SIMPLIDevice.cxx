// Device selection shared by the filters (see SIMPLIDevice.h).
#include "SIMPLIDevice.h"

#include "simpli/ocl/device.h"

#include <map>

namespace simpli::vtkdevice {

namespace {

// Filters run on one host thread (the model's device is not thread-safe either).
std::map<int, std::function<void()>>& users() {
  static std::map<int, std::function<void()>> map;
  return map;
}

} // namespace

void selectDevice(const std::string& selector, const std::string& property) {
  if (selector.empty())
    return;
  const auto [platform, device] = ocl::Device::parseSelector(selector, property);
  const ocl::DeviceInfo& info = ocl::Device::current().info();
  if (info.platformIndex == platform && info.deviceIndex == device)
    return;
  for (auto& [handle, release] : users())
    release();
  ocl::Device::select(platform, device);
}

std::string currentDevice() {
  const ocl::DeviceInfo& info = ocl::Device::current().info();
  return std::to_string(info.platformIndex) + ":" + std::to_string(info.deviceIndex);
}

int registerDeviceUser(std::function<void()> release) {
  static int next = 0;
  users()[++next] = std::move(release);
  return next;
}

void unregisterDeviceUser(int handle) {
  users().erase(handle);
}

} // namespace simpli::vtkdevice

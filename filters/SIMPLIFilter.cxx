// The shared part of every SIMPLI filter's request (see SIMPLIFilter.h).
#include "SIMPLIFilter.h"

#include <vtkAlgorithm.h>
#include <vtkSetGet.h>

#include "simpli/error.h"
#include "simpli/ocl/device.h"
#include "simpli/warning.h"

#include <algorithm>
#include <exception>
#include <map>

namespace simpli::vtkfilter {

namespace {

// Filters run on one host thread (the model's device is not thread-safe either).
std::map<int, std::function<void()>>& users() {
  static std::map<int, std::function<void()>> map;
  return map;
}

} // namespace

bool Progress::operator()(double f) const {
  algorithm_->UpdateProgress(begin_ + std::clamp(f, 0.0, 1.0) * (end_ - begin_));
  return !aborted();
}

bool Progress::aborted() const {
  return algorithm_->GetAbortExecute() != 0;
}

int runRequest(vtkAlgorithm* algorithm, const std::string& what,
               const std::function<void(const Progress&)>& body,
               const std::function<void()>& onFailure) {
  // The model's warnings (simpli/warning.h) during the request go to the algorithm's
  // vtkWarningMacro, where ParaView shows them, instead of stderr.
  struct ForwardWarnings {
    simpli::WarningHandler previous;
    ~ForwardWarnings() { simpli::setWarningHandler(std::move(previous)); }
  } forward{simpli::setWarningHandler([algorithm, what](const std::string& message) {
    vtkWarningWithObjectMacro(algorithm, << what << ": " << message);
  })};
  try {
    body(Progress(algorithm));
    return 1;
  } catch (const simpli::Error& e) {
    vtkErrorWithObjectMacro(algorithm, << what << ": " << e.what());
  } catch (const std::exception& e) {
    vtkErrorWithObjectMacro(algorithm, << what << ": unexpected failure: " << e.what());
  }
  if (onFailure)
    onFailure();
  return 0;
}

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

} // namespace simpli::vtkfilter

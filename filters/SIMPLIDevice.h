// OpenCL device selection for the module's filters. Private to the module (PRIVATE_HEADERS).
//
// The model keeps one process-wide device (simpli/ocl/device.h) and re-selecting it destroys
// the old one, so every tensor of the old device must be gone first. Filters that keep tensors
// between updates (vtkSIMPLIBuildMLI's cached network) register a release callback here;
// selectDevice runs them all before it changes the device.
#pragma once

#include <functional>
#include <string>

namespace simpli::vtkdevice {

/// Makes `selector` ("platform:device") the current OpenCL device; empty keeps the current
/// one. Nothing happens when it already is the current device. Throws simpli::Error naming
/// `property` and the value when it is malformed or the device does not exist.
void selectDevice(const std::string& selector, const std::string& property);

/// "p:d" of the current device (opens the default device when none is open yet).
std::string currentDevice();

/// Registers `release`, called before the device changes; returns a handle for
/// unregisterDeviceUser.
int registerDeviceUser(std::function<void()> release);
void unregisterDeviceUser(int handle);

} // namespace simpli::vtkdevice

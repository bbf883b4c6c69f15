#pragma once
// CLBlast tuning table: parameters measured with CLBlast's tuners on known devices, applied
// with clblast::OverrideParameters when a matching device is opened.
#include <CL/cl.h>

#include <string>

namespace simpli::ocl {

/// Applies the shipped parameters for `deviceName` (no-op for unknown devices). Returns the
/// number of kernel families overridden.
int applyGemmTuning(const std::string& deviceName, cl_device_id device);

} // namespace simpli::ocl

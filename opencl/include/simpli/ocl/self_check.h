#pragma once
// A quick engine self-check for users: runs a few representative ops on the current device
// in float32 and float64 and compares them with host computations. Used by `simpli devices
// --check` to tell a user whether their OpenCL driver computes correctly.
#include <ostream>

namespace simpli::ocl {

/// Prints one line per check; returns true when all pass.
bool runSelfCheck(std::ostream& out);

} // namespace simpli::ocl

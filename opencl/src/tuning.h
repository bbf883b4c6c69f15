#pragma once
// CLBlast tuning table: parameters measured with CLBlast's tuners on known devices, applied
// with clblast::OverrideParameters when a matching device is opened.
//
// Tables are JSON files in opencl/tuning/ (one per device, written by scripts/tune_clblast.sh,
// embedded at build time). The environment variable SIMPLI_CLBLAST_TUNING may name one more
// table file, read at run time and applied after the embedded ones, or be "off" to keep
// CLBlast's own defaults. See docs/clblast_tuning.md.
#include <CL/cl.h>

#include <cstddef>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace simpli::ocl {

/// Applies the shipped parameters for `deviceName` (no-op for unknown devices). Returns the
/// number of kernel families overridden.
int applyGemmTuning(const std::string& deviceName, cl_device_id device);

struct TuningEntry {
  std::string kernel; ///< CLBlast kernel family: Xgemm, XgemmDirect, Copy, Pad, ...
  int precision = 32; ///< 32 or 64
  std::unordered_map<std::string, std::size_t> parameters;
};

struct TuningTable {
  std::string origin;                         ///< file the table came from, for messages
  std::string clblastDeviceName;              ///< CLBlast's name, e.g. "skylake-avx512-AMD EPYC"
  std::vector<std::string> openclDeviceNames; ///< CL_DEVICE_NAME values seen when tuning
  std::vector<TuningEntry> entries;
};

/// Parses one table; throws simpli::Error naming `origin`, the field and the value.
TuningTable parseTuningTable(const std::string& json, const std::string& origin);
/// True when the table was made for an OpenCL device called `deviceName` (CL_DEVICE_NAME).
/// PoCL prefixes its driver ("pthread-", "cpu-") to the CPU name CLBlast reports, so a name
/// ending in "-" + the CLBlast name matches too.
bool tableMatches(const TuningTable& table, const std::string& deviceName);
/// What the last applyGemmTuning() did, one line.
const std::string& lastTuningSummary();

/// Embedded tables keyed by file stem (generated from opencl/tuning/*.json).
const std::map<std::string, const char*>& embeddedTuningTables();

} // namespace simpli::ocl

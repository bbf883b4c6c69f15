#include "tuning.h"

#include "clblast_call.h"
#include "simpli/error.h"

#include <clblast.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

namespace simpli::ocl {
namespace {

constexpr const char* kFormat = "simpli-clblast-tuning/1";
constexpr const char* kEnvVar = "SIMPLI_CLBLAST_TUNING";

// Kernel families clblast::OverrideParameters accepts (CLBlast 1.5's database names).
const std::set<std::string>& knownKernels() {
  static const std::set<std::string> names = {
      "Xgemm",       "XgemmDirect", "Copy",        "Pad",      "Transpose", "Padtranspose",
      "GemmRoutine", "Xaxpy",       "Xdot",        "Xgemv",    "XgemvFast", "XgemvFastRot",
      "Xger",        "Invert",      "TrsvRoutine", "Xconvgemm"};
  return names;
}

std::string& summarySlot() {
  static std::string summary = "CLBlast tuning: not applied yet (no device opened)";
  return summary;
}

const nlohmann::json& field(const nlohmann::json& object, const char* name,
                            const std::string& where) {
  auto it = object.find(name);
  if (it == object.end())
    fail("CLBlast tuning table ", where, ": missing field \"", name, "\"");
  return *it;
}

std::string stringField(const nlohmann::json& object, const char* name, const std::string& where) {
  const auto& v = field(object, name, where);
  if (!v.is_string() || v.get<std::string>().empty())
    fail("CLBlast tuning table ", where, ": field \"", name, "\" must be a non-empty string, got ",
         v.dump());
  return v.get<std::string>();
}

TuningEntry parseEntry(const nlohmann::json& e, const std::string& where) {
  if (!e.is_object())
    fail("CLBlast tuning table ", where, ": expected an object, got ", e.dump());
  TuningEntry entry;
  entry.kernel = stringField(e, "kernel", where);
  if (!knownKernels().count(entry.kernel))
    fail("CLBlast tuning table ", where, ": field \"kernel\" has unknown kernel family \"",
         entry.kernel, "\"");
  const auto& precision = field(e, "precision", where);
  if (!precision.is_number_integer() || (precision.get<int>() != 32 && precision.get<int>() != 64))
    fail("CLBlast tuning table ", where, ": field \"precision\" must be 32 or 64, got ",
         precision.dump());
  entry.precision = precision.get<int>();
  const auto& params = field(e, "parameters", where);
  if (!params.is_object() || params.empty())
    fail("CLBlast tuning table ", where, ": field \"parameters\" must be a non-empty object, got ",
         params.dump());
  for (auto it = params.begin(); it != params.end(); ++it) {
    if (!it.value().is_number_unsigned())
      fail("CLBlast tuning table ", where, ": parameter \"", it.key(),
           "\" must be a non-negative integer, got ", it.value().dump());
    entry.parameters[it.key()] = it.value().get<std::size_t>();
  }
  return entry;
}

bool deviceHasFp64(cl_device_id device) {
  cl_device_fp_config config = 0;
  clGetDeviceInfo(device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof(config), &config, nullptr);
  return config != 0;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    fail(kEnvVar, "=", path, ": cannot open the CLBlast tuning table");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

} // namespace

TuningTable parseTuningTable(const std::string& json, const std::string& origin) {
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(json);
  } catch (const nlohmann::json::exception& e) {
    fail("CLBlast tuning table ", origin, ": invalid JSON (", e.what(), ")");
  }
  if (!root.is_object())
    fail("CLBlast tuning table ", origin, ": the top level must be an object");
  const std::string format = stringField(root, "format", origin);
  if (format != kFormat)
    fail("CLBlast tuning table ", origin, ": field \"format\" is \"", format, "\", expected \"",
         kFormat, "\"");
  TuningTable table;
  table.origin = origin;
  table.clblastDeviceName = stringField(root, "clblast_device_name", origin);
  if (auto it = root.find("opencl_device_names"); it != root.end()) {
    if (!it->is_array())
      fail("CLBlast tuning table ", origin, ": field \"opencl_device_names\" must be an array");
    for (const auto& n : *it) {
      if (!n.is_string())
        fail("CLBlast tuning table ", origin, ": field \"opencl_device_names\" holds ", n.dump(),
             ", not a string");
      table.openclDeviceNames.push_back(n.get<std::string>());
    }
  }
  const auto& kernels = field(root, "kernels", origin);
  if (!kernels.is_array() || kernels.empty())
    fail("CLBlast tuning table ", origin, ": field \"kernels\" must be a non-empty array");
  for (std::size_t i = 0; i < kernels.size(); ++i)
    table.entries.push_back(parseEntry(kernels[i], origin + " kernels[" + std::to_string(i) + "]"));
  return table;
}

bool tableMatches(const TuningTable& table, const std::string& deviceName) {
  for (const auto& name : table.openclDeviceNames)
    if (name == deviceName)
      return true;
  const std::string& c = table.clblastDeviceName;
  if (deviceName == c)
    return true;
  return deviceName.size() > c.size() + 1 &&
         deviceName.compare(deviceName.size() - c.size(), c.size(), c) == 0 &&
         deviceName[deviceName.size() - c.size() - 1] == '-';
}

const std::string& lastTuningSummary() {
  return summarySlot();
}

int applyGemmTuning(const std::string& deviceName, cl_device_id device) {
  const char* env = std::getenv(kEnvVar);
  const std::string override = env ? env : "";
  if (override == "off") {
    summarySlot() = "CLBlast tuning: off (" + std::string(kEnvVar) + "=off), CLBlast defaults";
    return 0;
  }
  std::vector<TuningTable> tables;
  for (const auto& [stem, text] : embeddedTuningTables())
    tables.push_back(parseTuningTable(text, "opencl/tuning/" + stem + ".json (embedded)"));
  if (!override.empty())
    tables.push_back(parseTuningTable(readFile(override), override));

  const bool fp64 = deviceHasFp64(device);
  int applied = 0;
  std::string sources, problems;
  for (const auto& table : tables) {
    if (!tableMatches(table, deviceName))
      continue;
    sources += (sources.empty() ? "" : ", ") + table.origin;
    for (const auto& e : table.entries) {
      if (e.precision == 64 && !fp64)
        continue;
      const auto precision =
          e.precision == 64 ? clblast::Precision::kDouble : clblast::Precision::kSingle;
      const auto status = clblast::OverrideParameters(device, e.kernel, precision, e.parameters);
      if (status == clblast::StatusCode::kSuccess)
        ++applied;
      else
        problems += " " + e.kernel + "/fp" + std::to_string(e.precision) + ": " +
                    blas::statusName(static_cast<int>(status)) + ";";
    }
  }
  if (sources.empty())
    summarySlot() = "CLBlast tuning: no table for device \"" + deviceName +
                    "\", CLBlast defaults (see docs/clblast_tuning.md)";
  else
    summarySlot() = "CLBlast tuning: " + std::to_string(applied) +
                    " kernel parameter set(s) for \"" + deviceName + "\" from " + sources +
                    (problems.empty() ? "" : "; not applied:" + problems);
  return applied;
}

} // namespace simpli::ocl

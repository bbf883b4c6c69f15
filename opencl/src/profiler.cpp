#include "simpli/ocl/profiler.h"

#include "simpli/ocl/device.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>

namespace simpli::ocl {
namespace {

struct State {
  bool enabled = false;
  bool printAtExit = false;
  std::mutex mutex;
  std::map<std::string, ProfileEntry> table;

  State() {
    const char* env = std::getenv("SIMPLI_PROFILE");
    enabled = printAtExit = env && *env && std::string(env) != "0";
  }
  ~State() {
    if (printAtExit && !table.empty())
      std::fputs(Profiler::report().c_str(), stderr);
  }
};

State& state() {
  static State s;
  return s;
}

double nowMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

} // namespace

bool Profiler::enabled() {
  return state().enabled;
}

void Profiler::setEnabled(bool on) {
  state().enabled = on;
}

std::vector<ProfileEntry> Profiler::entries() {
  State& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  std::vector<ProfileEntry> out;
  for (const auto& [name, e] : s.table)
    out.push_back(e);
  std::sort(out.begin(), out.end(),
            [](const ProfileEntry& a, const ProfileEntry& b) { return a.ms > b.ms; });
  return out;
}

void Profiler::reset() {
  State& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  s.table.clear();
}

std::string Profiler::report(std::size_t rows) {
  const auto all = entries();
  double total = 0;
  for (const auto& e : all)
    total += e.ms;
  std::string text = "simpli profile (device calls, wall time with the queue finished around "
                     "each):\n";
  char line[256];
  std::snprintf(line, sizeof line, "%-52s %8s %11s %6s %9s\n", "kernel", "calls", "total ms", "%",
                "ms/call");
  text += line;
  for (std::size_t i = 0; i < all.size() && i < rows; ++i) {
    const auto& e = all[i];
    std::snprintf(line, sizeof line, "%-52s %8lld %11.1f %6.1f %9.3f\n", e.name.c_str(),
                  static_cast<long long>(e.calls), e.ms, total > 0 ? 100.0 * e.ms / total : 0.0,
                  e.calls ? e.ms / double(e.calls) : 0.0);
    text += line;
  }
  std::snprintf(line, sizeof line, "%-52s %8s %11.1f\n", "total", "", total);
  text += line;
  return text;
}

Profiler::Scope::Scope(const char* name) {
  if (!state().enabled)
    return;
  owned_ = name;
  name_ = owned_.c_str();
  Device::current().finish();
  start_ = nowMs();
}

Profiler::Scope::~Scope() {
  if (!name_)
    return;
  try {
    Device::current().finish();
  } catch (...) {
    return; // the failing call reports its own error
  }
  const double ms = nowMs() - start_;
  State& s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  ProfileEntry& e = s.table[owned_];
  e.name = owned_;
  ++e.calls;
  e.ms += ms;
}

} // namespace simpli::ocl

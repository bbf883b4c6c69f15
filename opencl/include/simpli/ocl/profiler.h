#pragma once
// A per-kernel time profile of the engine, for finding where a workload spends its time.
// Enabled by the environment (SIMPLI_PROFILE=1) or by Profiler::setEnabled(true). While
// enabled, every kernel launch and every CLBlast GEMM finishes the device queue before and
// after it and adds its wall time to a table keyed by name ("program.kernel" or
// "clblast.Gemm" / "clblast.GemmStridedBatched"), so the times are exact per entry but the
// whole run is slower (no overlap). With SIMPLI_PROFILE set, the table is printed to stderr at
// exit.
#include <cstdint>
#include <string>
#include <vector>

namespace simpli::ocl {

struct ProfileEntry {
  std::string name;
  int64_t calls = 0;
  double ms = 0; ///< total wall time
};

class Profiler {
public:
  static bool enabled();
  static void setEnabled(bool on);
  /// Entries sorted by total time, largest first.
  static std::vector<ProfileEntry> entries();
  static void reset();
  /// The table as text (top `rows` entries, plus the total).
  static std::string report(std::size_t rows = 40);

  /// Times one device call: finishes the queue at construction and destruction when enabled.
  class Scope {
  public:
    explicit Scope(const char* name);
    Scope(const std::string& name) : Scope(name.c_str()) {}
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

  private:
    const char* name_ = nullptr;
    std::string owned_;
    double start_ = 0;
  };
};

} // namespace simpli::ocl

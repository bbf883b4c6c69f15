#pragma once
// Shared pieces of the VTK tests: synthetic MLIs, a private temporary folder, an ErrorEvent
// recorder and a run that records an algorithm's errors.
#include <filesystem>
#include <string>
#include <vector>

#include <vtkAlgorithm.h>
#include <vtkCommand.h>

#include "simpli/model/mli/mli.h"

namespace simpli::vtktest {

namespace fs = std::filesystem;

/// A rotated, translated camera with an off-centre principal point.
scene::Camera testCamera(int W, int H);

/// L layers, back layers farther; random RGBA in [0, 1] and depths in [d(k), 2 d(k)].
mli::MLI randomMLI(int L, int H, int W, unsigned seed);

/// A fresh empty folder under the system temp folder, removed with its contents at the end.
class TempDir {
public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

private:
  fs::path path_;
};

/// Sorted entry names of `folder` (hidden ones included).
std::vector<std::string> listDir(const fs::path& folder);

void writeText(const fs::path& file, const std::string& text);

/// Records the message of every ErrorEvent (and so keeps them off stderr).
class ErrorRecorder : public vtkCommand {
public:
  static ErrorRecorder* New() { return new ErrorRecorder; }
  void Execute(vtkObject*, unsigned long, void* callData) override {
    messages.emplace_back(callData ? static_cast<const char*>(callData) : "");
  }
  /// True if one message contains all of `parts`.
  bool has(const std::vector<std::string>& parts) const;
  std::string all() const;
  std::vector<std::string> messages;
};

/// Runs `alg` through its executive with `errors` observing the algorithm's ErrorEvents (the
/// executive's "returned failure for request" is expected and muted); returns the executive's
/// result (1 = success).
int runWithErrors(vtkAlgorithm* alg, ErrorRecorder* errors);

} // namespace simpli::vtktest

#pragma once
// Shared pieces of the VTK tests: synthetic MLIs, an ErrorEvent recorder and a run that records
// an algorithm's errors (temporary folders: tests/support).
#include <filesystem>
#include <string>
#include <vector>

#include <vtkAlgorithm.h>
#include <vtkCommand.h>

#include "simpli/model/mli/mli.h"
#include "support/temp_dir.h"

namespace simpli::vtktest {

namespace fs = std::filesystem;

/// A rotated, translated camera with an off-centre principal point.
scene::Camera testCamera(int W, int H);

/// L layers, back layers farther; random RGBA in [0, 1] and depths in [d(k), 2 d(k)].
mli::MLI randomMLI(int L, int H, int W, unsigned seed);

using test::listDir;
using test::TempDir;
using test::writeText;

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

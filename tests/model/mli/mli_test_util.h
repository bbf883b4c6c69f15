#pragma once
// Shared helpers for the MLI tests: synthetic MLIs, a private temporary folder, error checks.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "simpli/model/mli/mli.h"

namespace simpli::test {

namespace fs = std::filesystem;

/// A rotated, translated camera with an off-centre principal point (fx != fy).
scene::Camera generalCamera(int W, int H);

/// Uniform random depth in [dmin, dmax] and RGBA in [0, 1], with a general camera.
mli::MLI randomMLI(int L, int H, int W, unsigned seed, float dmin = 1.0f, float dmax = 50.0f);

/// Smooth colour, alpha and depth (low-frequency sines), what JPEG handles well.
mli::MLI smoothMLI(int L, int H, int W);

/// A fresh empty folder under the system temp folder, removed with everything in it when the
/// object dies. Unique per process and object, so parallel ctest runs do not collide.
class TempDir {
public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }
  fs::path operator/(const std::string& name) const { return path_ / name; }

private:
  fs::path path_;
};

/// Sorted names of the entries of `folder` (hidden ones included).
std::vector<std::string> listDir(const fs::path& folder);

/// Runs `f`, expects a simpli::Error whose message contains every string in `parts`.
void expectError(const std::function<void()>& f, const std::vector<std::string>& parts);

std::string readText(const fs::path& file);
void writeText(const fs::path& file, const std::string& text);

} // namespace simpli::test

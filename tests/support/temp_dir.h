#pragma once
// A private temporary folder for a test, and small file helpers.
#include <filesystem>
#include <string>
#include <vector>

namespace simpli::test {

/// A fresh empty folder under the system temporary folder, removed with everything in it when
/// the object dies. The name holds the process id, a counter and a random number, so parallel
/// ctest runs and several folders in one test never collide.
class TempDir {
public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// path() / name (converts to std::string where a string is expected).
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  /// path() / child as a string; the folder itself when child is empty.
  std::string str(const std::string& child = "") const;

private:
  std::filesystem::path path_;
};

/// Sorted names of the entries of `folder` (hidden ones included).
std::vector<std::string> listDir(const std::filesystem::path& folder);

/// A whole file as bytes / writes bytes, replacing the file (for corrupting fixtures).
std::string readText(const std::filesystem::path& file);
void writeText(const std::filesystem::path& file, const std::string& text);

} // namespace simpli::test

// Checks before writing one output file (output_file.h).
#include "output_file.h"

#include "simpli/error.h"
#include "simpli/model/io/staged_folder.h"

#include <filesystem>

namespace simpli::app {

void checkOutputFile(const std::string& path, const std::string& what, bool force,
                     const std::string& folderHint) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec))
    fail(what, " ", path, " is a folder; ", folderHint);
  if (fs::exists(path, ec) && !force)
    fail(what, " ", path, " already exists (use --force to replace it)");
  // The file appears by a rename in its folder: that folder must be writable.
  const std::string parent =
      fs::path(path).parent_path().empty() ? "." : fs::path(path).parent_path().string();
  if (!fs::is_directory(parent, ec))
    fail(what, " ", path, ": its folder ", parent, " does not exist");
  io::checkOutputLocation(parent, what + " folder");
}

} // namespace simpli::app

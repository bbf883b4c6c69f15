// listImageFiles: the image files of a folder, in a deterministic (sorted) order.
#include "simpli/error.h"
#include "simpli/model/scene/readers.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace fs = std::filesystem;

namespace simpli::scene {

namespace {
bool isImageExtension(std::string ext) {
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return char(std::tolower(ch)); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}
} // namespace

std::vector<std::string> listImageFiles(const std::string& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    fail("image folder '", folder, "' does not exist");
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    if (entry.is_regular_file(ec) && isImageExtension(entry.path().extension().string()))
      files.push_back(entry.path().string());
  }
  if (ec)
    fail("cannot list image folder '", folder, "': ", ec.message());
  // Byte-wise order of the file names, as LLFF's sorted(os.listdir(...)).
  std::sort(files.begin(), files.end());
  return files;
}

} // namespace simpli::scene

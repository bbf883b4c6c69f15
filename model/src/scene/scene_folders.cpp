// Folders of scene folders (scene/scene_folders.h).
#include "simpli/model/scene/scene_folders.h"

#include "simpli/error.h"
#include "simpli/model/scene/scene.h"

#include <algorithm>
#include <filesystem>

namespace simpli::scene {

namespace fs = std::filesystem;

bool isSceneFolder(const std::string& path) {
  try {
    detectSceneFormat(path);
    return true;
  } catch (const Error&) {
    return false;
  }
}

std::vector<SceneFolder> listSceneFolders(const std::string& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec))
    fail("scene folder collection '", folder, "' does not exist");
  if (!fs::is_directory(folder, ec))
    fail("scene folder collection '", folder, "' is not a folder");
  std::vector<SceneFolder> scenes;
  for (const fs::directory_entry& e : fs::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    if (!e.is_directory(ec) || name.empty() || name[0] == '.')
      continue;
    SceneFolder s;
    s.name = name;
    s.path = e.path().string();
    try {
      detectSceneFormat(s.path);
    } catch (const Error& err) {
      s.problem = err.what();
    }
    scenes.push_back(std::move(s));
  }
  if (ec)
    fail("scene folder collection '", folder, "': cannot list it: ", ec.message());
  std::sort(scenes.begin(), scenes.end(),
            [](const SceneFolder& a, const SceneFolder& b) { return a.name < b.name; });
  return scenes;
}

} // namespace simpli::scene

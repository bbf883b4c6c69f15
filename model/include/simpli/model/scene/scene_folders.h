#pragma once
// A folder of scene folders: the training data of `simpli train DATA` and the collection of
// `simpli infer SCENES_DIR` (each subfolder a scene detectSceneFormat recognises).
#include <string>
#include <vector>

namespace simpli::scene {

struct SceneFolder {
  std::string name; ///< the subfolder's name
  std::string path; ///< folder / name
  /// Why detectSceneFormat refused it (its error message); empty for a scene folder.
  std::string problem;
};

/// True when `path` is a scene folder itself (detectSceneFormat accepts it).
bool isSceneFolder(const std::string& path);

/// The subfolders of `folder`, sorted by name, hidden ones (".name") skipped, each with what
/// detectSceneFormat says of it. Throws simpli::Error naming the folder when it does not exist
/// or is not a folder.
std::vector<SceneFolder> listSceneFolders(const std::string& folder);

} // namespace simpli::scene

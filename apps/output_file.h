#pragma once
// The checks before a command writes one output file (written atomically elsewhere):
// `simpli convert ... OUT.glb` and `simpli widen --out / --config-out`.
#include <string>

namespace simpli::app {

/// Throws simpli::Error ("<what> <path> ...") unless `path` may be written as one file: not a
/// folder (`folderHint` tells what to give instead), an existing file only with `force`, and its
/// folder existing and writable (io::checkOutputLocation), all before any long work.
void checkOutputFile(const std::string& path, const std::string& what, bool force,
                     const std::string& folderHint);

} // namespace simpli::app

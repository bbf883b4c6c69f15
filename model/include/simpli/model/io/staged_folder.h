#pragma once
// A folder written as a whole: everything goes into a hidden staging sibling, which replaces the
// target in one step only when it is complete. Used by every command that writes an output
// folder (MLI files, `simpli infer --out`).
//
// Names beside the target `parent/NAME`:
//   .NAME.simpli-tmp-PID  the staging folder of process PID (after an atomic exchange: the old
//                         folder, about to be removed)
//   .NAME.simpli-old-PID  the old folder, moved aside where the file system has no atomic
//                         exchange (rename old aside, rename new in, remove old)
// A crash (SIGKILL, power loss) at any point leaves the old complete folder or the new complete
// one at `parent/NAME`, except between the two renames of the move-aside path, where NAME is
// missing and .NAME.simpli-old-PID holds the old folder. The next StagedFolder for the same
// target recovers: it moves such an old folder back (when NAME is missing) and removes the
// staging and old folders of processes that no longer run (and of its own PID, left by an
// earlier process of that number). Folders of live processes are left alone. So one process
// writes a given target through one StagedFolder at a time.
#include <filesystem>
#include <functional>
#include <string>

namespace simpli::io {

/// Why the existing, non-empty folder `folder` must not be replaced as a whole; "" when it may.
/// Must not modify anything.
using ReplaceCheck = std::function<std::string(const std::filesystem::path& folder)>;

/// Throws simpli::Error ("<what>: refusing to replace <target>: <why>") unless `target` is
/// absent, an empty folder, or a folder (not a symbolic link) for which `replaceable` returns "".
/// Writes nothing; commands call it before long work so that they fail early.
void checkReplaceable(const std::string& target, const ReplaceCheck& replaceable,
                      const std::string& what);

/// Throws simpli::Error ("<what> <target>: <why>") unless a folder can be written at `target`:
/// the nearest existing ancestor of `target` (its parent when `createParents` is false, which must
/// then exist) is a folder, not a file, and a folder can be created in it (probed by creating and
/// removing a hidden folder: catches permissions, read-only file systems and pseudo file systems
/// alike). `target` itself, when it exists, must be a folder. Commands call it before any long
/// work, so that a bad --out fails at once with a named error.
void checkOutputLocation(const std::string& target, const std::string& what,
                         bool createParents = false);

struct StagedFolderOptions {
  /// Prefix of error messages ("writeMLI", "--out").
  std::string what = "output folder";
  /// Testing: false takes the move-aside path that file systems without RENAME_EXCHANGE take.
  bool atomicExchange = true;
};

class StagedFolder {
public:
  /// Recovers what killed writers of `target` left (see above), checks `target` with
  /// checkReplaceable and that its parent folder exists, and creates the empty staging folder.
  /// Throws simpli::Error naming the path.
  StagedFolder(const std::string& target, ReplaceCheck replaceable,
               StagedFolderOptions options = {});
  /// Removes the staging folder (and everything in it) unless commit() succeeded.
  ~StagedFolder();
  StagedFolder(const StagedFolder&) = delete;
  StagedFolder& operator=(const StagedFolder&) = delete;

  /// The staging folder to fill.
  const std::filesystem::path& path() const { return staging_; }
  /// The folder that commit() replaces (normalised: no trailing slash).
  const std::filesystem::path& target() const { return target_; }

  /// Flushes the staging tree to disk, checks `target` again (it may have changed since the
  /// constructor) and moves the staging folder into place, replacing the old folder. On failure
  /// the old folder is left as it was and the staging folder is removed.
  void commit();

private:
  void moveIntoPlace();

  std::filesystem::path target_, parent_, staging_;
  std::string name_;
  ReplaceCheck replaceable_;
  StagedFolderOptions options_;
  bool committed_ = false;
};

/// Recovers and removes what killed StagedFolders of `target` left beside it (see the header
/// comment); returns how many leftover folders it removed or moved back. Never throws.
int recoverStagedFolders(const std::string& target);

} // namespace simpli::io

// Atomic folder writes for MLI output (see mli/files_internal.h): write everything into a hidden
// temporary sibling, flush it, then rename it into place, so that readers (and a crash) only
// ever see the old complete folder or the new complete folder.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <sstream>

#include <fcntl.h>
#include <unistd.h>

#include "mli/files_internal.h"
#include "simpli/error.h"

namespace simpli::mli {

namespace {

std::string errnoText(int err) {
  return std::strerror(err);
}

// fsync a file or folder; the rename is only durable once the data it points to is.
void syncPath(const fs::path& path, bool directory) {
  const int fd = ::open(path.c_str(), O_RDONLY | (directory ? O_DIRECTORY : 0) | O_CLOEXEC);
  if (fd < 0)
    fail(path.string(), ": cannot open to flush (", errnoText(errno), ")");
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  // Some file systems (e.g. some FUSE mounts) cannot fsync a folder; the data files matter more.
  if (rc != 0 && !(directory && (err == EINVAL || err == ENOTSUP)))
    fail(path.string(), ": flush to disk failed (", errnoText(err), ")");
}

void syncFolderTree(const fs::path& folder) {
  for (const fs::directory_entry& e : fs::directory_iterator(folder))
    if (e.is_regular_file())
      syncPath(e.path(), false);
  syncPath(folder, true);
}

std::string uniqueSuffix() {
  std::random_device rd;
  std::ostringstream os;
  os << ::getpid() << '-' << std::hex << rd() << rd();
  return os.str();
}

// A fresh hidden sibling folder ".<name>.<tag>-<pid>-<random>".
fs::path makeSibling(const fs::path& parent, const std::string& name, const std::string& tag) {
  for (int attempt = 0; attempt < 16; ++attempt) {
    const fs::path p = parent / ("." + name + "." + tag + "-" + uniqueSuffix());
    std::error_code ec;
    if (fs::create_directory(p, ec))
      return p;
    if (ec)
      fail(p.string(), ": cannot create temporary folder (", ec.message(), ")");
  }
  fail(parent.string(), ": cannot find a free temporary folder name for ", name);
}

void removeQuietly(const fs::path& p) {
  std::error_code ec;
  fs::remove_all(p, ec);
}

// Moves `tmp` onto the existing folder `target`. Prefers an atomic exchange; where the file
// system lacks it, moves the old folder aside first (a short window without `target`, but
// never a partial one) and moves it back if the second rename fails.
void replaceFolder(const fs::path& tmp, const fs::path& target, const fs::path& parent,
                   const std::string& name) {
#ifdef RENAME_EXCHANGE
  if (::renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
    removeQuietly(tmp); // now holds the old folder
    return;
  }
  if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
    fail(target.string(), ": cannot replace with the new MLI (", errnoText(errno), ")");
#endif
  const fs::path old = parent / ("." + name + ".old-" + uniqueSuffix());
  if (::rename(target.c_str(), old.c_str()) != 0)
    fail(target.string(), ": cannot move the old MLI aside (", errnoText(errno), ")");
  if (::rename(tmp.c_str(), target.c_str()) != 0) {
    const int err = errno;
    ::rename(old.c_str(), target.c_str());
    fail(target.string(), ": cannot move the new MLI into place (", errnoText(err), ")");
  }
  removeQuietly(old);
}

} // namespace

void writeFolderAtomically(const fs::path& requested,
                           const std::function<void(const fs::path& tmp)>& fill) {
  // "out/scene/" names the folder "out/scene".
  fs::path target = requested.lexically_normal();
  if (!target.has_filename())
    target = target.parent_path();
  const std::string name = target.filename().string();
  if (name.empty() || name == "." || name == "..")
    fail("writeMLI: \"", requested.string(), "\" does not name a folder to write");
  fs::path parent = target.parent_path();
  if (parent.empty())
    parent = ".";

  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    fail("writeMLI: ", target.string(), ": parent folder ", parent.string(), " does not exist");
  const bool exists = fs::exists(fs::symlink_status(target, ec));
  if (exists) {
    if (!fs::is_directory(fs::symlink_status(target, ec)))
      fail("writeMLI: ", target.string(), " exists and is not a folder; refusing to replace it");
    // Replacing means deleting the old contents: only do that to something that is an MLI.
    if (!fs::is_empty(target, ec) && !fs::exists(target / "meta.json", ec))
      fail("writeMLI: ", target.string(), " exists and is not an MLI folder (no meta.json); ",
           "refusing to replace it");
  }

  const fs::path tmp = makeSibling(parent, name, "tmp");
  try {
    fill(tmp);
    syncFolderTree(tmp);
    if (!exists) {
      if (::rename(tmp.c_str(), target.c_str()) != 0)
        fail(target.string(), ": cannot move the new MLI into place (", errnoText(errno), ")");
    } else {
      replaceFolder(tmp, target, parent, name);
    }
  } catch (const fs::filesystem_error& e) {
    removeQuietly(tmp);
    fail("writeMLI: ", target.string(), ": ", e.what());
  } catch (...) {
    removeQuietly(tmp);
    throw;
  }
  // Make the rename itself durable; a failure here cannot undo the (complete) write.
  try {
    syncPath(parent, true);
  } catch (const Error&) {
  }
}

} // namespace simpli::mli

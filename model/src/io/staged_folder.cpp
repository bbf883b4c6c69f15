// Folders written as a whole through a hidden staging sibling (io/staged_folder.h).
#include "simpli/model/io/staged_folder.h"

#include "simpli/error.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace simpli::io {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStagingTag = ".simpli-tmp-";
constexpr const char* kOldTag = ".simpli-old-";

std::string errnoText(int err) {
  return std::strerror(err);
}

/// `parent` and `name` of a target path ("out/scene/" names the folder "out/scene").
struct TargetPath {
  fs::path target, parent;
  std::string name;
};

TargetPath splitTarget(const std::string& requested, const std::string& what) {
  TargetPath t;
  t.target = fs::path(requested).lexically_normal();
  if (!t.target.has_filename())
    t.target = t.target.parent_path();
  t.name = t.target.filename().string();
  if (t.name.empty() || t.name == "." || t.name == "..")
    fail(what, ": \"", requested, "\" does not name a folder to write");
  t.parent = t.target.parent_path();
  if (t.parent.empty())
    t.parent = ".";
  return t;
}

fs::path siblingName(const TargetPath& t, const char* tag, long pid) {
  return t.parent / ("." + t.name + tag + std::to_string(pid));
}

/// The PID in a leftover's name ".NAME<tag>PID", -1 when `file` is not such a name.
long leftoverPid(const std::string& file, const std::string& name, const char* tag) {
  const std::string prefix = "." + name + tag;
  if (file.size() <= prefix.size() || file.compare(0, prefix.size(), prefix) != 0)
    return -1;
  const std::string digits = file.substr(prefix.size());
  if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos)
    return -1;
  return std::stol(digits);
}

/// Whether a leftover of process `pid` belongs to nobody: the process is gone, or the PID is
/// ours (then it was left by an earlier process with this PID, e.g. PID 1 in a container).
bool leftoverIsStale(long pid) {
  if (pid <= 0)
    return false;
  if (pid == static_cast<long>(::getpid()))
    return true;
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
}

bool isRealFolder(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(fs::symlink_status(p, ec));
}

void removeQuietly(const fs::path& p) {
  std::error_code ec;
  fs::remove_all(p, ec);
}

// fsync a file or folder; a rename is only durable once the data it points to is.
void syncPath(const fs::path& path, bool directory, const std::string& what) {
  const int fd = ::open(path.c_str(), O_RDONLY | (directory ? O_DIRECTORY : 0) | O_CLOEXEC);
  if (fd < 0)
    fail(what, ": ", path.string(), ": cannot open to flush (", errnoText(errno), ")");
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  // Some file systems (e.g. some FUSE mounts) cannot fsync a folder; the data files matter more.
  if (rc != 0 && !(directory && (err == EINVAL || err == ENOTSUP)))
    fail(what, ": ", path.string(), ": flush to disk failed (", errnoText(err), ")");
}

void syncTree(const fs::path& folder, const std::string& what) {
  for (const fs::directory_entry& e : fs::directory_iterator(folder)) {
    if (e.is_symlink())
      continue;
    if (e.is_directory())
      syncTree(e.path(), what);
    else if (e.is_regular_file())
      syncPath(e.path(), false, what);
  }
  syncPath(folder, true, what);
}

/// True when `target` exists (then it passed the checks), false when it is absent.
bool checkTarget(const fs::path& target, const ReplaceCheck& replaceable, const std::string& what) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(target, ec);
  if (!fs::exists(status))
    return false;
  auto refuse = [&](const std::string& why) {
    fail(what, ": refusing to replace ", target.string(), ": ", why,
         "; move it away or choose another folder");
  };
  if (fs::is_symlink(status))
    refuse("it is a symbolic link");
  if (!fs::is_directory(status))
    refuse("it exists and is not a folder");
  const bool empty = fs::is_empty(target, ec);
  if (ec)
    refuse("its contents cannot be listed (" + ec.message() + ")");
  if (!empty) {
    const std::string why = replaceable ? replaceable(target) : "it is not empty";
    if (!why.empty())
      refuse(why);
  }
  return true;
}

} // namespace

void checkReplaceable(const std::string& target, const ReplaceCheck& replaceable,
                      const std::string& what) {
  checkTarget(splitTarget(target, what).target, replaceable, what);
}

namespace {

/// Why no folder can be created in the folder `dir` ("" when one can): creates and removes a
/// hidden probe folder.
std::string cannotCreateIn(const fs::path& dir) {
  const fs::path probe = dir / (".simpli-probe-" + std::to_string(::getpid()));
  if (::mkdir(probe.c_str(), 0700) != 0) {
    const int err = errno;
    if (err != EEXIST)
      return "cannot create a folder in " + dir.string() + " (" + errnoText(err) + ")";
  }
  ::rmdir(probe.c_str());
  return "";
}

} // namespace

void checkOutputLocation(const std::string& requested, const std::string& what,
                         bool createParents) {
  const TargetPath t = splitTarget(requested, what);
  const std::string head = what + " " + requested + ": ";
  std::error_code ec;
  const fs::file_status target = fs::status(t.target, ec);
  if (fs::exists(target) && !fs::is_directory(target))
    fail(head, "it exists and is not a folder");
  fs::path dir = t.parent;
  while (createParents && !fs::exists(fs::status(dir, ec))) {
    const fs::path up = dir.parent_path();
    if (up == dir)
      break;
    dir = up.empty() ? fs::path(".") : up;
  }
  const fs::file_status parent = fs::status(dir, ec);
  if (!fs::exists(parent))
    fail(head, "parent folder ", dir.string(), " does not exist");
  if (!fs::is_directory(parent))
    fail(head, dir.string(), " is a file, not a folder");
  std::string why = cannotCreateIn(dir);
  if (why.empty() && fs::is_directory(target))
    why = cannotCreateIn(t.target);
  if (!why.empty())
    fail(head, why);
}

int recoverStagedFolders(const std::string& requested) {
  TargetPath t;
  try {
    t = splitTarget(requested, "recoverStagedFolders");
  } catch (const Error&) {
    return 0;
  }
  std::error_code ec;
  fs::directory_iterator it(t.parent, ec), end;
  if (ec)
    return 0;
  std::vector<fs::path> staging, old;
  for (; it != end; it.increment(ec)) {
    const std::string file = it->path().filename().string();
    if (!isRealFolder(it->path()))
      continue;
    if (leftoverIsStale(leftoverPid(file, t.name, kStagingTag)))
      staging.push_back(it->path());
    else if (leftoverIsStale(leftoverPid(file, t.name, kOldTag)))
      old.push_back(it->path());
    if (ec)
      break;
  }
  int recovered = 0;
  // A writer killed between "old aside" and "new in": the old folder goes back. Its staging
  // folder may be complete, but nothing recorded that, so the old complete folder wins.
  if (!old.empty() && !fs::exists(fs::symlink_status(t.target, ec))) {
    if (::rename(old.front().c_str(), t.target.c_str()) == 0) {
      old.erase(old.begin());
      ++recovered;
    }
  }
  for (const std::vector<fs::path>* list : {&staging, &old})
    for (const fs::path& p : *list) {
      fs::remove_all(p, ec);
      if (!ec)
        ++recovered;
    }
  return recovered;
}

StagedFolder::StagedFolder(const std::string& target, ReplaceCheck replaceable,
                           StagedFolderOptions options)
    : replaceable_(std::move(replaceable)), options_(std::move(options)) {
  const std::string& what = options_.what;
  const TargetPath t = splitTarget(target, what);
  target_ = t.target;
  parent_ = t.parent;
  name_ = t.name;
  if (!isRealFolder(parent_))
    fail(what, ": ", target_.string(), ": parent folder ", parent_.string(), " does not exist");
  recoverStagedFolders(target_.string());
  checkTarget(target_, replaceable_, what);

  staging_ = siblingName(t, kStagingTag, static_cast<long>(::getpid()));
  std::error_code ec;
  if (!fs::create_directory(staging_, ec))
    fail(what, ": ", target_.string(), ": cannot create the staging folder ", staging_.string(),
         " (", ec ? ec.message() : std::string("it already exists"), ")");
}

StagedFolder::~StagedFolder() {
  if (!committed_)
    removeQuietly(staging_);
}

void StagedFolder::commit() {
  if (committed_)
    fail(options_.what, ": ", target_.string(), ": already committed");
  try {
    moveIntoPlace();
  } catch (...) {
    if (!committed_)
      removeQuietly(staging_);
    throw;
  }
  // Make the rename itself durable; a failure here cannot undo the (complete) write.
  try {
    syncPath(parent_, true, options_.what);
  } catch (const Error&) {
  }
}

void StagedFolder::moveIntoPlace() {
  const std::string& what = options_.what;
  try {
    syncTree(staging_, what);
  } catch (const fs::filesystem_error& e) {
    fail(what, ": ", target_.string(), ": ", e.what());
  }
  const bool exists = checkTarget(target_, replaceable_, what);
  // rename() moves a folder onto an absent name or an empty folder in one step.
  std::error_code ec;
  if (!exists || fs::is_empty(target_, ec)) {
    if (::rename(staging_.c_str(), target_.c_str()) != 0)
      fail(what, ": ", target_.string(), ": cannot move ", staging_.string(), " into place (",
           errnoText(errno), ")");
    committed_ = true;
  }
#ifdef RENAME_EXCHANGE
  if (!committed_ && options_.atomicExchange) {
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
      committed_ = true;
      removeQuietly(staging_); // now the old folder; a crash here leaves a stale staging folder
    } else if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP) {
      fail(what, ": ", target_.string(), ": cannot exchange it with ", staging_.string(), " (",
           errnoText(errno), ")");
    }
  }
#endif
  if (!committed_) {
    // Old aside, new in, old removed; a crash between the renames is undone by the next writer.
    const fs::path old = parent_ / ("." + name_ + kOldTag + std::to_string(::getpid()));
    removeQuietly(old);
    if (::rename(target_.c_str(), old.c_str()) != 0)
      fail(what, ": ", target_.string(), ": cannot move the old folder aside to ", old.string(),
           " (", errnoText(errno), ")");
    if (::rename(staging_.c_str(), target_.c_str()) != 0) {
      const int err = errno;
      ::rename(old.c_str(), target_.c_str());
      fail(what, ": ", target_.string(), ": cannot move ", staging_.string(), " into place (",
           errnoText(err), ")");
    }
    committed_ = true;
    removeQuietly(old);
  }
}

} // namespace simpli::io

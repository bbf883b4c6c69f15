// Folders written as a whole (io/staged_folder.h): nothing appears before the commit, a refused
// folder is never touched, both replace paths leave only the new folder, and what a killed
// writer left behind (at every point of the replace) is recovered by the next writer.
#include "support/expect_error.h"
#include "support/temp_dir.h"

#include "simpli/model/io/staged_folder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

using namespace simpli;
using simpli::test::expectError;
using simpli::test::listDir;
using simpli::test::readText;
using simpli::test::TempDir;
using simpli::test::writeText;
namespace fs = std::filesystem;

namespace {

// Accepts a folder whose only entries are files named "own*" (a stand-in for "an MLI simpli
// wrote"); names the first other entry.
std::string onlyOwnFiles(const fs::path& folder) {
  for (const fs::directory_entry& e : fs::directory_iterator(folder)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("own", 0) != 0 || !e.is_regular_file())
      return "it holds \"" + name + "\"";
  }
  return "";
}

io::StagedFolderOptions named(const std::string& what, bool exchange = true) {
  io::StagedFolderOptions o;
  o.what = what;
  o.atomicExchange = exchange;
  return o;
}

// The PID of a process that has exited and been reaped.
long deadPid() {
  const pid_t pid = ::fork();
  if (pid == 0)
    ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return static_cast<long>(pid);
}

std::string hidden(const std::string& name, const char* tag, long pid) {
  return "." + name + tag + std::to_string(pid);
}

TEST(StagedFolder, NewFolderAppearsOnlyOnCommit) {
  TempDir dir;
  const fs::path target = dir / "out";
  {
    io::StagedFolder staged(target.string(), onlyOwnFiles, named("test"));
    writeText(staged.path() / "own_a", "new");
    EXPECT_FALSE(fs::exists(target)) << "nothing at the target before the commit";
    EXPECT_EQ(staged.path().parent_path(), dir.path());
    EXPECT_EQ(staged.path().filename().string(), ".out.simpli-tmp-" + std::to_string(::getpid()));
    staged.commit();
  }
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"out"}) << "no staging folder left";
  EXPECT_EQ(readText(target / "own_a"), "new");
}

TEST(StagedFolder, WithoutCommitNothingIsLeft) {
  TempDir dir;
  fs::create_directory(dir / "out");
  writeText(dir / "out" / "own_old", "old");
  {
    io::StagedFolder staged((dir / "out").string(), onlyOwnFiles, named("test"));
    writeText(staged.path() / "own_new", "new");
  } // e.g. an exception or a cancel before the commit
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"out"});
  EXPECT_EQ(listDir(dir / "out"), std::vector<std::string>{"own_old"});
}

class StagedFolderReplace : public ::testing::TestWithParam<bool> {};

TEST_P(StagedFolderReplace, LeavesOnlyTheNewFolder) {
  TempDir dir;
  const fs::path target = dir / "out";
  fs::create_directory(target);
  writeText(target / "own_old", "old");
  io::StagedFolder staged(target.string() + "/", onlyOwnFiles, named("test", GetParam()));
  EXPECT_EQ(staged.target(), target) << "a trailing slash names the same folder";
  writeText(staged.path() / "own_new", "new");
  fs::create_directory(staged.path() / "sub");
  writeText(staged.path() / "sub" / "x", "nested");
  staged.commit();
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"out"}) << "no staging or old folder";
  EXPECT_EQ(listDir(target), (std::vector<std::string>{"own_new", "sub"}));
  EXPECT_EQ(readText(target / "sub" / "x"), "nested");
}

TEST_P(StagedFolderReplace, FillsAnEmptyFolder) {
  TempDir dir;
  fs::create_directory(dir / "out");
  io::StagedFolder staged((dir / "out").string(), onlyOwnFiles, named("test", GetParam()));
  writeText(staged.path() / "own_new", "new");
  staged.commit();
  EXPECT_EQ(listDir(dir / "out"), std::vector<std::string>{"own_new"});
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"out"});
}

INSTANTIATE_TEST_SUITE_P(Paths, StagedFolderReplace, ::testing::Values(true, false),
                         [](const ::testing::TestParamInfo<bool>& i) {
                           return i.param ? "AtomicExchange" : "MoveAside";
                         });

TEST(StagedFolder, RefusesWhatTheCheckRejectsAndTouchesNothing) {
  TempDir dir;
  const fs::path target = dir / "thesis";
  fs::create_directories(target / "photos");
  writeText(target / "own_meta", "{}");
  writeText(target / "thesis.tex", "precious");
  const std::string message =
      expectError([&] { io::StagedFolder staged(target.string(), onlyOwnFiles, named("--out")); },
                  {"--out: refusing to replace", target.string(), "it holds \"",
                   "move it away or choose another folder"});
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"thesis"}) << "no staging folder";
  EXPECT_EQ(listDir(target), (std::vector<std::string>{"own_meta", "photos", "thesis.tex"}));
  EXPECT_EQ(readText(target / "thesis.tex"), "precious");
  // checkReplaceable says the same without creating anything.
  expectError([&] { io::checkReplaceable(target.string(), onlyOwnFiles, "--out"); },
              {"--out: refusing to replace", target.string(), "it holds \""});
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"thesis"});
}

TEST(StagedFolder, RefusesFilesLinksAndMissingParents) {
  TempDir dir;
  writeText(dir / "plain_file", "keep me");
  expectError(
      [&] { io::StagedFolder s((dir / "plain_file").string(), onlyOwnFiles, named("test")); },
      {"plain_file", "is not a folder", "refusing"});
  EXPECT_EQ(readText(dir / "plain_file"), "keep me");

  fs::create_directory(dir / "real");
  writeText(dir / "real" / "own_x", "kept");
  fs::create_directory_symlink(dir / "real", dir / "link");
  expectError([&] { io::StagedFolder s((dir / "link").string(), onlyOwnFiles, named("test")); },
              {"link", "is a symbolic link", "refusing"});
  EXPECT_EQ(readText(dir / "real" / "own_x"), "kept");

  expectError(
      [&] { io::StagedFolder s((dir / "no" / "out").string(), onlyOwnFiles, named("test")); },
      {"parent folder", "no", "does not exist"});
  expectError([&] { io::StagedFolder s("..", onlyOwnFiles, named("test")); },
              {"does not name a folder"});
  EXPECT_EQ(listDir(dir.path()), (std::vector<std::string>{"link", "plain_file", "real"}));
}

TEST(StagedFolder, CommitChecksTheTargetAgain) {
  // The target changed while the output was computed: the commit refuses and keeps it.
  TempDir dir;
  const fs::path target = dir / "out";
  fs::create_directory(target);
  writeText(target / "own_old", "old");
  io::StagedFolder staged(target.string(), onlyOwnFiles, named("test"));
  writeText(staged.path() / "own_new", "new");
  writeText(target / "notes.txt", "added by the user meanwhile");
  expectError([&] { staged.commit(); }, {"refusing to replace", "notes.txt"});
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"out"}) << "staging folder removed";
  EXPECT_EQ(listDir(target), (std::vector<std::string>{"notes.txt", "own_old"}));
}

TEST(StagedFolder, KilledWriterLeavesTheOldFolderAndTheNextOneCleansUp) {
  // A real kill: a child process stages a half-written folder and dies of SIGKILL.
  TempDir dir;
  const fs::path target = dir / "out";
  fs::create_directory(target);
  writeText(target / "own_old", "old");
  const pid_t child = ::fork();
  if (child == 0) {
    io::StagedFolder staged(target.string(), onlyOwnFiles, named("test"));
    writeText(staged.path() / "own_half", "half");
    ::raise(SIGKILL);
    ::_exit(3); // not reached
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);
  const std::string stale = hidden("out", ".simpli-tmp-", child);
  EXPECT_EQ(listDir(dir.path()), (std::vector<std::string>{stale, "out"}));
  EXPECT_EQ(listDir(target), std::vector<std::string>{"own_old"}) << "old folder intact";

  io::StagedFolder next(target.string(), onlyOwnFiles, named("test"));
  EXPECT_FALSE(fs::exists(dir / stale)) << "the dead writer's staging folder is removed";
  writeText(next.path() / "own_new", "new");
  next.commit();
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"out"});
  EXPECT_EQ(listDir(target), std::vector<std::string>{"own_new"});
}

TEST(StagedFolder, KillBetweenTheRenamesIsUndoneByTheNextWriter) {
  // The move-aside path killed after "old aside", before "new in": no target, the old folder
  // aside, the complete staging folder. The next writer brings the old folder back first.
  TempDir dir;
  const long dead = deadPid();
  const fs::path old = dir / hidden("out", ".simpli-old-", dead);
  const fs::path staging = dir / hidden("out", ".simpli-tmp-", dead);
  fs::create_directories(old);
  writeText(old / "own_old", "old");
  fs::create_directories(staging);
  writeText(staging / "own_new", "complete but uncommitted");
  EXPECT_EQ(io::recoverStagedFolders((dir / "out").string()), 2);
  EXPECT_EQ(listDir(dir.path()), std::vector<std::string>{"out"});
  EXPECT_EQ(readText(dir / "out" / "own_old"), "old");

  // Killed after "new in", before "old removed": the new folder stays, the old one goes.
  fs::create_directories(old);
  writeText(old / "own_old", "old");
  io::StagedFolder next((dir / "out").string(), onlyOwnFiles, named("test"));
  EXPECT_EQ(listDir(dir.path()),
            (std::vector<std::string>{next.path().filename().string(), "out"}));
  EXPECT_EQ(readText(dir / "out" / "own_old"), "old");
}

TEST(StagedFolder, LeavesLiveAndForeignFoldersAlone) {
  TempDir dir;
  const long dead = deadPid();
  const long live = static_cast<long>(::getppid());
  const std::vector<std::string> kept{
      hidden("out", ".simpli-tmp-", live),   // another simpli writing right now
      hidden("other", ".simpli-tmp-", dead), // a different target
      ".out.simpli-tmp-12x",                 // not a PID
      ".out.tmp-" + std::to_string(dead),    // not simpli's staging name
  };
  for (const std::string& name : kept)
    fs::create_directory(dir / name);
  writeText(dir / hidden("out", ".simpli-old-", dead), "a file, not a folder simpli made");
  fs::create_directory(dir / hidden("out", ".simpli-tmp-", dead));
  fs::create_directory(dir / hidden("out", ".simpli-tmp-", ::getpid())); // an earlier PID twin
  EXPECT_EQ(io::recoverStagedFolders((dir / "out").string()), 2);
  std::vector<std::string> expected = kept;
  expected.push_back(hidden("out", ".simpli-old-", dead));
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(listDir(dir.path()), expected);
}

} // namespace

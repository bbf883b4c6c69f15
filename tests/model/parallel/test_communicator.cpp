// The serial communicator (what every command uses without an MPI launcher), the launcher's
// environment, the Session's refusal of several processes in a build without MPI, and the
// round-robin share of scenes.
#include "support/expect_error.h"

#include "simpli/model/parallel/communicator.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

namespace simpli::parallel {
namespace {

// Sets (or unsets) an environment variable for one scope.
class ScopedEnv {
public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name))
      old_ = old;
    if (value)
      ::setenv(name, value, 1);
    else
      ::unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_)
      ::setenv(name_, old_->c_str(), 1);
    else
      ::unsetenv(name_);
  }

private:
  const char* name_;
  std::optional<std::string> old_;
};

struct NoLauncher {
  ScopedEnv ompi{"OMPI_COMM_WORLD_SIZE", nullptr}, pmi{"PMI_SIZE", nullptr},
      pmix{"PMIX_RANK", nullptr};
};

TEST(ParallelSerial, OneRankAndIdentityCollectives) {
  Communicator& c = world();
  ASSERT_EQ(c.size(), 1) << "run this test without mpiexec";
  EXPECT_EQ(c.rank(), 0);
  EXPECT_TRUE(c.isRoot());
  EXPECT_NE(c.describe().find("serial"), std::string::npos);
  std::vector<float> f{1.5f, -2.0f, 3.25f};
  c.allreduceSum(f);
  EXPECT_EQ(f, (std::vector<float>{1.5f, -2.0f, 3.25f}));
  std::vector<double> d{0.1, 1e300};
  c.allreduceSum(d);
  EXPECT_EQ(d, (std::vector<double>{0.1, 1e300}));
  std::string text("abc\0def", 7); // binary bytes survive
  c.broadcast(text);
  EXPECT_EQ(text, std::string("abc\0def", 7));
  c.broadcast(d);
  EXPECT_EQ(d.size(), 2u);
  EXPECT_EQ(c.gather("rank zero"), std::vector<std::string>{"rank zero"});
  c.barrier();
  test::expectError([&] { c.broadcast(text, 1); }, {"root rank 1 does not exist", "1 rank"});
  test::expectError([&] { c.gather("x", 3); }, {"root rank 3"});
}

TEST(ParallelLauncher, SizeFromTheEnvironment) {
  NoLauncher none;
  EXPECT_EQ(launcherSize(), 0);
  {
    ScopedEnv ompi("OMPI_COMM_WORLD_SIZE", "3");
    EXPECT_EQ(launcherSize(), 3);
  }
  {
    ScopedEnv pmi("PMI_SIZE", "4");
    EXPECT_EQ(launcherSize(), 4);
  }
  {
    ScopedEnv junk("OMPI_COMM_WORLD_SIZE", "two");
    EXPECT_EQ(launcherSize(), 0);
  }
  {
    ScopedEnv pmix("PMIX_RANK", "0"); // a PMIx launcher: the size is not in the environment
    EXPECT_EQ(launcherSize(), 1);
  }
}

TEST(ParallelSession, WithoutALauncherMpiStaysOff) {
  NoLauncher none;
  int argc = 1;
  char name[] = "test";
  char* args[] = {name, nullptr};
  char** argv = args;
  Session session(argc, argv);
  EXPECT_EQ(world().size(), 1);
  EXPECT_EQ(argc, 1);
}

TEST(ParallelSession, SeveralProcessesNeedAnMpiBuild) {
  if (builtWithMpi())
    GTEST_SKIP() << "built with MPI: a launcher's processes start MPI (tests/apps/*_mpi.sh)";
  NoLauncher none;
  ScopedEnv ompi("OMPI_COMM_WORLD_SIZE", "2");
  int argc = 1;
  char name[] = "test";
  char* args[] = {name, nullptr};
  char** argv = args;
  test::expectError([&] { Session session(argc, argv); },
                    {"2 processes", "built without MPI", "SIMPLI_USE_MPI=OFF"});
  ScopedEnv one("OMPI_COMM_WORLD_SIZE", "1"); // one process is simply serial
  Session session(argc, argv);
  EXPECT_EQ(world().size(), 1);
}

TEST(ParallelShare, RoundRobinCoversEveryItemOnce) {
  EXPECT_EQ(roundRobinShare(5, 0, 2), (std::vector<std::size_t>{0, 2, 4}));
  EXPECT_EQ(roundRobinShare(5, 1, 2), (std::vector<std::size_t>{1, 3}));
  EXPECT_EQ(roundRobinShare(2, 2, 3), std::vector<std::size_t>{});
  EXPECT_EQ(roundRobinShare(3, 0, 1), (std::vector<std::size_t>{0, 1, 2}));
  std::vector<int> seen(7, 0);
  for (int r = 0; r < 3; ++r)
    for (std::size_t i : roundRobinShare(7, r, 3))
      ++seen[i];
  EXPECT_EQ(seen, std::vector<int>(7, 1));
  EXPECT_TRUE(ownsItem(5, 1, 2));
  EXPECT_FALSE(ownsItem(5, 0, 2));
  EXPECT_TRUE(ownsItem(7, 0, 1));
  test::expectError([] { roundRobinShare(3, 2, 2); }, {"rank 2 of 2 ranks"});
  test::expectError([] { roundRobinShare(3, 0, 0); }, {"rank 0 of 0 ranks"});
  test::expectError([] { ownsItem(0, -1, 2); }, {"rank -1 of 2 ranks"});
}

} // namespace
} // namespace simpli::parallel

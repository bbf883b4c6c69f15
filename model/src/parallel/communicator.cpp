// The serial communicator, the launcher check and the Session (parallel/communicator.h).
#include "simpli/model/parallel/communicator.h"

#include "parallel/backend.h"
#include "simpli/error.h"

#include <cstdio>
#include <cstdlib>
#include <string>

namespace simpli::parallel {

namespace {

class SerialCommunicator : public Communicator {
public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  std::string describe() const override { return "serial (1 rank)"; }
  void allreduceSum(std::vector<float>&) override {}
  void allreduceSum(std::vector<double>&) override {}
  void broadcast(std::string&, int root) override { checkRoot(root); }
  void broadcast(std::vector<double>&, int root) override { checkRoot(root); }
  std::vector<std::string> gather(const std::string& text, int root) override {
    checkRoot(root);
    return {text};
  }
  void barrier() override {}
  [[noreturn]] void abort(const std::string& message, int exitCode) override {
    std::fflush(stdout);
    std::fprintf(stderr, "simpli: %s\n", message.c_str());
    std::fflush(stderr);
    std::_Exit(exitCode);
  }

private:
  static void checkRoot(int root) {
    if (root != 0)
      fail("serial communicator: root rank ", root, " does not exist (1 rank)");
  }
};

// A positive integer environment variable, else 0.
int positiveEnv(const char* name) {
  const char* v = std::getenv(name);
  if (!v || !*v)
    return 0;
  char* end = nullptr;
  const long n = std::strtol(v, &end, 10);
  return (*end == '\0' && n > 0 && n < (1L << 30)) ? int(n) : 0;
}

void finishAtExit() {
  backend::finish();
}

} // namespace

Communicator& world() {
  static SerialCommunicator serial;
  if (Communicator* mpi = backend::running())
    return *mpi;
  return serial;
}

bool builtWithMpi() {
  return backend::available();
}

int launcherSize() {
  // Open MPI's mpiexec; MPICH / Intel MPI (Hydra) and Slurm's PMI; a PMIx launcher (size not
  // in the environment: at least this process).
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const int n = positiveEnv(name))
      return n;
  return std::getenv("PMIX_RANK") ? 1 : 0;
}

Session::Session(int& argc, char**& argv) {
  const int launched = launcherSize();
  if (launched == 0)
    return;
  if (!backend::available()) {
    if (launched > 1)
      fail("started by an MPI launcher with ", launched,
           " processes, but this simpli was built without MPI (CMake option SIMPLI_USE_MPI=OFF); "
           "each process would run the whole job alone. Rebuild with MPI (Debian: "
           "libopenmpi-dev) or run one process");
    return;
  }
  if (backend::start(argc, argv))
    std::atexit(finishAtExit); // std::exit() from a command still finalises MPI
}

Session::~Session() {
  backend::finish();
}

bool ownsItem(std::size_t index, int rank, int size) {
  if (size < 1 || rank < 0 || rank >= size)
    fail("round robin: rank ", rank, " of ", size, " ranks");
  return index % std::size_t(size) == std::size_t(rank);
}

std::vector<std::size_t> roundRobinShare(std::size_t count, int rank, int size) {
  std::vector<std::size_t> share;
  for (std::size_t i = 0; i < count; ++i)
    if (ownsItem(i, rank, size))
      share.push_back(i);
  return share;
}

} // namespace simpli::parallel

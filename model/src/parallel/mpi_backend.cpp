// parallel/backend.h on MPI (SIMPLI_USE_MPI=ON): a communicator on a duplicate of
// MPI_COMM_WORLD (simpli's messages never mix with a library's), with MPI_ERRORS_RETURN so that
// a failed call becomes a simpli::Error naming it instead of an abort inside the library.
#include "parallel/backend.h"

#include "simpli/error.h"

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace simpli::parallel::backend {

namespace {

// Elements per MPI call: counts are ints, and smaller messages keep the library's buffers small.
constexpr std::size_t kChunk = std::size_t(1) << 26;

std::string mpiErrorString(int code) {
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  if (MPI_Error_string(code, text, &length) != MPI_SUCCESS)
    return "MPI error " + std::to_string(code);
  return std::string(text, std::size_t(length));
}

std::string libraryVersion() {
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(text, &length);
  std::string v(text, std::size_t(length));
  const std::size_t end = v.find_first_of(",\n");
  return end == std::string::npos ? v : v.substr(0, end);
}

class MpiCommunicator : public Communicator {
public:
  MpiCommunicator() {
    check(MPI_Comm_dup(MPI_COMM_WORLD, &comm_), "MPI_Comm_dup", "MPI_COMM_WORLD");
    check(MPI_Comm_set_errhandler(comm_, MPI_ERRORS_RETURN), "MPI_Comm_set_errhandler", "");
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &size_);
    version_ = libraryVersion();
  }
  ~MpiCommunicator() override { MPI_Comm_free(&comm_); }

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::string describe() const override {
    return "MPI, rank " + std::to_string(rank_) + " of " + std::to_string(size_) + " (" + version_ +
           ")";
  }

  void allreduceSum(std::vector<float>& values) override {
    allreduce(values.data(), values.size(), MPI_FLOAT, "floats");
  }
  void allreduceSum(std::vector<double>& values) override {
    allreduce(values.data(), values.size(), MPI_DOUBLE, "doubles");
  }

  void broadcast(std::string& bytes, int root) override {
    uint64_t n = bytes.size();
    check(MPI_Bcast(&n, 1, MPI_UINT64_T, root, comm_), "MPI_Bcast", "a size");
    bytes.resize(std::size_t(n));
    for (std::size_t at = 0; at < bytes.size(); at += kChunk)
      check(MPI_Bcast(&bytes[at], int(std::min(kChunk, bytes.size() - at)), MPI_CHAR, root, comm_),
            "MPI_Bcast", std::to_string(n) + " bytes");
  }
  void broadcast(std::vector<double>& values, int root) override {
    uint64_t n = values.size();
    check(MPI_Bcast(&n, 1, MPI_UINT64_T, root, comm_), "MPI_Bcast", "a size");
    values.resize(std::size_t(n));
    for (std::size_t at = 0; at < values.size(); at += kChunk)
      check(MPI_Bcast(values.data() + at, int(std::min(kChunk, values.size() - at)), MPI_DOUBLE,
                      root, comm_),
            "MPI_Bcast", std::to_string(n) + " doubles");
  }

  std::vector<std::string> gather(const std::string& text, int root) override {
    const int length = checkedInt(text.size(), "MPI_Gatherv");
    std::vector<int> lengths(rank_ == root ? std::size_t(size_) : 0);
    check(MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, root, comm_), "MPI_Gather",
          "text lengths");
    std::vector<int> offsets(lengths.size());
    std::size_t total = 0;
    for (std::size_t r = 0; r < lengths.size(); ++r) {
      offsets[r] = checkedInt(total, "MPI_Gatherv");
      total += std::size_t(lengths[r]);
    }
    checkedInt(total, "MPI_Gatherv");
    std::string all(total, '\0');
    check(MPI_Gatherv(text.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(),
                      MPI_CHAR, root, comm_),
          "MPI_Gatherv", std::to_string(text.size()) + " bytes");
    std::vector<std::string> texts;
    for (std::size_t r = 0; r < lengths.size(); ++r)
      texts.push_back(all.substr(std::size_t(offsets[r]), std::size_t(lengths[r])));
    return texts;
  }

  void barrier() override { check(MPI_Barrier(comm_), "MPI_Barrier", ""); }

  [[noreturn]] void abort(const std::string& message, int exitCode) override {
    std::fflush(stdout);
    std::fprintf(stderr, "simpli: rank %d of %d: %s; ending all ranks\n", rank_, size_,
                 message.c_str());
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, exitCode);
    std::_Exit(exitCode); // MPI_Abort does not return; if it did, this rank still ends
  }

private:
  void allreduce(void* data, std::size_t n, MPI_Datatype type, const char* what) {
    const std::size_t bytes = type == MPI_FLOAT ? 4 : 8;
    for (std::size_t at = 0; at < n; at += kChunk)
      check(MPI_Allreduce(MPI_IN_PLACE, static_cast<char*>(data) + at * bytes,
                          int(std::min(kChunk, n - at)), type, MPI_SUM, comm_),
            "MPI_Allreduce", std::to_string(n) + " " + what);
  }

  int checkedInt(std::size_t n, const char* call) const {
    if (n > std::size_t(INT_MAX))
      fail(call, ": ", n, " bytes on rank ", rank_, " exceed MPI's int counts");
    return int(n);
  }

  void check(int code, const char* call, const std::string& what) const {
    if (code != MPI_SUCCESS)
      fail(call, what.empty() ? "" : " (" + what + ")", " failed on rank ", rank_, " of ", size_,
           ": ", mpiErrorString(code));
  }

  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
  std::string version_;
};

MpiCommunicator* g_world = nullptr;
bool g_started = false;

} // namespace

bool available() {
  return true;
}

bool start(int& argc, char**& argv) {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (initialised)
    fail("MPI is already initialised in this process (simpli's Session starts it once)");
  int provided = 0;
  // Only the main thread calls MPI (the OpenCL driver's threads never do).
  const int code = MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  if (code != MPI_SUCCESS)
    fail("MPI_Init_thread failed: ", mpiErrorString(code));
  g_started = true;
  g_world = new MpiCommunicator();
  return true;
}

void finish() {
  if (!g_started)
    return;
  delete g_world;
  g_world = nullptr;
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (!finalised)
    MPI_Finalize();
  g_started = false;
}

Communicator* running() {
  return g_world;
}

} // namespace simpli::parallel::backend

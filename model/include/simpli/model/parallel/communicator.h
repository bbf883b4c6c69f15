#pragma once
// The processes of one job (MPI here is the Message Passing Interface, not the multiplane images
// of geometry/) and the few collective operations simpli uses: data-parallel
// training (one fused gradient all-reduce per step, training/trainer.h) and scenes spread over
// ranks (`simpli infer SCENES_DIR`). Two implementations behind one interface, so that the
// callers are the same code either way:
//   - serial: one rank; every collective is the identity (or a copy). Used when simpli was
//     built without MPI (SIMPLI_USE_MPI=OFF) or was not started by an MPI launcher.
//   - MPI (MPI_COMM_WORLD): when built with MPI and started by mpiexec / mpirun / srun. The
//     communicator returns MPI errors instead of aborting in the library, and each failed call
//     throws simpli::Error naming the call and the MPI error string.
// As in MPI, every rank must call the collectives in the same order with matching sizes.
//
// MPI is started only by a Session (one per process, created first thing in main()), and only
// when the environment shows an MPI launcher (OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK):
// `simpli` run by hand never initialises MPI, so the one-process commands, their tests and
// their start-up time are unchanged. (ParaView's pvbatch starts MPI itself; the VTK filters
// use its pipeline's pieces, not this communicator: filters/vtkSIMPLIBuildMLI.h.)
#include <cstddef>
#include <string>
#include <vector>

namespace simpli::parallel {

class Communicator {
public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  bool isRoot() const { return rank() == 0; }
  /// "serial (1 rank)" or "MPI, rank 1 of 2 (Open MPI v4.1.4, ...)"; for logs.
  virtual std::string describe() const = 0;

  /// Element-wise sum over the ranks, in place; every rank passes the same number of values.
  /// The order of the additions is the MPI library's: with two ranks a + b is exact and the
  /// same on both, with more the result can differ in the last bits from a fixed-order sum.
  virtual void allreduceSum(std::vector<float>& values) = 0;
  virtual void allreduceSum(std::vector<double>& values) = 0;
  /// `root`'s bytes on every rank (the others' are replaced, sizes included).
  virtual void broadcast(std::string& bytes, int root = 0) = 0;
  /// `root`'s values on every rank (sizes included).
  virtual void broadcast(std::vector<double>& values, int root = 0) = 0;
  /// Every rank's text, in rank order, on `root`; the other ranks get an empty list.
  virtual std::vector<std::string> gather(const std::string& text, int root = 0) = 0;
  virtual void barrier() = 0;
  /// Ends every rank of the job: prints "simpli: rank R of K: MESSAGE; ending all ranks" to
  /// stderr and exits with `exitCode` (MPI_Abort). Serial: prints "simpli: MESSAGE" and exits.
  [[noreturn]] virtual void abort(const std::string& message, int exitCode) = 0;
};

/// The job's communicator: (a duplicate of) MPI_COMM_WORLD while a Session has MPI running,
/// else the serial one.
Communicator& world();

/// True when simpli was built with MPI (CMake option SIMPLI_USE_MPI).
bool builtWithMpi();

/// The number of processes an MPI launcher started, read from its environment variables;
/// 0 when the process was not started by one.
int launcherSize();

/// Starts MPI for the lifetime of the object when the process was started by an MPI launcher
/// (launcherSize() > 0) and finalises it at the end (also on std::exit, through atexit). Create
/// it first thing in main(), before any thread is started (MPI's threads then inherit the
/// signal mask of the caller). Throws simpli::Error when the launcher started several processes
/// but simpli was built without MPI: each would run the whole job alone (and share one output).
class Session {
public:
  Session(int& argc, char**& argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

/// Rank r's share of `count` items dealt round robin: r, r + K, r + 2K, ... (K = size).
std::vector<std::size_t> roundRobinShare(std::size_t count, int rank, int size);
/// Whether item `index` is rank r's in that dealing (index mod K == r).
bool ownsItem(std::size_t index, int rank, int size);

} // namespace simpli::parallel

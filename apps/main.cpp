// simpli: command line entry point.
#include "blas_environment.h"
#include "commands.h"
#include "stop_signals.h"

#include "simpli/error.h"
#include "simpli/model/parallel/communicator.h"
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <memory>
#include <string>

namespace {

// With several ranks an error on one must end all of them (the others would wait in the next
// collective for ever): the message names the rank, and MPI_Abort ends the job.
int reportError(const char* kind, const char* what, int code) {
  simpli::parallel::Communicator& world = simpli::parallel::world();
  if (world.size() > 1)
    world.abort(std::string(kind) + ": " + what, code);
  std::fprintf(stderr, "simpli: %s: %s\n", kind, what);
  return code;
}

} // namespace

int main(int argc, char** argv) {
  simpli::app::reexecWithBlasEnvironment(argc, argv); // before MPI and any thread
  // MPI first, while the stop signals are still blocked (stop_signals.cpp): the threads it
  // starts keep them blocked, so SIGINT / SIGTERM reach the main thread's polling.
  std::unique_ptr<simpli::parallel::Session> mpi;
  try {
    mpi = std::make_unique<simpli::parallel::Session>(argc, argv);
  } catch (const simpli::Error& e) {
    std::fprintf(stderr, "simpli: error: %s\n", e.what());
    return 1;
  }
  simpli::app::unblockStopSignalsInMainThread();
  CLI::App app{"simpli: Self-improving Multiplane-to-Layer Images (novel view synthesis)"};
  app.require_subcommand(1);
  simpli::app::addDevicesCommand(app);
  simpli::app::addBenchCommand(app);
  simpli::app::addBenchTradeCommand(*app.get_subcommand("bench"));
  simpli::app::addInfoCommand(app);
  simpli::app::addMakeSceneCommand(app);
  simpli::app::addConvertCommand(app);
  simpli::app::addRenderCommand(app);
  simpli::app::addInferCommand(app);
  simpli::app::addTrainCommand(app);
  simpli::app::addEvalCommand(app);
  simpli::app::addWidenCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const simpli::Error& e) {
    return reportError("error", e.what(), 1);
  } catch (const std::exception& e) {
    return reportError("internal error", e.what(), 2);
  }
  return 0;
}

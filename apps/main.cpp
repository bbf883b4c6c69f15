// simpli: command line entry point.
#include "commands.h"
#include "stop_signals.h"

#include "simpli/error.h"
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  simpli::app::unblockStopSignalsInMainThread();
  CLI::App app{"simpli: Self-improving Multiplane-to-Layer Images (novel view synthesis)"};
  app.require_subcommand(1);
  simpli::app::addDevicesCommand(app);
  simpli::app::addBenchCommand(app);
  simpli::app::addInfoCommand(app);
  simpli::app::addMakeSceneCommand(app);
  simpli::app::addConvertCommand(app);
  simpli::app::addRenderCommand(app);
  simpli::app::addInferCommand(app);
  simpli::app::addTrainCommand(app);
  simpli::app::addEvalCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const simpli::Error& e) {
    std::fprintf(stderr, "simpli: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "simpli: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}

#pragma once
// Each subcommand lives in its own cmd_*.cpp and registers itself on the CLI11 app.
// A registered callback throws simpli::Error on bad input; main() prints it and exits 1.
namespace CLI {
class App;
}

namespace simpli::app {
void addDevicesCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
/// `simpli bench trade` (cmd_bench_trade.cpp), registered on the `bench` subcommand.
void addBenchTradeCommand(CLI::App& bench);
void addInfoCommand(CLI::App& app);
void addMakeSceneCommand(CLI::App& app);
void addConvertCommand(CLI::App& app);
void addRenderCommand(CLI::App& app);
void addInferCommand(CLI::App& app);
void addTrainCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
/// `simpli bench ops|infer|train` only: re-executes the process with OPENBLAS_CORETYPE and
/// OPENBLAS_L2_SIZE removed from its environment, so that OpenBLAS loads its native kernel
/// (cmd_bench.cpp). Call first in main, before any thread starts; returns when nothing to do.
void reexecBenchmarkWithNativeBlas(int argc, char** argv);
} // namespace simpli::app

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
void addWidenCommand(CLI::App& app);
} // namespace simpli::app

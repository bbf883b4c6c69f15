#pragma once
// SIGINT / SIGTERM as a stop request for long commands (train, infer): while a StopSignals
// object lives, every such signal is only recorded (the command polls stopSignal() between
// steps and stops cleanly). Further signals are absorbed too, so that the checkpoint or output
// being written when they arrive is completed: `timeout` sends SIGTERM to the process and then
// to its whole group, and a second Ctrl-C is common. SIGKILL (or SIGQUIT, Ctrl-\) still ends a
// command at once; its writes are atomic, so that leaves the old files, never partial ones.
//
// The two signals are also blocked in the creating thread, and so in every thread and child
// process started after it, and are taken by polling (stopSignal()). Two things break otherwise:
// a signal to the process group (Ctrl-C in a terminal, `timeout`) kills the helper processes the
// OpenCL driver runs (PoCL links kernels with a child `ld`, and aborts the whole command when it
// dies), and a signal delivered while PoCL compiles runs LLVM's handler, which deletes the
// compiler's temporary files and fails the build. Create it first thing in a command, before the
// OpenCL device is opened. Threads that libraries start before main() (OpenBLAS's pool) are
// covered by blocking the signals at process start (stop_signals.cpp) and unblocking them in the
// main thread only (unblockStopSignalsInMainThread).
#include <csignal>

namespace simpli::app {

class StopSignals {
public:
  StopSignals();  ///< installs the handlers, blocks the signals, clears an earlier signal
  ~StopSignals(); ///< discards pending ones, restores the previous handlers and mask
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

private:
  struct sigaction oldInt_ {
  }, oldTerm_{};
  sigset_t oldMask_{};
};

/// The first signal received since the last StopSignals was installed, 0 when none.
int stopSignal();

/// First thing in main(): gives the main thread back the signal mask the process started with.
/// Every thread a library started before main() keeps SIGINT / SIGTERM blocked, so signals go to
/// the main thread (default action, or StopSignals).
void unblockStopSignalsInMainThread();

} // namespace simpli::app

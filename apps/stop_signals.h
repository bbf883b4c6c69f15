#pragma once
// SIGINT / SIGTERM as a stop request for long commands (train, infer): while a StopSignals
// object lives, the first signal is only recorded (the command polls stopSignal() between
// steps and stops cleanly); a second one gets the default action (SA_RESETHAND), so a user can
// still kill a command that is busy writing.
#include <csignal>

namespace simpli::app {

class StopSignals {
public:
  StopSignals();  ///< installs the handlers and clears an earlier signal
  ~StopSignals(); ///< restores the previous handlers
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

private:
  struct sigaction oldInt_ {
  }, oldTerm_{};
};

/// The signal received since the last StopSignals was installed, 0 when none.
int stopSignal();

} // namespace simpli::app

// Stop requests from SIGINT / SIGTERM (stop_signals.h).
#include "stop_signals.h"

#include <ctime>

#include <pthread.h>

namespace simpli::app {

namespace {

volatile std::sig_atomic_t g_signal = 0;

// The first signal decides the exit code (130 / 143); later ones are absorbed. Runs in threads
// that were started before the StopSignals and so do not block the signals.
extern "C" void onStopSignal(int signal) {
  if (g_signal == 0)
    g_signal = signal;
}

sigset_t stopSet() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

// A pending (blocked) stop signal, taken without waiting; 0 when none. Only for a thread that
// blocks both signals (sigtimedwait's precondition).
int takePending() {
  sigset_t current;
  if (pthread_sigmask(SIG_BLOCK, nullptr, &current) != 0 || !sigismember(&current, SIGINT) ||
      !sigismember(&current, SIGTERM))
    return 0;
  const sigset_t set = stopSet();
  const timespec zero{};
  const int sig = sigtimedwait(&set, nullptr, &zero);
  return sig > 0 ? sig : 0;
}

// The mask the process started with, and the early block (see stop_signals.h). A function in the
// executable's .preinit_array runs before the initialisers of every shared library, so before
// any library can start a thread.
sigset_t g_startMask;

extern "C" void blockStopSignalsAtStart(int, char**, char**) {
  const sigset_t set = stopSet();
  pthread_sigmask(SIG_BLOCK, &set, &g_startMask);
}

__attribute__((section(".preinit_array"),
               used)) void (*const g_blockAtStart)(int, char**, char**) = blockStopSignalsAtStart;

} // namespace

void unblockStopSignalsInMainThread() {
  pthread_sigmask(SIG_SETMASK, &g_startMask, nullptr);
}

StopSignals::StopSignals() {
  g_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sa.sa_mask = stopSet();
  // No SA_RESETHAND: a second signal must not kill a command that is writing its checkpoint.
  sa.sa_flags = SA_RESTART;
  sigaction(SIGINT, &sa, &oldInt_);
  sigaction(SIGTERM, &sa, &oldTerm_);
  const sigset_t set = stopSet();
  pthread_sigmask(SIG_BLOCK, &set, &oldMask_);
}

StopSignals::~StopSignals() {
  // Signals that came after the last poll: recorded (the command has finished its work) and
  // dropped, so that unblocking them below does not kill the process now.
  while (const int sig = takePending())
    if (g_signal == 0)
      g_signal = sig;
  sigaction(SIGINT, &oldInt_, nullptr);
  sigaction(SIGTERM, &oldTerm_, nullptr);
  pthread_sigmask(SIG_SETMASK, &oldMask_, nullptr);
}

int stopSignal() {
  if (g_signal == 0)
    if (const int sig = takePending())
      g_signal = sig;
  return g_signal;
}

} // namespace simpli::app

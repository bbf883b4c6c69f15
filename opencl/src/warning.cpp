// The warning handler (simpli/warning.h).
#include "simpli/warning.h"

#include <cstdio>
#include <mutex>

namespace simpli {

namespace {

std::mutex& handlerMutex() {
  static std::mutex m;
  return m;
}

WarningHandler& currentHandler() {
  static WarningHandler handler;
  return handler;
}

} // namespace

WarningHandler setWarningHandler(WarningHandler handler) {
  std::lock_guard<std::mutex> lock(handlerMutex());
  WarningHandler previous = std::move(currentHandler());
  currentHandler() = std::move(handler);
  return previous;
}

void emitWarning(const std::string& message) {
  // Held while the handler runs: warnings from several threads come out whole, one per line.
  std::lock_guard<std::mutex> lock(handlerMutex());
  if (currentHandler())
    currentHandler()(message);
  else
    std::fprintf(stderr, "simpli: warning: %s\n", message.c_str());
}

} // namespace simpli

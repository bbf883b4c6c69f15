// parallel/backend.h for a build without MPI (SIMPLI_USE_MPI=OFF): world() is always serial.
#include "parallel/backend.h"

namespace simpli::parallel::backend {

bool available() {
  return false;
}
bool start(int&, char**&) {
  return false;
}
void finish() {}
Communicator* running() {
  return nullptr;
}

} // namespace simpli::parallel::backend

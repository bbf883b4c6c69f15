#pragma once
// The MPI side of parallel/communicator.h, one of two translation units: mpi_backend.cpp (built
// with SIMPLI_USE_MPI) or no_mpi_backend.cpp (without). communicator.cpp holds what is common.
#include "simpli/model/parallel/communicator.h"

namespace simpli::parallel::backend {

/// Whether this build has MPI.
bool available();
/// Starts MPI (MPI_Init_thread) and makes the MPI communicator; false without MPI.
bool start(int& argc, char**& argv);
/// Frees the communicator and finalises MPI when start() started it (idempotent).
void finish();
/// The MPI communicator while MPI runs, else null.
Communicator* running();

} // namespace simpli::parallel::backend

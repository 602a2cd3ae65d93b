#include <cstdlib>

#include "apps/mpi_session.h"

namespace prism::app {

bool started_as_mpi_rank() {
    // OpenMPI's mpirun, and PMI/PMIx launchers (MPICH's hydra, srun): only a world of several ranks counts.
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"}) {
        const char* value = std::getenv(name);
        if (value && std::atoi(value) > 1) return true;
    }
    return false;
}

}  // namespace prism::app

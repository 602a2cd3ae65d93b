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

int launcher_rank() {
    for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
        if (const char* value = std::getenv(name)) return std::atoi(value);
    return 0;
}

}  // namespace prism::app

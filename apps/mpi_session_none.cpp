// The stand-in for builds without MPI (apps/mpi_session.h): it only says so.
#include "apps/mpi_session.h"

#include "core/util/error.h"

namespace prism::app {

MpiSession::MpiSession() {
    throw Error(
        "this prism was built without MPI, so it cannot split work over mpirun's ranks (install "
        "libopenmpi-dev and reconfigure)");
}

MpiSession::~MpiSession() = default;

WorkMessage MpiSession::exchange_with_coordinator(const WorkMessage&) { return {}; }
void MpiSession::send_to_coordinator(const WorkMessage&) {}
WorkMessage MpiSession::receive_from_workers(int&) { return {}; }
void MpiSession::send_to_worker(int, const WorkMessage&) {}

}  // namespace prism::app

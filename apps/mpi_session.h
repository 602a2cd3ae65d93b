// MPI for `prism render` under mpirun: start-up, this rank's place, and WorkMessages between rank 0 (the
// coordinator) and the other ranks. Built with MPI (apps/mpi_session.cpp) when CMake finds it, else a stand-in
// (apps/mpi_session_none.cpp) that says so.
#pragma once

#include <memory>
#include <mutex>

#include "apps/work_message.h"
#include "core/util/non_copyable.h"

namespace prism::app {

// True when the process was started by mpirun/srun as one of several ranks (read from the launcher's environment,
// so a plain run never initialises MPI).
bool started_as_mpi_rank();
// This process's rank as the launcher's environment gives it (0 when not started by one), known before MPI starts.
int launcher_rank();

class MpiSession : private NonCopyable {
public:
    MpiSession();   // MPI_Init_thread; throws prism::Error when the build has no MPI
    ~MpiSession();  // MPI_Finalize

    int rank() const { return rank_; }
    int size() const { return size_; }
    int local_rank() const { return local_rank_; }  // among the ranks on this host: picks this rank's GPU

    // Worker ranks: any thread may call; a message and its answer are one exchange (a mutex orders them).
    WorkMessage exchange_with_coordinator(const WorkMessage& message);
    void send_to_coordinator(const WorkMessage& message);  // no answer expected (Failed, RankDone)
    // Rank 0, main thread only.
    WorkMessage receive_from_workers(int& source_rank);
    void send_to_worker(int rank, const WorkMessage& message);

private:
    int rank_ = 0, size_ = 1, local_rank_ = 0;
    std::mutex exchange_;
};

}  // namespace prism::app

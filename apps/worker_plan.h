// Which backends (devices) a split render runs on: the --backend list, one entry per MPI rank (rank r takes entry
// r mod the list's length) or, in one process, one worker per entry; "<api>:all" is every device of that API.
#pragma once

#include <string>
#include <vector>

#include "core/bvh/bvh.h"

namespace prism::app {

// "cuda,cpu,cpu" -> {"cuda", "cpu", "cpu"}. Throws prism::Error naming --backend for an empty entry.
std::vector<std::string> split_backend_list(const std::string& text);

// Whether `backend` (a list, or one name) asks for more than one worker in one process.
bool names_several_devices(const std::string& backend);

// The backends this process runs, one worker each. `rank`/`ranks`: this process's place under mpirun (0 of 1
// without); `local_rank` picks the GPU of a rank whose entry names none: device local_rank mod the device count
// (CUDA, which numbers its devices).
std::vector<std::string> plan_local_workers(const std::string& backend, int rank, int ranks, int local_rank);

// One BVH layout for every worker, so every tile is traced the same way: `requested`, or for "auto" the wide layout
// when every backend of the list is a cpu one, else the GPU backends' layout.
BvhLayout shared_bvh_layout(const std::string& requested, const std::string& backend);

}  // namespace prism::app

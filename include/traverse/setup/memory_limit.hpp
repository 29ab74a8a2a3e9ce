#pragma once
// What the machine allows one rank to use, for the memory check of run_limits.hpp.
#include <mpi.h>

#include "traverse/setup/run_limits.hpp"

namespace traverse::setup {

/// The memory one rank may use: --max-memory when given; else the memory available on this
/// host (the smallest of /proc/meminfo MemAvailable and the room left under this process's
/// cgroup limit, sysconf when neither is readable) shared by the ranks on this host, and at
/// most the room left under the process's address-space and data limits (ulimit -v, -d).
/// Collective over `comm`: every rank gets the smallest figure of all ranks (and its source),
/// so every rank takes the same decision. MPI_COMM_NULL: MPI not started (check outside a
/// launcher), this process alone.
MemoryLimit memory_limit(const RunLimits& limits, MPI_Comm comm);

}  // namespace traverse::setup

#pragma once
// traverse sweep (docs/sweeps.md): every case of the --vary product run in one process, or
// spread over the ranks of `comm` (each case on one rank, on MPI_COMM_SELF), one output file
// per case and an index of the cases.
#include <mpi.h>

#include <functional>
#include <string>
#include <vector>

#include "cli.hpp"

namespace traverse::app {

/// One case of a sweep: its --vary assignments, output file and rough cost.
struct SweepCase {
  std::vector<std::string> assignments;  ///< "key=value" of each --vary, in option order
  std::string output;                    ///< DIR/case_NNNN.h5
  /// Time steps x (nodes for a rod, modes plus the nodes written per step for a beam); 1 for a
  /// continuation; 0 for a case whose scene is bad input (it ends at once). Spreads the cases
  /// over the ranks.
  double cost = 0.0;
};

/// The sweep checked and its cases planned, each case's scene loaded once to find its cost and
/// whether it needs Trilinos (the executable traverse decides its hand-over with it).
struct SweepPlan {
  std::vector<SweepCase> cases;
  bool needs_trilinos = false;  ///< a case needs Trilinos (hand_over.hpp)
};

/// Checks everything about the sweep but its output directory (the scene, each --vary key,
/// --summary: UsageError or scene::SceneError, exit 2) and plans its cases. A case whose scene
/// is bad input needs nothing and costs 0 (it is recorded as that case's failure when it runs).
SweepPlan plan_sweep(const CommandLine& cl);

/// The group of each case when groups of capacities[g] processes share the cases: the most
/// costly first, each to the group whose cost per process would be least with it (ties: the
/// lower group). The hosts of a sweep's ranks, each host's ranks then sharing a queue.
std::vector<int> assign_groups(const std::vector<SweepCase>& cases, const std::vector<int>& capacities);

/// Checks the output directory (output::OutputError, exit 2, before any case runs), runs the
/// cases of `plan` (plan_sweep(cl)), writes DIR/index.csv on rank 0. The ranks of each host
/// take the next case (the most costly first) whenever they are free, from a queue in memory
/// they share (an MPI shared window); ranks on several hosts first split the cases by host
/// (assign_groups, by estimated cost in proportion to each host's ranks). Returns 0 when every
/// case completed, else the exit code of the first case (in case order) that did not.
/// Collective over `comm`.
int run_sweep(const CommandLine& cl, const SweepPlan& plan, MPI_Comm comm);

/// traverse sweep -j J outside an MPI launcher: checks the output directory (as run_sweep),
/// forks J - 1 worker processes (J at most the number of cases), and each of the J processes
/// takes the next case (the most costly first) whenever it is free, from a queue in shared
/// memory; the workers send their index rows to this process through a pipe, and it writes
/// DIR/index.csv. Each process calls `start_mpi` before its first case: its communicator
/// (MPI_COMM_NULL when cases run without MPI; else MPI_COMM_WORLD of a singleton, each case on
/// MPI_COMM_SELF). A worker that ends before reporting (killed, crashed) leaves the case it was
/// running recorded as an error; the other processes take the rest. SIGINT / SIGTERM to this
/// process stop the workers too (interrupt.hpp), and no process takes another case; those
/// left are recorded as not run. Returns as run_sweep in this process, kSuccess in a worker
/// (which then ends like any run: MPI finalized, no index).
int run_sweep_jobs(const CommandLine& cl, const SweepPlan& plan, const std::function<MPI_Comm()>& start_mpi);

}  // namespace traverse::app

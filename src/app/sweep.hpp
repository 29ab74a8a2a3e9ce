#pragma once
// traverse sweep (docs/sweeps.md): every case of the --vary product run in one process, or
// spread over the ranks of `comm` (each case on one rank, on MPI_COMM_SELF), one output file
// per case and an index of the cases.
#include <mpi.h>

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

/// The sweep checked and its cases planned, each case's scene loaded once to find its cost.
struct SweepPlan {
  std::vector<SweepCase> cases;
};

/// Checks everything about the sweep but its output directory (the scene, each --vary key,
/// --summary: UsageError or scene::SceneError, exit 2) and plans its cases. A case whose scene
/// is bad input needs nothing and costs 0 (it is recorded as that case's failure when it runs).
SweepPlan plan_sweep(const CommandLine& cl);

/// Checks the output directory (output::OutputError, exit 2, before any case runs), runs the
/// cases of `plan` (plan_sweep(cl)), writes DIR/index.csv on rank 0. The ranks take the next
/// case (the most costly first) whenever they are free, from a counter on rank 0 (MPI one-sided
/// atomics). Returns 0 when every
/// case completed, else the exit code of the first case (in case order) that did not.
/// Collective over `comm`.
int run_sweep(const CommandLine& cl, const SweepPlan& plan, MPI_Comm comm);

/// The summary `s` of the complete case file `path`: the value of the index's --summary column.
double case_summary(const std::string& path, const SummarySpec& s);

}  // namespace traverse::app

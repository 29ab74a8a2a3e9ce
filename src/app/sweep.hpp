#pragma once
// traverse sweep (docs/sweeps.md): every case of the --vary product run in one process, or
// spread over the ranks of `comm` (each case on one rank, on MPI_COMM_SELF), one output file
// per case and an index of the cases.
#include <mpi.h>

#include "cli.hpp"

namespace traverse::app {

/// Checks everything up front (the scene, each --vary key, --summary, the output directory;
/// UsageError, scene::SceneError or output::OutputError, exit 2, before any case runs), runs
/// the cases, writes DIR/index.csv on rank 0. Returns 0 when every case completed, else the
/// exit code of the first case (in case order) that did not. Collective over `comm`.
int run_sweep(const CommandLine& cl, MPI_Comm comm);

/// Whether a case of the sweep needs Trilinos (hand_over.hpp: a continuation, or a rod run
/// that does not step on block storage in one process; a case whose scene is bad input needs
/// nothing). Checks the sweep as run_sweep does first (UsageError, SceneError).
bool sweep_needs_trilinos(const CommandLine& cl);

}  // namespace traverse::app

#pragma once
// The rod run with a coupled mass (run_rod hands it over when the scene has one).
#include <mpi.h>

#include "rod_setup.hpp"
#include "run.hpp"

namespace traverse::app {

/// Runs a rod scene whose (only) load is a coupled_mass on the serial reference stepper (one
/// rank, box scheme); what it does not support is refused with a SceneError naming the key;
/// --restart replays from t = 0 (CoupledReplay). Same contract as run_rod otherwise.
void run_rod_coupled(const scene::Scene& scene, const RodSetup& setup, const TimeGrid& grid, const RunOptions& options,
                     MPI_Comm comm);

}  // namespace traverse::app

#pragma once
// The rod run with a coupled mass (run_rod hands it over when the scene has one).
#include <mpi.h>

#include "rod_setup.hpp"
#include "run.hpp"

namespace traverse::app {

/// What the coupled rod run does not support (SceneError naming the key): rho_inf != 1, more
/// than 20001 nodes. Also called by `traverse check`.
void check_coupled_rod(const scene::Scene& scene, const rod::RodModel& model);

/// Runs a rod scene whose (only) load is a coupled_mass (box scheme; any ranks, the planar or
/// the 3D path, any linear solver); what it does not support is refused with a SceneError
/// naming the key; --restart continues from the newest restart point (the mass's state included). Same contract as run_rod
/// otherwise.
void run_rod_coupled(const scene::Scene& scene, const RodSetup& setup, const TimeGrid& grid, const RunOptions& options,
                     MPI_Comm comm);

}  // namespace traverse::app

#pragma once
// The beam run with vehicles on suspensions (run_beam hands it over when the scene has a
// sprung_mass or a vehicle).
#include <mpi.h>

#include "run.hpp"
#include "traverse/beam/beam_problem.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

/// Runs a beam scene whose loads are sprung masses and vehicles on the beam problem `problem`
/// (its loads are ignored) with beam::VehicleBeam. Same contract as run_beam; a unilateral
/// contact that would pull ends the run with the event lift_off.
void run_beam_vehicles(const scene::Scene& scene, const beam::BeamProblem& problem, const RunOptions& options,
                       MPI_Comm comm);

}  // namespace traverse::app

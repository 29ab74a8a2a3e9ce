#pragma once
// The beam run with a coupled mass (run_beam hands it over when the scene has one).
#include <mpi.h>

#include <string>
#include <vector>

#include "output_replay.hpp"
#include "run.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/beam/beam_problem.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

/// The load stepped with the structure by a partitioned iteration: the scene's coupled_mass, or
/// on the rod its sprung_mass; nullptr without one.
const scene::MovingLoadSpec* coupled_load(const scene::Scene& scene);

/// time.end: auto (scene::TimeSpec::end_at_event) and no event by time.auto_limit: appends the
/// event time_limit at (t, position) and prints why the run ended there (unless quiet).
void add_time_limit_event(const scene::Scene& scene, std::vector<output::RunEvent>& events, double t, double position,
                          bool quiet);

/// Runs a beam scene whose (only) load is a coupled_mass, on the beam problem `problem` (its
/// loads are ignored). Same contract as run_beam; --restart re-integrates from t = 0 and checks
/// the output steps the file holds (UsageError when they differ).
void run_beam_coupled(const scene::Scene& scene, const beam::BeamProblem& problem, const RunOptions& options,
                      MPI_Comm comm);

}  // namespace traverse::app

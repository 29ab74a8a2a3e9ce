#pragma once
// Running a validated scene: one function per model.
#include <mpi.h>

#include <string>

#include "cli.hpp"
#include "traverse/core/numerics_error.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/beam/beam_problem.hpp"
#include "traverse/setup/rod_setup.hpp"
#include "traverse/setup/run_checks.hpp"
#include "traverse/setup/step_view.hpp"

namespace traverse::app {

/// Settings of a run taken from the command line.
struct RunOptions {
  std::string output;  ///< resolved output path
  bool overwrite = false;
  bool quiet = false;
  bool verbose = false;  ///< -v: the plan (run_scene) and the solver's details beside the summary
  bool progress = false;
  std::string invocation;
  double restart_interval = 60.0;  ///< wall seconds between restart points (0: every output step)
  double progress_interval = 1.0;  ///< wall seconds between progress reports (output.progress_interval)
  double flush_interval = 1.0;     ///< wall seconds between flushes of the output (output.flush_interval)
  bool restart = false;  ///< continue the run of `output` from its last restart point (traverse/output/restart.hpp)
  setup::RunLimits limits;      ///< --max-memory, --max-steps
  setup::StepCallback on_step;  ///< rod and beam runs with time steps: called every on_step.every steps
};

/// Runs a beam scene; throws scene::SceneError for input that only shows as bad once the
/// model is built, output::OutputError for output-path problems, NumericsError when the
/// numerics fail (after marking the output file failed).
void run_beam(const scene::Scene& scene, const RunOptions& options, MPI_Comm comm);

/// Checks what only the rod model can check (solver parameters, the pair of end
/// conditions); throws scene::SceneError.
void check_rod(const scene::Scene& scene);

/// Runs a rod scene with a continuation section (same contract as run_beam).
void run_statics(const scene::Scene& scene, const RunOptions& options, MPI_Comm comm);

/// Runs a rod scene (same contract as run_beam).
void run_rod(const scene::Scene& scene, const RunOptions& options, MPI_Comm comm);

/// Runs a rod scene whose (only) load is a coupled_mass (box scheme; any ranks, the planar or
/// the 3D path, any linear solver); what it does not support is refused with a SceneError
/// naming the key; --restart continues from the newest restart point (the mass's state
/// included). Same contract as run_rod otherwise.
void run_rod_coupled(const scene::Scene& scene, const setup::RodSetup& setup, const TimeGrid& grid,
                     const RunOptions& options, MPI_Comm comm);

/// Runs a beam scene whose loads are sprung masses and vehicles on the beam problem `problem`
/// (its loads are ignored) with beam::VehicleBeam. Same contract as run_beam; a unilateral
/// contact that would pull ends the run with the event lift_off.
void run_beam_vehicles(const scene::Scene& scene, const beam::BeamProblem& problem, const RunOptions& options,
                       MPI_Comm comm);

/// Runs `scene` with the runner of its model (run_beam, run_statics or run_rod).
void run_scene(const scene::Scene& scene, const RunOptions& options, MPI_Comm comm);

}  // namespace traverse::app

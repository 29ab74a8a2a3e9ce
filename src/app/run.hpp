#pragma once
// Running a validated scene: one function per model.
#include <mpi.h>

#include <stdexcept>
#include <string>

#include "cli.hpp"
#include "run_limits.hpp"
#include "traverse/core/time_grid.hpp"
#include "traverse/rod/rod_model.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

/// The numerics failed (exit code 3): the message says where and why.
class NumericsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

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
  RunLimits limits;      ///< --max-memory, --max-steps
};

/// The outcome of a run's up-front checks (run_limits.hpp, docs/reliability.md "Limits"):
/// the time grid (dynamic runs) and one line saying what was estimated against what limit.
/// Each check_*_run throws scene::SceneError (exit 2) for a run that does not fit; they are
/// collective over `comm` and allocate nothing of the structure's size.
struct CheckedRun {
  TimeGrid grid;
  int output_every = 1;  ///< output.every resolved (a beam's auto from its fastest mode)
  std::string summary;
};
CheckedRun check_beam_run(const scene::Scene& scene, const RunLimits& limits, MPI_Comm comm);
/// A rod run, dynamic or a continuation (then without a time grid); `model` from build_rod_model.
CheckedRun check_rod_run(const scene::Scene& scene, const rod::RodModel& model, const RunLimits& limits, MPI_Comm comm);
/// The checks of the scene's kind of run, for `traverse check`: the summary line.
/// `comm` may be MPI_COMM_NULL (this process alone, MPI not started).
std::string check_run(const scene::Scene& scene, const RunLimits& limits, MPI_Comm comm);

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

/// Runs `scene` with the runner of its model (run_beam, run_statics or run_rod).
void run_scene(const scene::Scene& scene, const RunOptions& options, MPI_Comm comm);

/// Ends what rod runs started for the whole process (Kokkos, started by the first rod run
/// and kept for the next ones, e.g. the cases of a sweep); call before MPI_Finalize.
void finish_solver_runtime();

}  // namespace traverse::app

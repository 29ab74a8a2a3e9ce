#pragma once
// Running a validated scene: one function per model.
#include <mpi.h>

#include <stdexcept>
#include <string>

#include "cli.hpp"
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
  bool progress = false;
  std::string invocation;
  double restart_interval = 60.0;  ///< wall seconds between restart points (0: every output step)
  bool restart = false;  ///< continue the run of `output` from its last restart point (traverse/output/restart.hpp)
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

}  // namespace traverse::app

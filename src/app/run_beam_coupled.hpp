#pragma once
// The beam run with a coupled mass (run_beam hands it over when the scene has one).
#include <mpi.h>

#include <string>
#include <vector>

#include "run.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/beam/beam_problem.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

/// --restart of a run with a coupled mass (beam or rod, both serial and deterministic): the run
/// is integrated again from t = 0 and the output steps the restart source holds are checked
/// against the replay (time and every probe to 1e-12), then rewritten (docs/reliability.md).
class CoupledReplay {
 public:
  /// Reads the source's output steps and moves it aside (opt.restart only).
  CoupledReplay(const RunOptions& opt, const std::vector<std::string>& probe_names,
                const std::vector<std::string>& field_names, MPI_Comm comm);
  std::size_t kept() const { return kept_; }
  /// Throws UsageError when output step o (< kept()) of the replay differs from the file.
  void check(std::size_t o, double t, const std::vector<std::vector<double>>& probes) const;
  /// After each written output step / at the end: removes the source once it is replaced.
  void written(std::size_t steps, MPI_Comm comm) const;
  void finished(std::size_t steps, MPI_Comm comm) const;

 private:
  const RunOptions& opt_;
  std::vector<std::string> names_;
  std::size_t kept_ = 0;
  std::vector<double> time_;
  std::vector<output::Series> probes_;
};

/// The scene's coupled_mass load, or nullptr.
const scene::MovingLoadSpec* coupled_load(const scene::Scene& scene);

/// Runs a beam scene whose (only) load is a coupled_mass, on the beam problem `problem` (its
/// loads are ignored). Same contract as run_beam; --restart re-integrates from t = 0 and checks
/// the output steps the file holds (UsageError when they differ).
void run_beam_coupled(const scene::Scene& scene, const beam::BeamProblem& problem, const RunOptions& options,
                      MPI_Comm comm);

}  // namespace traverse::app

#pragma once
// The up-front checks of a run for each kind of run (run_limits.hpp, docs/reliability.md
// "Limits"), collective over the ranks: every rank computes the same estimate and gets the
// same limit, so all refuse together.
#include <mpi.h>

#include <string>

#include "traverse/core/time_grid.hpp"
#include "traverse/rod/rod_model.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/setup/run_limits.hpp"

namespace traverse::setup {

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

/// What the coupled rod run does not support (SceneError naming the key): rho_inf != 1, more
/// than 20001 nodes.
void check_coupled_rod(const scene::Scene& scene, const rod::RodModel& model);

}  // namespace traverse::setup

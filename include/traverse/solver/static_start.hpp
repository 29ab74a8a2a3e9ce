#pragma once
// The static initial state of a dynamic run, solved over the ranks: the rod's equilibrium
// under the scene's dead loads at t = 0 (gravity, the point forces where they stand, the end
// forces), by rod::StaticSolver's load steps and Newton iteration (same tolerances, same
// rebasing of the frames) on the static model on Tpetra (StaticRodModel), each rank holding
// only its nodes and their ghosts. The linear solver is the block-tridiagonal LU (direct,
// exact across ranks) when the left end is clamped; otherwise, or when that fails, the
// statics solver of solver_parameters.hpp (docs/solver.md, "Static initial state"). In one
// process the same start without Tpetra: block_static_start.hpp.
#include <Teuchos_Comm.hpp>
#include "traverse/core/param_list.hpp"
#include <Teuchos_RCP.hpp>
#include <string>
#include <vector>

#include "traverse/solver/block_static_start.hpp"

namespace traverse::solver {

/// Collective over `comm`. `solver`: the run's solver parameters (the statics defaults of
/// StaticLinearSolver apply to them when the block LU is not used).
StaticStart solve_static_start(const rod::StaticModel& m, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                               const ParamList& solver = ParamList(), int halo = 2);

}  // namespace traverse::solver

#pragma once
// The static initial state of a dynamic run, solved over the ranks: the rod's equilibrium
// under the scene's dead loads at t = 0 (gravity, the point forces where they stand, the end
// forces), by load steps (rod::solve_with_load_steps), each one NOX Newton solve on the static
// model on Tpetra (StaticRodModel; tests of rod::StaticTolerances), the frames rebased after
// each converged step; each rank holds only its nodes and their ghosts. The linear solver is
// the block-tridiagonal LU (direct, exact across ranks) when the left end is clamped;
// otherwise, or when that fails, the statics solver of solver_parameters.hpp (docs/solver.md,
// "Static initial state").
#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>
#include <string>
#include <vector>

#include "traverse/rod/rod_state.hpp"
#include "traverse/rod/static_load_steps.hpp"

namespace traverse::solver {

struct StaticStart {
  rod::StaticReport report;            ///< of the load stepping that ended the solve
  int first_node = 0;                  ///< global index of nodes.front()
  int first_owned_node = 0, num_owned_nodes = 0;  ///< this rank's nodes (the mesh's partition)
  /// Converged: this rank's nodes and up to `halo` more on each side, rebased (theta = 0).
  std::vector<rod::StaticNode> nodes;
  std::string linear_solver;           ///< what solved the Newton systems (the last one tried)
  std::string first_failure;           ///< when the block LU was tried first and failed: why
};

/// Collective over `comm`. `solver`: the run's solver parameters (the statics defaults of
/// StaticLinearSolver apply to them when the block LU is not used).
StaticStart solve_static_start(const rod::StaticModel& m, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                               const Teuchos::ParameterList& solver = Teuchos::ParameterList(), int halo = 2);

/// This rank's piece of the dynamic state at rest from a converged start: its nodes and one
/// ghost each side, as the steppers partition the rod (first_node: the first's index).
rod::RodState dynamic_state_piece(const rod::StaticModel& m, const StaticStart& start, int& first_node);

/// The peak memory of the static initial state per owned node [bytes]: the 3D static system
/// (12 unknowns and a frame per node), its Jacobian and the block-tridiagonal LU (measured as
/// time_step_bytes_per_node is).
double static_start_bytes_per_node();

}  // namespace traverse::solver

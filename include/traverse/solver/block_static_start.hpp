#pragma once
// The static initial state of a dynamic run in one process, without Tpetra: rod::StaticSolver's
// load steps and Newton iteration on the whole rod (the same tolerances and rebasing as the
// distributed start, static_start.hpp), the Newton systems on block storage solved by the
// block-tridiagonal LU with its residual check, when the left end is clamped (as the
// distributed start tries first: the same numbers); otherwise, or when that fails, by
// rod::StaticSolver's sparse LU. Eigen only.
#include <string>
#include <vector>

#include "traverse/rod/static_solver.hpp"

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

/// The start in this process alone: every node (first_node 0, all of them owned). `planar`:
/// when the problem is symmetric about a plane (rod::static_planar_split), the block LU on
/// the in-plane rows and unknowns only (6 x 6 blocks; the same state to rounding), then the
/// full system if that fails.
StaticStart solve_static_start_in_one_process(const rod::StaticModel& m, bool planar = false);

/// This rank's piece of the dynamic state at rest from a converged start: its nodes and one
/// ghost each side, as the steppers partition the rod (first_node: the first's index).
rod::RodState dynamic_state_piece(const rod::StaticModel& m, const StaticStart& start, int& first_node);

}  // namespace traverse::solver

#pragma once
// The tests' serial reference for the rod's statics: the static form's residual and sparse
// Jacobian of the whole rod (rod/static_kernels.hpp), and a Newton solve of its own on it with
// Eigen's sparse LU in one process (the same convergence test and load steps as the static
// start), apart from the NOX solves over Tpetra of the solver module that it checks.
#include <Eigen/SparseCore>

#include <vector>

#include "traverse/rod/static_load_steps.hpp"

namespace traverse::rod {

/// The residual of the whole rod.
VecX static_residual(const StaticModel& m, const std::vector<StaticNode>& nodes);
/// The residual and its sparse Jacobian.
void static_residual_and_jacobian(const StaticModel& m, const std::vector<StaticNode>& nodes, VecX& r,
                                  Eigen::SparseMatrix<double>& J);

/// Newton at the loads of `m` from `nodes` (updated in place; frames rebased on success,
/// restored on failure), on the whole rod in this process: Eigen's sparse LU, the convergence
/// test of `tol` (as the static start's, solver/static_start.hpp).
StaticReport serial_newton(const StaticModel& m, std::vector<StaticNode>& nodes, const StaticTolerances& tol = {});
/// Load steps (rod::solve_with_load_steps) of serial_newton from `nodes` (equilibrium under no
/// load), on the whole rod.
StaticReport serial_load_steps(const StaticModel& m, std::vector<StaticNode>& nodes, const StaticTolerances& tol = {});

}  // namespace traverse::rod

#pragma once
// The tests' serial reference for the rod's statics: the static form's residual and sparse
// Jacobian of the whole rod (rod/static_kernels.hpp), and rod::StaticSolver's Newton and load
// steps on it with Eigen's sparse LU in one process, apart from the Tpetra systems of the
// solver module that it checks.
#include <Eigen/SparseCore>

#include <vector>

#include "traverse/rod/static_load_steps.hpp"

namespace traverse::rod {

/// The residual of the whole rod.
VecX static_residual(const StaticModel& m, const std::vector<StaticNode>& nodes);
/// The residual and its sparse Jacobian.
void static_residual_and_jacobian(const StaticModel& m, const std::vector<StaticNode>& nodes, VecX& r,
                                  Eigen::SparseMatrix<double>& J);

/// `solver`'s Newton from `nodes` (updated in place; frames rebased on success, restored on
/// failure), on the whole rod in this process.
StaticReport serial_newton(const StaticSolver& solver, const StaticModel& m, std::vector<StaticNode>& nodes);
/// `solver`'s load steps from `nodes` (equilibrium under no load), on the whole rod.
StaticReport serial_load_steps(const StaticSolver& solver, const StaticModel& m, std::vector<StaticNode>& nodes);

}  // namespace traverse::rod

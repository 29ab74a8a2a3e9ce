#pragma once
// Builds the Stratimikos linear solver objects of a LinearSolverChoice (private to solver).
#include <Thyra_LinearOpWithSolveFactoryBase.hpp>
#include <Thyra_PreconditionerFactoryBase.hpp>
#include <Tpetra_MultiVector.hpp>

#include <functional>
#include <memory>

#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/solver/rod_step_model.hpp"

namespace traverse::solver {

struct LinearSolverObjects {
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> lows;
  /// Detached from `lows` so the model evaluator owns it (W_prec); null for direct solvers
  /// and unpreconditioned GMRES.
  Teuchos::RCP<Thyra::PreconditionerFactoryBase<double>> prec;
};

/// Stratimikos builder with ReusableIfpack2Factory registered as "Ifpack2" and the
/// block-tridiagonal LU as kBlockTridiagonalLu. The block LU refactors when
/// `jacobian_version()` (RodStepModel::jacobian_version; empty: always) is not the one last
/// factored, and counts its work in `stats` (optional).
LinearSolverObjects build_linear_solver(const LinearSolverChoice& choice,
                                        std::function<long()> jacobian_version = {},
                                        std::shared_ptr<DirectSolverStats> stats = {});

/// Whether `factory` is the block-tridiagonal LU (kBlockTridiagonalLu).
bool is_block_tridiagonal_solve_factory(const Thyra::LinearOpWithSolveFactoryBase<double>& factory);
/// With the block-tridiagonal LU's factory: x = LU^{-1} b with its last factorisation (no
/// refinement). False for another factory, or before the first factorisation.
bool solve_with_last_factors(const Thyra::LinearOpWithSolveFactoryBase<double>& factory,
                             const Tpetra::MultiVector<double>& b, Tpetra::MultiVector<double>& x);

}  // namespace traverse::solver

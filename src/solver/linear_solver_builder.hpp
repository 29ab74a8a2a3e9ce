#pragma once
// Builds the Stratimikos linear solver objects of a LinearSolverChoice (private to solver).
#include <Thyra_LinearOpWithSolveFactoryBase.hpp>
#include <Thyra_PreconditionerFactoryBase.hpp>

#include "traverse/solver/linear_solver_choice.hpp"

namespace traverse::solver {

struct LinearSolverObjects {
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> lows;
  /// Detached from `lows` so the model evaluator owns it (W_prec); null for direct solvers
  /// and unpreconditioned GMRES.
  Teuchos::RCP<Thyra::PreconditionerFactoryBase<double>> prec;
};

/// Stratimikos builder with ReusableIfpack2Factory registered as "Ifpack2".
LinearSolverObjects build_linear_solver(const LinearSolverChoice& choice);

}  // namespace traverse::solver

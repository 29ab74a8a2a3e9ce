#pragma once
// NOX Newton on a RodStepModel: NOX::Thyra::Group + NOX::Solver::buildSolver, line search per
// the parameters, status tests (max|f| AND WRMS update) OR max iterations OR non-finite.
// The group, the solver, W, the linear solver and the preconditioner object are built once
// and reused by every solve (only the initial guess and the model's old level change).
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>
#include <Tpetra_Vector.hpp>
#include <memory>

#include "traverse/solver/newton_report.hpp"

namespace traverse::solver {

class RodStepModel;

class NewtonSolver {
 public:
  /// `params`: validated_solver_parameters keys (Newton, line search, NOX pass-through,
  /// linear tolerance). The model must already have its W factory (and prec factory).
  NewtonSolver(Teuchos::RCP<RodStepModel> model, const Teuchos::ParameterList& params);
  ~NewtonSolver();
  NewtonSolver(const NewtonSolver&) = delete;
  NewtonSolver& operator=(const NewtonSolver&) = delete;

  /// Newton from x (in: initial guess; out: the last iterate, the solution when converged).
  /// Exceptions thrown inside NOX or the linear solver are caught and reported as failure.
  NewtonReport solve(Tpetra::Vector<double>& x);

  /// The NOX parameter list in use (after defaults were merged).
  const Teuchos::ParameterList& nox_parameters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace traverse::solver

#pragma once
// Private to the solver module: the distributed objects shared by the statics routines
// (mesh, StaticRodModel, the Stratimikos linear solver with its preconditioner attached),
// the bordered Newton used for fixed-parameter solves, bifurcation location and branch
// switching, and the eigenvalue analysis (static_stability.cpp).
#include <Thyra_LinearOpWithSolveFactoryBase.hpp>

#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/solver/static_continuation.hpp"
#include "traverse/solver/static_rod_model.hpp"

namespace traverse::solver {

using Params = std::array<double, rod::num_static_parameters>;

struct StaticContext {
  Comm comm;
  Teuchos::RCP<mesh::DistributedMesh> mesh;
  Teuchos::RCP<StaticRodModel> model;
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> lows;  ///< preconditioner attached
  LinearSolverChoice choice;

  /// Frames of `state` become the model's references (state should be rebased).
  StaticContext(const rod::StaticProblem& problem, const std::vector<rod::StaticNode>& state, const Comm& comm,
                const Teuchos::ParameterList& solver);
  /// Solves W y = b (Stratimikos); false on every rank when the solver reports failure on any.
  bool solve(const StaticRodModel::Matrix& W, const StaticRodModel::Vector& b, StaticRodModel::Vector& y) const;
};

/// Newton on F(x, p) = 0 with, when iparam >= 0, the parameter p[iparam] free and the extra
/// equation a . (x - x_ref) = c (a, x_ref distributed like x). iparam < 0: fixed parameters.
StaticSolveReport bordered_newton(const StaticContext& ctx, StaticRodModel::Vector& x, Params& p, int iparam,
                                  const StaticRodModel::Vector* a, const StaticRodModel::Vector* x_ref, double c,
                                  int max_iterations, double ftol, double xtol);

/// Eigenvalue analysis at (x, p) (static_stability.cpp).
Stability compute_stability(const StaticContext& ctx, const StaticRodModel::Vector& x, const Params& p,
                            const StabilityOptions& options);

/// -0.01 EI / (rhoA L^4) unless options.shift is set.
double stability_shift(const rod::StaticProblem& problem, const StabilityOptions& options);

}  // namespace traverse::solver

#pragma once
// Private to the solver module: the distributed objects shared by the statics routines
// (mesh, StaticRodModel, the Stratimikos linear solver with its preconditioner attached), the
// fixed-parameter solve (NOX), the bordered Newton of the bifurcation location and the branch
// switching, and the eigenvalue analysis (static_stability.cpp).
#include <Thyra_LinearOpWithSolveFactoryBase.hpp>

#include <functional>

#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/solver/static_continuation.hpp"
#include "traverse/solver/static_rod_model.hpp"

namespace traverse::solver {

using Params = std::array<double, rod::num_static_parameters>;

/// The statics linear solver (Stratimikos, preconditioner attached) with verdicts that are
/// the same on every rank: a direct solver can fail on one rank's block only (a singular
/// subdomain factorisation throws there), and all ranks must then take the same branch.
class StaticLinearSolver {
 public:
  /// `solver`: keys of solver_parameters.hpp. On 2+ ranks without an explicit
  /// "Preconditioner", GMRES + ILUT (see the .cpp file for why).
  StaticLinearSolver(const Teuchos::ParameterList& solver, const Comm& comm);
  /// The block-tridiagonal LU as a direct solver (exact across ranks, residual-checked, no
  /// Krylov basis), factorised again only when jacobian_version() has changed; with
  /// `clamp_left_end` factorised with the left end clamped and each solve corrected for the
  /// end's own rows (BlockTridiagonalPreconditioner::set_left_end_clamp).
  StaticLinearSolver(std::function<long()> jacobian_version, const Comm& comm, bool clamp_left_end = false);
  /// Factorisation or preconditioner set-up for W (kept for solve); false on every rank when
  /// it fails on any.
  bool set_up(const Teuchos::RCP<const Thyra::VectorSpaceBase<double>>& space, const StaticRodModel::Matrix& W) const;
  /// y = W^-1 b with the last set-up; false on every rank when the solver reports failure (or
  /// y is not finite) on any.
  bool solve(const StaticRodModel::Vector& b, StaticRodModel::Vector& y) const;
  const LinearSolverChoice& choice() const { return choice_; }
  long set_up_count() const { return set_ups_; }  ///< calls of set_up so far
  long solve_count() const { return solves_; }    ///< calls of solve so far
  const Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>>& factory() const { return lows_; }

 private:
  bool everywhere(bool local) const;
  Comm comm_;
  LinearSolverChoice choice_;
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> lows_;
  mutable Teuchos::RCP<const Thyra::VectorSpaceBase<double>> space_;  // of the last set-up
  mutable Teuchos::RCP<Thyra::LinearOpWithSolveBase<double>> op_;
  mutable long set_ups_ = 0, solves_ = 0;
};

struct StaticContext {
  Comm comm;
  Teuchos::RCP<mesh::DistributedMesh> mesh;
  Teuchos::RCP<StaticRodModel> model;
  StaticLinearSolver linear;

  /// Frames of `state` become the model's references (state should be rebased).
  StaticContext(const rod::StaticProblem& problem, const std::vector<rod::StaticNode>& state, const Comm& comm,
                const Teuchos::ParameterList& solver);
};

/// Newton (NOX, static_newton.hpp) on F(x, p) = 0 at the fixed parameters p from x:
/// max |f| <= ftol and max |dx| <= xtol. The model's problem keeps its own values.
StaticSolveReport fixed_parameter_solve(const StaticContext& ctx, StaticRodModel::Vector& x, const Params& p,
                                        int max_iterations, double ftol, double xtol);

/// Newton on F(x, p) = 0 with the parameter p[iparam] free and the extra equation
/// a . (x - x_ref) = c (a, x_ref distributed like x), by block elimination: two solves with
/// the Jacobian per iteration (-F and dF/dp). The chord-plane solves of the bifurcation
/// location and the branch switch (docs/statics.md says why this is not LOCA's).
StaticSolveReport bordered_newton(const StaticContext& ctx, StaticRodModel::Vector& x, Params& p, int iparam,
                                  const StaticRodModel::Vector& a, const StaticRodModel::Vector& x_ref, double c,
                                  int max_iterations, double ftol, double xtol);

/// Eigenvalue analysis at (x, p) (static_stability.cpp).
Stability compute_stability(const StaticContext& ctx, const StaticRodModel::Vector& x, const Params& p,
                            const StabilityOptions& options);

/// -0.01 EI / (rhoA L^4) unless options.shift is set.
double stability_shift(const rod::StaticProblem& problem, const StabilityOptions& options);

}  // namespace traverse::solver

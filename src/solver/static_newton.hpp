#pragma once
// One NOX Newton solve of the static rod model (StaticRodModel) at fixed loads: NOX::Thyra::Group
// on the model (W the model's own matrix, solved by the model's W factory), full Newton steps,
// and the status tests
//   OR(FiniteValue, AND(max|f| <= residual, scaled update <= update), MaxIters)
// where the scaled update is max_i |x_k - x_{k-1}|_i / scale(kind of unknown i), the kinds
// r, theta, kappa, n of rod/static_kernels.hpp (rod::scaled_update: for a force in a direction
// the rod strains in, the smaller of that and the strain's update). It serves the static
// initial state's load steps (scales rod::static_update_scales, residual ftol * force scale)
// and the statics' fixed-parameter solves (unit scales). The frames stay fixed during a
// solve: the caller rebases them after it converges. Private to the solver module.
#include <array>

#include "static_context.hpp"
#include "traverse/rod/static_load_steps.hpp"

namespace traverse::solver {

struct StaticNewtonTests {
  double residual = 1e-9;  ///< max |f| <= residual [N] ...
  double update = 1e-10;   ///< ... and the scaled update <= update, after at least one iteration
  std::array<double, 4> scales{1.0, 1.0, 1.0, 1.0};  ///< of r, theta, kappa, n
  /// The rod's compliance C (rod::scaled_update): zero, the force updates measured by the scale only.
  Vec3 compliance = Vec3::Zero();
  int max_iterations = 40;
  /// > 0: a residual 2-norm above `divergence` times the initial guess's in two consecutive
  /// iterations ends the solve as diverged (NOX::StatusTest::Divergence) instead of using up
  /// the iterations; 0: no such test.
  double divergence = 0.0;
};

/// Newton on `model` (its problem's parameter values, or its fixed model) from x. x in: the
/// initial guess; out: the last iterate (the solution when converged). The report's message
/// says why a solve failed: a residual that is not finite, the iterations used up (with where
/// the residual and the update stood against their tests), or an exception from NOX or the
/// linear solver. Collective over the model's communicator.
/// W: the matrix the Jacobian goes into (on the mesh graph); null: the model's own (the
/// fastest to fill, but shared with any other solver group on the model, e.g. LOCA's).
StaticSolveReport nox_static_solve(const Teuchos::RCP<StaticRodModel>& model, StaticRodModel::Vector& x,
                                   const StaticNewtonTests& tests,
                                   const Teuchos::RCP<StaticRodModel::Matrix>& W = Teuchos::null);

}  // namespace traverse::solver

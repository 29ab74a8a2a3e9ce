#pragma once
// The tests' independent reference for the rod's time step (small problems only, N <= ~200):
// plain Newton with the exact Jacobian on the whole rod and Eigen's sparse LU, one time step
// at a time, written apart from the solver module's NOX path that it checks; and the coupled
// mass's rod solve on it (reference_rod_solve).
#include <Eigen/SparseCore>

#include <memory>

#include "traverse/rod/coupled_mass_rod.hpp"
#include "traverse/rod/rod_kernels.hpp"

namespace traverse::rod {

struct ReferenceStepReport {
  bool converged = false;
  int iterations = 0;
  double last_correction = 0.0;  ///< max |dx| of the last Newton update
  double residual_norm = 0.0;    ///< max |r| at the returned state
};

class ReferenceStepper {
 public:
  explicit ReferenceStepper(RodModel model);

  const RodModel& model() const { return model_; }
  RodModel& model() { return model_; }

  /// Global residual r(x) for unknowns x at the new level (layout: RodModel).
  VecX residual(const StepTimes& step, const RodState& old_state, const VecX& x) const;
  /// Residual and sparse Jacobian dr/dx.
  void residual_and_jacobian(const StepTimes& step, const RodState& old_state, const VecX& x,
                             VecX& r, Eigen::SparseMatrix<double>& J) const;

  /// Stacked node unknowns of a state (Newton initial guess = the old state).
  VecX unknowns(const RodState& state) const;
  /// The new state implied by converged unknowns x.
  RodState state_from_unknowns(const RodState& old_state, const VecX& x, double dt) const;

  /// Advance state by dt (Newton from the old state). On failure the state is unchanged.
  ReferenceStepReport step(RodState& state, double dt) const;

  double rtol = 1e-13;   ///< stop when max|dx| <= rtol * max|x| + atol
  double atol = 1e-15;
  int max_iterations = 25;

 private:
  RodModel model_;
};

/// The coupled mass's rod solve on ReferenceStepper's residual and Jacobian (sparse LU of the
/// whole rod; its tolerances), warm-started from the last solution on `again`.
std::unique_ptr<CoupledRodSolve> reference_rod_solve(RodModel model);

}  // namespace traverse::rod

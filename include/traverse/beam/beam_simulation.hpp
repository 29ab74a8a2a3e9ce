#pragma once
// Driver: modal (Galerkin) beam with moving masses/forces, fixed-step time integration.
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "traverse/beam/beam_problem.hpp"

namespace traverse::beam {

class BeamSimulation;

/// State handed to the observer at output instants. Valid only during the callback.
class BeamSnapshot {
 public:
  double t;            ///< time [s]
  const VecX& Y;       ///< modal coordinates [m]
  const VecX& Ydot;    ///< modal velocities [m/s]

  double deflection(double x) const;  ///< w(x, t) [m], positive up
  double slope(double x) const;       ///< w_x(x, t) [-]
  double velocity(double x) const;    ///< w_t(x, t) [m/s]
  /// w_tt(x, t) [m/s^2] from the modal accelerations Y'' of the equation of motion at this
  /// state (needs BeamProblem::accelerations; throws std::logic_error otherwise).
  double acceleration(double x) const;
  std::size_t load_count() const;
  double load_position(std::size_t k) const;  ///< x_k(t) [m] (may lie outside [0, L])
  bool load_on_beam(std::size_t k) const;     ///< t >= entry and 0 <= x_k <= L
  /// w(x_k(t), t) [m] if the load is on the beam, NaN otherwise.
  double load_deflection(std::size_t k) const;

 private:
  friend class BeamSimulation;
  BeamSnapshot(const BeamSimulation& s, double time, const VecX& y, const VecX& ydot, const VecX* yddot)
      : t(time), Y(y), Ydot(ydot), sim_(&s), Yddot_(yddot) {}
  const BeamSimulation* sim_;
  const VecX* Yddot_;
};

/// Observer callback, called at t_start, every `output_every` grid steps and at t_end.
using BeamObserver = std::function<void(const BeamSnapshot&)>;

/// Solves
///   (Mb + sum M_k Phi_k Phi_k^T) Y'' + (C + sum 2 M_k v_k Phi_k Phi_k'^T) Y'
///     + (Kb + sum M_k (v_k^2 Phi_k Phi_k''^T + a_k Phi_k Phi_k'^T)) Y = -Pb + sum F_k Phi_k
/// (Phi_k = Phi(x_k(t)), F_k = -M_k g by default; M_k = 0 for a moving force; C the structural
/// damping of BeamProblem::damping, modal_damping.hpp) with fixed steps.
/// The mass matrix is inverted by a Woodbury update of the precomputed Mb^{-1}
/// (resp. (Mb + h^2/4 Kb)^{-1} for Newmark), so a step costs O(n^2) per load.
/// Adaptive stepping: a step whose error stays above the tolerance at the smallest step.
class StepSizeUnderflow : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class BeamSimulation {
 public:
  /// A remainder of the time span below this fraction of dt joins the last step.
  static constexpr double kGridJoin = 1e-9;
  /// Throws std::invalid_argument for a problem it cannot integrate (non-positive sizes, a
  /// time grid of more than kMaxGridSteps steps: traverse/core/time_grid.hpp).
  explicit BeamSimulation(BeamProblem problem);
  ~BeamSimulation();
  BeamSimulation(const BeamSimulation&) = delete;
  BeamSimulation& operator=(const BeamSimulation&) = delete;

  /// Reset to the initial state at t_start and integrate to t_end, calling the observer.
  void run(const BeamObserver& observer = {});
  /// Reset to the initial state at t_start (done by run as well).
  void reset();

  const BeamProblem& problem() const { return problem_; }
  const ModeSet& modes() const { return *modes_; }
  const GalerkinMatrices& matrices() const { return mats_; }
  const std::vector<LoadKinematics>& kinematics() const { return kin_; }
  double time() const { return t_; }
  const VecX& Y() const { return Y_; }
  const VecX& Ydot() const { return V_; }
  /// Number of (sub)steps taken by the last run (adaptive: the accepted ones).
  long steps_taken() const { return steps_; }
  /// Adaptive runs: accepted and rejected steps, the range of dt.
  const StepControlTotals& adaptive_totals() const { return totals_; }
  /// Adaptive runs: the step the controller proposes next [s].
  double proposed_dt() const { return next_dt_; }
  /// w(x) [m] of the current state.
  double deflection(double x) const;

 private:
  friend class BeamSnapshot;
  struct Work;

  void prepare_status(double ta, double tb);
  void eval_loads(double t);
  void residual(const VecX& Y, const VecX& V, Eigen::Ref<VecX> r) const;
  void solve_low_rank(const MatX& Binv, const VecX& r, VecX& out);
  void acceleration(double t, const VecX& Y, const VecX& V, VecX& A);
  void step(double ta, double tb);
  /// Adaptive: from ta to tb in steps chosen by step doubling.
  void adaptive_advance(double ta, double tb);
  double doubling_error(const VecX& Yf, const VecX& Vf);
  void set_adaptive_floors();
  void rk4_step(double ta, double tb);
  void newmark_step(double ta, double tb);
  const MatX& newmark_inverse(double h);
  void evaluate_modes(double x) const;
  /// The observer's snapshot of the current state (with Y'' when BeamProblem::accelerations).
  BeamSnapshot snapshot();

  BeamProblem problem_;
  std::shared_ptr<const ModeSet> modes_;
  GalerkinMatrices mats_;
  std::vector<LoadKinematics> kin_;
  std::vector<double> force_, inertia_;  // per load: F_k [N], M_k [kg]
  MatX Mb_inv_;
  MatX C_;              ///< structural damping matrix (zero size when undamped)
  VecX A_out_;          ///< Y'' at the output instant (BeamProblem::accelerations)
  std::unique_ptr<Work> w_;
  double t_ = 0.0;
  long steps_ = 0;
  VecX Y_, V_, A_;
  bool A_valid_ = false;
  // Adaptive stepping
  StepControlTotals totals_;
  double next_dt_ = 0.0, peak_Y_ = 0.0, peak_V_ = 0.0, floor_Y_ = 0.0, floor_V_ = 0.0;
  bool after_rejection_ = false;
};

}  // namespace traverse::beam

#pragma once
// Driver: modal (Galerkin) beam with moving masses/forces, fixed-step time integration.
#include <functional>
#include <memory>
#include <stdexcept>
#include <vector>

#include "traverse/beam/beam_problem.hpp"
#include "traverse/time/time_integrator.hpp"

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
/// The time integrator (time/time_integrator.hpp) takes the steps: fixed ones on the grid of
/// dt, split where a load enters or leaves the beam (BeamProblem::split_at_load_events), or
/// adaptive ones checked by step doubling (BeamProblem::adaptive).
class BeamSimulation : public time::SteppedModel {
 public:
  /// A remainder of the time span below this fraction of dt joins the last step.
  static constexpr double kGridJoin = 1e-9;
  /// Throws std::invalid_argument for a problem it cannot integrate (non-positive sizes, a
  /// time grid of more than kMaxGridSteps steps: traverse/core/time_grid.hpp).
  explicit BeamSimulation(BeamProblem problem);
  ~BeamSimulation();
  BeamSimulation(const BeamSimulation&) = delete;
  BeamSimulation& operator=(const BeamSimulation&) = delete;

  /// Reset to the initial state at t_start and integrate to t_end, calling the observer
  /// (time::RunFailed when an adaptive step fails at dt_min).
  void run(const BeamObserver& observer = {});
  /// The steps of a run of the problem.
  time::Schedule schedule() const;
  /// Reset to the initial state at t_start (done by run as well).
  void reset();

  const BeamProblem& problem() const { return problem_; }
  const ModeSet& modes() const { return *modes_; }
  const GalerkinMatrices& matrices() const { return mats_; }
  const std::vector<LoadKinematics>& kinematics() const { return kin_; }
  double time() const override { return t_; }
  /// The integrator's model: a step of h from the current state (fixed), or an attempt of h
  /// checked by step doubling (adaptive), then accept() or reject().
  void step(double h) override;
  time::Attempt attempt(double h) override;
  std::vector<double> accept() override;
  void reject() override;
  /// The first time after t where a load enters or leaves the beam (+inf: none).
  double next_kink(double t) const override;
  const VecX& Y() const { return Y_; }
  const VecX& Ydot() const { return V_; }
  /// Number of (sub)steps taken by the last run (adaptive: the accepted ones).
  long steps_taken() const { return steps_; }
  /// Adaptive runs through run(): accepted and rejected steps, the range of dt.
  const StepControlTotals& adaptive_totals() const { return totals_; }
  /// w(x) [m] of the current state.
  double deflection(double x) const;
  /// The observer's snapshot of the current state (with Y'' when BeamProblem::accelerations).
  BeamSnapshot snapshot();

 private:
  friend class BeamSnapshot;
  struct Work;

  void prepare_status(double ta, double tb);
  void eval_loads(double t);
  void residual(const VecX& Y, const VecX& V, Eigen::Ref<VecX> r) const;
  void solve_low_rank(const MatX& Binv, const VecX& r, VecX& out);
  void acceleration(double t, const VecX& Y, const VecX& V, VecX& A);
  void advance(double ta, double tb);
  double doubling_error(const VecX& Yf, const VecX& Vf);
  void set_adaptive_floors();
  void rk4_step(double ta, double tb);
  void newmark_step(double ta, double tb);
  const MatX& newmark_inverse(double h);
  void evaluate_modes(double x) const;

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
  std::vector<double> events_;  ///< the loads' entries and exits (split_at_load_events), sorted
  // Adaptive stepping: the attempt in hand (its start and length) and the error scales
  StepControlTotals totals_;
  VecX Y0_, V0_, A0_;
  bool A0_valid_ = false;
  long steps0_ = 0;
  double h_ = 0.0;
  double peak_Y_ = 0.0, peak_V_ = 0.0, floor_Y_ = 0.0, floor_V_ = 0.0;
};

/// What a beam run holds [bytes], from its data layout: per quadrature node on every rank
/// (its position and weight), per output node of a rank (its position, each written field
/// component, the modes and their first two derivatives there: three vectors of `modes`
/// values), and the modal matrices (mass, stiffness, damping and the integrator's work
/// matrices, modes^2 each) with each load's modal vectors.
struct BeamMemory {
  double per_quadrature_node = 0.0, per_output_node = 0.0, fixed = 0.0;
};
BeamMemory beam_memory(int modes, int loads, int field_components);

}  // namespace traverse::beam

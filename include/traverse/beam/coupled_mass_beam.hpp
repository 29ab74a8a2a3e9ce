#pragma once
// A beam carrying a mass that moves by itself (two-way coupling, docs/beam.md
// "Coupled mass"): the mass's axial position x(t) is an unknown of the Galerkin ODE.
#include <functional>
#include <memory>
#include <string>

#include "traverse/beam/beam_problem.hpp"
#include "traverse/time/time_integrator.hpp"

namespace traverse::beam {

/// The coupled mass (plain data, SI units).
struct CoupledMass {
  double mass = 0.0;        ///< M [kg], > 0
  double start = 0.0;       ///< x(t_start) [m], in [0, L]
  double velocity = 0.0;    ///< x'(t_start) [m/s] (signed)
  double drive = 0.0;       ///< D [N]: constant force along the beam's axis (tangent)
  double resistance = 0.0;  ///< c [N s/m] >= 0: force -c x' (external, not through the beam)
  bool unilateral = false;  ///< resting on the beam's upper side: lift-off ends the run
  double friction = 0.0;    ///< Coulomb mu >= 0: tangential force -mu |N| sign(x') (N the normal force)
};

/// Why a coupled run ended.
enum class CoupledEnd {
  EndTime,    ///< t_end reached with the mass on the beam
  LeftLeft,   ///< the mass left the beam at x = 0
  LeftRight,  ///< the mass left the beam at x = L
  LiftOff,    ///< unilateral contact: the normal force reached zero (it would pull)
  Stick       ///< friction: x' reached 0 and the demand is at most mu |N| (the mass sticks)
};
/// "end_time", "left_beam_at_0", "left_beam_at_L", "lift_off", "stick".
const std::string& coupled_end_name(CoupledEnd e);

/// Energies of beam + mass [J] and the work of the non-conservative forces.
struct CoupledEnergies {
  double beam_kinetic = 0.0;   ///< 1/2 V^T Mb V
  double beam_elastic = 0.0;   ///< 1/2 Y^T Kb Y
  double beam_gravity = 0.0;   ///< Pb . Y = int rhoA g w dx (0 without self weight)
  double mass_kinetic = 0.0;   ///< 1/2 M (x'^2 + (dw/dt)^2), dw/dt = w_t + x' w_x at x
  double mass_gravity = 0.0;   ///< M g w(x)
  double drive_work = 0.0;     ///< int D x' dt since t_start
  double dissipated = 0.0;     ///< int c x'^2 dt since t_start
  double friction_work = 0.0;  ///< int mu |N| |x'| dt since t_start
  /// The mechanical energy (first five terms).
  double mechanical() const { return beam_kinetic + beam_elastic + beam_gravity + mass_kinetic + mass_gravity; }
  /// mechanical - drive work + the losses (constant up to the time discretisation).
  double balance() const { return mechanical() - drive_work + dissipated + friction_work; }
};

/// Solves, for generalised coordinates (Y, x) with the mass's vertical velocity
/// dw/dt = G . (Y', x'), G = (Phi(x), w_x(x)),
///     (blockdiag(Mb, M) + M G G^T) (Y'', x'') = (-Pb - Kb Y - M (g + h) Phi,  D - c x' - M (g + h) w_x)
///     h = 2 x' Phi'(x).Y' + x'^2 Phi''(x).Y      (Coriolis and centrifugal parts of d2w/dt2)
/// the Lagrange equations of T = 1/2 Y'^T Mb Y' + 1/2 M (x'^2 + (dw/dt)^2),
/// U = 1/2 Y^T Kb Y + Pb . Y + M g w(x) (docs/beam.md "Coupled mass"): the beam row is the
/// moving mass of section 1 with v = x', a = x''; the mass row is the spec's
/// x'' = D/M - (c/M) x' - (g + w_tt + 2 x' w_xt + x'^2 w_xx) w_x plus its term x'' w_x^2
/// (second order in the slope), which makes the pair conservative. The mass matrix is a
/// rank-one update of blockdiag(Mb, M) (Sherman-Morrison on the precomputed Mb^{-1}).
/// RK4 (the work of drive and resistance integrated with the state) or average-acceleration
/// Newmark (Kb and c implicit, the modes at x and the convective terms by a fixed-point
/// iteration; the works by the trapezoidal rule) at fixed steps; a step
/// in which an event happens (the mass leaves at either end, unilateral lift-off) is
/// shortened to end at the event (secant on the step length), and the run ends there.
/// With problem().adaptive (time.adaptive, docs/adaptive.md) the steps are chosen by step
/// doubling instead: each step is two half steps checked against one full step, the error
/// (half - full) / (2^p - 1) weighed per group (Y, Y', the mass's x and x') against the
/// tolerance; the steps land on the output times, and an event is located as at fixed steps
/// (by the same pair of half steps).
/// Coulomb friction (docs/beam.md "Coupled mass"): the generalised force -mu |N| s on x (s the
/// sliding direction, fixed while sliding; N = M (g + w_tt + 2 x' w_xt + x'^2 w_xx) + w_x (D - c x')
/// the normal force to first order in the slope, linear in the beam's accelerations, so the
/// accelerations come from a 2 x 2 reduced solve). The step in which x' s reaches 0 is shortened
/// to it; there the mass sticks (the event, the run ends) when the tangential force that holds it
/// to the beam is at most mu |N|, otherwise it reverses (s flips) and the step goes on.
class CoupledMassBeam : public time::SteppedModel {
 public:
  /// Throws std::invalid_argument for a problem it cannot integrate (loads other than the
  /// coupled mass, non-positive sizes, start off the beam). run() throws std::runtime_error
  /// when the Newmark iteration does not converge.
  CoupledMassBeam(BeamProblem beam, CoupledMass mass);
  ~CoupledMassBeam();
  CoupledMassBeam(const CoupledMassBeam&) = delete;
  CoupledMassBeam& operator=(const CoupledMassBeam&) = delete;

  using Observer = std::function<void(const CoupledMassBeam&)>;
  /// Resets to the initial state (static equilibrium under the beam's and the mass's weight,
  /// or rest, per problem().initial_state; x = start, x' = velocity) and integrates to t_end or
  /// the first event. The observer sees t_start, every output_every grid steps and the last state.
  void run(const Observer& observer = {});
  void reset();
  /// The steps of a run of the problem (time/time_integrator.hpp).
  time::Schedule schedule() const;
  /// The integrator's model: a grid step of h (fixed; the Newmark iteration's failure throws
  /// time::StepFailed), or an attempt of h checked by step doubling, then accept() (which
  /// locates an event in it) or reject(). The run ends at an event (ended()).
  void step(double h) override;
  time::Attempt attempt(double h) override;
  std::vector<double> accept() override;
  void reject() override {}
  bool ended() const override { return end_ != CoupledEnd::EndTime; }

  const BeamProblem& problem() const { return problem_; }
  const CoupledMass& coupled_mass() const { return mass_; }
  const ModeSet& modes() const { return *modes_; }
  const GalerkinMatrices& matrices() const { return mats_; }
  double time() const override { return t_; }
  const VecX& Y() const { return Y_; }
  const VecX& Ydot() const { return V_; }
  double position() const { return x_; }  ///< x [m]
  double speed() const { return v_; }     ///< x' [m/s] (signed)
  /// x'' [m/s^2] and the mass's vertical acceleration d2w/dt2 [m/s^2] at the current state.
  double acceleration() const;
  double vertical_acceleration() const;
  double deflection(double x) const;        ///< w(x) [m]
  double velocity(double x) const;          ///< w_t(x) [m/s]
  double slope(double x) const;             ///< w_x(x)
  double mass_deflection() const { return deflection(x_); }  ///< w(x(t), t)
  double mass_vertical_velocity() const;    ///< dw/dt = w_t + x' w_x at x
  /// Contact force of the beam on the mass [N]: the component along the beam's normal
  /// (-w_x, 1) / sqrt(1 + w_x^2) (positive: pushes the mass up), M (g + d2w/dt2 - w_x x'') / sqrt(1 + w_x^2).
  double normal_force() const;
  /// Its tangential component [N] (along (1, w_x) / sqrt(1 + w_x^2)): zero without friction
  /// to the model's order (the drive acts along the axis), evaluated from the state.
  double tangential_force() const;
  CoupledEnergies energies() const;
  /// Steps taken (adaptive: the accepted half steps).
  long steps_taken() const { return steps_; }
  /// Adaptive runs through run(): accepted, rejected and failed steps, the range of dt.
  const StepControlTotals& adaptive_totals() const { return totals_; }
  CoupledEnd end_reason() const { return end_; }

 private:
  struct Work;
  struct State;
  void derivative(const State& s, State& d) const;
  /// derivative() at the current state (its work arrays then hold the modes at x).
  State current_derivative() const;
  void rk4(const State& s0, double h, State& s1) const;
  void newmark(const State& s0, double h, State& s1) const;
  void step(const State& s0, double h, State& s1) const;
  /// The step that is kept: step(), or with adaptive steps two half steps.
  void advance(const State& s0, double h, State& s1) const;
  /// Adaptive: (half - full) / (2^p - 1) over absolute + relative scale, the largest group.
  double doubling_error(const State& half, const State& full) const;
  void set_adaptive_floors();
  void current_state(State& s) const;
  const MatX& newmark_inverse(double h) const;
  double event_value(CoupledEnd e, const State& s) const;
  bool locate_event(const State& s0, double t0, double h, State& s1);
  /// The accelerations (Y'', x'') of the state's rows (w_->r0, r1 and the modes at x in the work
  /// arrays) with the effective matrices Binv, Mx and friction; returns the normal force.
  double accelerations(const MatX& Binv, double Mx, double r1, double n_rest, double slope, VecX& A, double& a) const;
  /// At x' = 0: whether the friction holds the mass (and the direction it slides otherwise).
  bool holds(const State& s, double& direction) const;
  bool advance_to(double t_target);
  void refresh_accelerations();  ///< A_, a_, n_ from the current state
  void load_state(const State& s);

  BeamProblem problem_;
  CoupledMass mass_;
  std::shared_ptr<const ModeSet> modes_;
  GalerkinMatrices mats_;
  MatX Mb_inv_;
  std::unique_ptr<Work> w_;
  double t_ = 0.0;
  long steps_ = 0;
  VecX Y_, V_, A_;
  double a_ = 0.0;
  double x_ = 0.0, v_ = 0.0, work_drive_ = 0.0, work_loss_ = 0.0, work_friction_ = 0.0, n_ = 0.0;
  double dir_ = 1.0;  ///< sliding direction (friction)
  // Adaptive stepping: totals, the attempt, the peaks and floors of the groups' scales.
  StepControlTotals totals_;
  double h_ = 0.0;  ///< the attempt in hand (its states in the work arrays s0, s1)
  double peak_Y_ = 0.0, peak_V_ = 0.0, peak_dx_ = 0.0, peak_v_ = 0.0;
  double floor_Y_ = 0.0, floor_V_ = 0.0, floor_x_ = 0.0, floor_v_ = 0.0;
  CoupledEnd end_ = CoupledEnd::EndTime;
};

}  // namespace traverse::beam

#pragma once
// A beam crossed by vehicles on suspensions (docs/beam.md): the vehicles' bodies are
// unknowns coupled with the beam's modes through the axles' contact forces.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "traverse/beam/beam_problem.hpp"
#include "traverse/time/time_integrator.hpp"

namespace traverse::beam {

/// One axle of a vehicle (plain data, SI units).
struct Axle {
  double offset = 0.0;     ///< e_a [m]: from the body's centre, positive ahead (along the travel)
  double stiffness = 0.0;  ///< k_a [N/m] > 0
  double damping = 0.0;    ///< c_a [N s/m] >= 0
  double wheel_mass = 0.0; ///< m_w,a [kg] >= 0: unsprung, rides on the structure (moving-mass inertia)
};

/// A vehicle: a rigid body on its axles' suspensions, travelling at a prescribed speed.
/// One axle: a sprung mass (bounce z only); several: bounce z and pitch theta (needs J > 0).
/// Kinematics of the leading axle as MovingLoad's (entry end, speed, acceleration, entry_time,
/// start): at entry_time it is at `start` (default the entry end); before, the vehicle comes at
/// the entry speed over rigid, level ground (w = 0), so that it arrives in its static state.
struct Vehicle {
  std::string name;
  double mass = 0.0;           ///< M_v [kg] > 0 (the body, without the wheel masses)
  double pitch_inertia = 0.0;  ///< J_v [kg m^2] about the centre (> 0 with several axles)
  std::vector<Axle> axles;
  MovingLoad motion;           ///< kind, mass and force unused
  bool unilateral = false;     ///< contact force must stay compressive: lift-off ends the run
};

/// Why a vehicle run ended.
enum class VehicleEnd {
  EndTime,  ///< t_end reached
  LiftOff   ///< unilateral contact: an axle's contact force on the beam reached zero
};

/// Solves, for q = (Y, z_1, [theta_1], z_2, ...), the linear time-varying system
///     M(t) q'' + C(t) q' + K(t) q = f(t)
///   M = blockdiag(Mb, M_v, J_v, ...) + sum_a m_w Phi_a Phi_a^T
///   C = blockdiag(C_beam, 0) + sum_a (c_a g_a g_a^T + 2 v m_w Phi_a Phi_a'^T)
///   K = blockdiag(Kb, 0) + sum_a (k_a g_a g_a^T - c_a v g_a Phi_a'^T + m_w (v^2 Phi_a Phi_a''^T + a Phi_a Phi_a'^T))
///   f = -(Pb, M_v g, 0, ...) - sum_a m_w g Phi_a
/// with Phi_a the modes at axle a (zero off the beam), g_a = (-Phi_a, 1 at z, e_a at theta):
/// the stretch of axle a's suspension is e_a = g_a . q (body displacement z + e_a theta minus
/// the beam's w under the axle; w = 0 off the beam) and its rate e_a' = g_a . q' - v w_x. These
/// are the spec's M_v z'' = -sum (k e + c e') - M_v g, J theta'' = -sum e_a (k e + c e') and the
/// beam's force F_a = k e + c e' - m_w (g + w_c'') at each axle. Dense solves of size
/// n + (vehicle unknowns): for a handful of vehicles and tens of modes.
/// RK4 or average-acceleration Newmark (trapezoidal in q'', exact for the linear system at each
/// step: one solve with M + h/2 C + h^2/4 K) at fixed steps, split where an axle enters or
/// leaves the beam. Unilateral contact: the step in which a contact force turns tensile is
/// shortened to the instant it reaches zero (secant on the step length); the run ends there.
class VehicleBeam : public time::SteppedModel {
 public:
  /// Throws std::invalid_argument for what it cannot integrate (no vehicle, an axle without
  /// stiffness, several axles without pitch inertia, non-positive sizes, BeamProblem::loads).
  VehicleBeam(BeamProblem beam, std::vector<Vehicle> vehicles);
  ~VehicleBeam();
  VehicleBeam(const VehicleBeam&) = delete;
  VehicleBeam& operator=(const VehicleBeam&) = delete;

  using Observer = std::function<void(const VehicleBeam&)>;
  /// Resets (the beam in static equilibrium under its weight and the vehicles' static axle loads,
  /// each body on its suspension in static equilibrium with e' = 0, or rest for
  /// InitialState::Rest) and integrates to t_end or lift-off; the observer sees t_start, every
  /// output_every grid steps, and the last state.
  void run(const Observer& observer = {});
  void reset();
  /// The steps of a run of the problem (time/time_integrator.hpp): fixed, split where an axle
  /// enters or leaves the beam.
  time::Schedule schedule() const;
  /// The integrator's model: a step of h, shortened to a lift-off in it (the run ends there).
  void step(double h) override;
  time::Attempt attempt(double h) override;  ///< no adaptive steps: throws std::logic_error
  std::vector<double> accept() override { return {}; }
  void reject() override {}
  double next_kink(double t) const override;
  bool ended() const override { return end_ != VehicleEnd::EndTime; }

  const BeamProblem& problem() const { return problem_; }
  const ModeSet& modes() const { return *modes_; }
  const GalerkinMatrices& matrices() const { return mats_; }
  const std::vector<Vehicle>& vehicles() const { return vehicles_; }
  double time() const override { return t_; }
  long steps_taken() const { return steps_; }
  VehicleEnd end_reason() const { return end_; }
  /// Modal coordinates Y [m], velocities Y' [m/s], accelerations Y'' [m/s^2] (current state).
  VecX Y() const;
  VecX Ydot() const;
  VecX Yddot() const;
  double deflection(double x) const;    ///< w(x) [m]
  double velocity(double x) const;      ///< w_t(x) [m/s]
  double acceleration(double x) const;  ///< w_tt(x) [m/s^2], from the modal accelerations
  /// Vehicle j's body: bounce z [m] (up, from the unloaded-spring level over undeformed ground),
  /// its velocity and acceleration, pitch theta [rad] (0 for one axle).
  double body_displacement(std::size_t j) const;
  double body_velocity(std::size_t j) const;
  double body_acceleration(std::size_t j) const;
  double body_pitch(std::size_t j) const;
  /// Position [m] of axle a of vehicle j along the beam (also off the beam).
  double axle_position(std::size_t j, std::size_t a) const;
  /// Contact force of the beam (or the ground, off the beam) on axle a of vehicle j [N], positive
  /// when compressive (it pushes the wheel up): -F_a = m_w (g + w_c'') - k e - c e'.
  double contact_force(std::size_t j, std::size_t a) const;
  /// Mechanical energy [J]: beam kinetic + elastic + self-weight potential, bodies' kinetic and
  /// gravity potential M_v g z, springs 1/2 k e^2 (no wheel masses: they need the path's terms).
  double mechanical_energy() const;
  /// Power dissipated by the suspensions' dampers and the beam's damping [W], and the power of
  /// the horizontal forces that keep the speeds prescribed, -sum_a F_a v w_x [W] (without wheel masses).
  double dissipation_power() const;
  double drive_power() const;

 private:
  struct Work;
  struct AxleRef {
    std::size_t vehicle, axle;
    Eigen::Index z, theta;  // rows of the body's unknowns (theta < 0: no pitch)
  };
  double reference_position(std::size_t j, double t) const;
  double reference_velocity(std::size_t j, double t) const;
  double reference_acceleration(std::size_t j, double t) const;
  void set_status(double ta, double tb);
  void assemble(double t, bool dynamic) const;
  void accelerations(double t, const VecX& q, const VecX& v, VecX& a) const;
  void rk4(double ta, double tb);
  void newmark(double ta, double tb);
  void advance(double ta, double tb);
  std::vector<double> events(double t0, double t1) const;
  double min_contact() const;
  /// The step (ta, tb] from (q0, v0), whose smallest unilateral contact force was f0, ended
  /// tensile: redo it up to the zero of that force; false if the redone full step is not tensile.
  bool locate_lift_off(double ta, double tb, const VecX& q0, const VecX& v0, double f0);
  Eigen::Index body_row(std::size_t j) const;
  void stretch(std::size_t i, double& e, double& ed, double& vwx) const;
  void refresh();

  BeamProblem problem_;
  std::vector<Vehicle> vehicles_;
  std::vector<AxleRef> axles_;
  std::shared_ptr<const ModeSet> modes_;
  GalerkinMatrices mats_;
  MatX Cb_;
  Eigen::Index n_ = 0, N_ = 0;
  std::unique_ptr<Work> w_;
  double t_ = 0.0;
  long steps_ = 0;
  VecX q_, v_, a_;
  std::vector<double> events_;  ///< where axles enter or leave the beam, t_start .. t_end
  VehicleEnd end_ = VehicleEnd::EndTime;
};

}  // namespace traverse::beam

#pragma once
// A mass that moves by itself along the rod (two-way coupling): sigma
// and its speed are unknowns of each time step, found by a partitioned iteration converged to
// the Newton tolerance (docs/rod.md "Coupled mass"). The rod's step inside it is solved by a
// CoupledRodSolve: the runs use solver::DistributedStepper (on any ranks, either path, any
// linear solver), the tests also an independent reference.
#include <array>
#include <functional>
#include <memory>

#include "traverse/rod/rod_kernels.hpp"

namespace traverse::rod {

/// A body on a spring and damper above the mass, acting along the fixed direction `up`: the
/// mass is then the wheel (unsprung, mass >= 0) of a sprung mass (docs/rod.md "Sprung mass").
/// The body moves with the wheel across `up`; along `up` its displacement z is an unknown:
///     M_v z'' = -k e - c e' + M_v g . up,     e = z - w,
/// w the wheel's displacement along up (the integral of up . p', p' its velocity). The rod
/// carries the wheel as a moving mass, the body as a moving mass across up only (rod_loads.hpp,
/// MovingMass::carried: no weight, no inertia along up) and the force (k e + c e') up at the
/// wheel.
struct Suspension {
  double body_mass = 0.0;  ///< M_v [kg]
  double stiffness = 0.0;  ///< k [N/m]
  double damping = 0.0;    ///< c [N s/m]
  Vec3 up = Vec3::UnitY();
};

/// The coupled mass (SI). Bilateral contact (a bead threaded on the rod); the app checks the
/// unilateral sign condition.
struct CoupledRodMass {
  double mass = 0.0;        ///< M [kg] (the wheel's with a suspension, may be 0 there)
  double drive = 0.0;       ///< D [N] along d3 (a robot's traction)
  double resistance = 0.0;  ///< c [N s/m]: the force -c sigma' d3 on the mass
  double friction = 0.0;    ///< Coulomb coefficient mu >= 0: tangential contact force -mu |C_perp| sign(sigma')
  /// false (air): the resistance acts on the mass alone, the rod's load is M (g - p'') - c sigma' d3
  /// and the loss c sigma' d3 . p' (docs/rod.md, "Coupled mass"). true: a force pair with the rod (wheels, a
  /// motor), the rod taking +c sigma' d3: its load is M (g - p''), the loss c sigma'^2 >= 0.
  bool resistance_through_rod = false;
  /// A prescribed path instead of the mass's own motion (a sprung mass rides at a given
  /// speed): sigma(t) and sigma'(t); then drive, resistance and friction must be 0, and the
  /// force along the rod that keeps the path is the drive (its work counts as drive work).
  std::function<double(double)> path_sigma{}, path_speed{};
  bool prescribed() const { return static_cast<bool>(path_sigma); }
  bool suspended = false;
  Suspension suspension{};
};

/// The mass's state at a time level.
struct CoupledMassState {
  double sigma = 0.0;       ///< position along the rod [m]
  double speed = 0.0;       ///< sigma' [m/s]
  double drive_work = 0.0;  ///< int D sigma' dt since the start [J]
  double dissipated = 0.0;  ///< work of the resistance since the start [J] (docs/rod.md)
  double friction_work = 0.0;  ///< int mu |C_perp| |sigma'| dt since the start [J]
  /// Set by the step that produced this state: sigma' reached 0 in it, at this fraction of the
  /// step, with the tangential demand at most mu |C_perp| (the mass sticks; the step kept the
  /// sliding friction to its end, so sigma' has overshot to the other sign). -1: no stop.
  double stick_fraction = -1.0;
  bool sticks() const { return stick_fraction >= 0.0; }
  // With a suspension: the body's displacement z and velocity z' along up, the wheel's w and
  // w' (z - w the spring's stretch), the force k e + c e' on the rod along up over the step that
  // produced this state, and the damper's dissipation int c e'^2 dt [J].
  double body = 0.0, body_speed = 0.0, wheel = 0.0, wheel_speed = 0.0, spring_force = 0.0, damper_work = 0.0;
  /// These six values in this order (a restart point keeps them).
  std::array<double, 6> suspension_values() const {
    return {body, body_speed, wheel, wheel_speed, spring_force, damper_work};
  }
  void set_suspension_values(const double* v) {
    body = v[0], body_speed = v[1], wheel = v[2], wheel_speed = v[3], spring_force = v[4], damper_work = v[5];
  }
};
/// The state of a sprung mass at rest in static equilibrium with its wheel at sigma (e =
/// M_v g . up / k, z' = w' = up . p', w = 0); m.sigma and m.speed set; `model` the rod's.
void start_suspension(const CoupledRodMass& mass, const RodModel& model, const RodState& state, CoupledMassState& m);
/// The body's acceleration z'' [m/s^2] at a state (the body's equation at that level).
double body_acceleration(const CoupledRodMass& mass, const Vec3& gravity, const CoupledMassState& m);

/// The rod's fields at sigma, interpolated linearly between the nodes of the cell holding it
/// (the transpose of the hat weights that distribute the mass's force, docs/rod.md).
struct RodPointKinematics {
  Vec3 U = Vec3::Zero();   ///< material velocity R^T u [m/s], fixed frame
  /// The centreline's tangent r_s (interpolated, not renormalised), fixed frame: d3 = R^T e3 for
  /// the inextensible rod, R^T v (the strain, RodProperties::strain) for one that strains.
  Vec3 d3 = Vec3::Zero();
};
/// A node's tangent r_s, fixed frame (RodPointKinematics::d3).
Vec3 node_tangent(const RodNode& node, const RodProperties& props);
RodPointKinematics point_kinematics(const RodState& state, double sigma, const RodProperties& props);
/// The mass's velocity p' = U + sigma' r_s at sigma [m/s], fixed frame.
Vec3 mass_velocity(const RodState& state, const CoupledMassState& m, const RodProperties& props);

/// The rod's time step with the coupled mass's path in it, for CoupledRodStepper. The model it
/// is made from holds the mass's loads (their path is read from the stepper while it solves).
/// Every call is collective when the solver is distributed; the states passed and returned
/// are whole (N + 1 nodes) and the same on every rank.
class CoupledRodSolve {
 public:
  virtual ~CoupledRodSolve() = default;
  /// Solves the step of dt from `old`; `again`: the same step once more after the mass's path
  /// changed, Newton starting from the last solution. Adds its Newton iterations; false when
  /// the solve fails.
  virtual bool solve(const RodState& old, double dt, bool again, int& newton_iterations) = 0;
  /// U and d3 at sigma of the last solution (point_kinematics of it).
  virtual RodPointKinematics point(double sigma) const = 0;
  /// The last solution.
  virtual RodState solution() const = 0;
};
/// Makes the rod solve from the model with the mass's loads.
using CoupledRodSolveFactory = std::function<std::unique_ptr<CoupledRodSolve>(RodModel)>;

struct CoupledStepReport {
  bool converged = false;
  int coupling_iterations = 0;  ///< partitioned iterations (each one rod Newton solve)
  int newton_iterations = 0;    ///< rod Newton iterations in all
  double last_change = 0.0;     ///< max(|d sigma| / ds, |d speed| dt / ds) of the last iteration
};

/// Advances rod + mass by one step. The rod's model must not contain the coupled mass: the
/// stepper adds it as a MovingMass (line-mass inertia and weight, rod_loads.hpp) whose path in
/// the step runs linearly from (sigma_old, t_old) to (sigma_new, t_new) with the speed linear
/// from v_old to v_new, plus (resistance through the air) -c v d3 as a point force. The mass's
/// tangential equation, discretised by the midpoint rule in momentum form,
///     M (p'_new - p'_old) . d3m = dt [M g . d3m + D - c (v_old + v_new) / 2],
///     sigma_new = sigma_old + dt (v_old + v_new) / 2,     d3m = unit(d3_old + d3_new)
/// (d3 and p' at sigma at each level) gives v_new given the rod's new level; the rod step is
/// solved given (sigma_new, v_new). The iteration between the two (Newton of the rod warm-
/// started from the previous iterate) stops when both change by less than tol * ds (or by less
/// than 1e3 tol * ds when the change no longer halves: the round-off floor of a heavy mass).
/// Coulomb friction adds the impulse J = -mu |C_perp| int sign(v(t)) dt (v linear in the step,
/// |C_perp| the normal part of the contact force of the step, from the latest iterate) to the
/// right-hand side: while sliding J = -mu |C_perp| dt sign(v_old); a step in which v crosses 0
/// sticks (stick_fraction) when the demand T = M g . d3m + D - M (U_new - U_old) . d3m / dt is at
/// most mu |C_perp|, and otherwise reverses (J switches sign at the crossing: v_new from a
/// quadratic, docs/rod.md "Coupled mass").
/// With a prescribed path (CoupledRodMass::path_sigma) the mass's equation is not solved: its
/// path is given. With a suspension the iteration is on the spring's force F over the step
/// (the rod takes F up at the wheel): given the rod's new level, the body's midpoint rule
///     M_v (z'_new - z'_old) = dt (M_v g . up - F),   F = k e_mid + c e'_mid,
/// with w' = up . p' at the wheel, gives F; it stops when the body's position changes by less
/// than tol * ds (Aitken-relaxed as the speed).
class CoupledRodStepper {
 public:
  /// `model` without the mass; `make` builds the rod solve from it with the mass's loads
  /// added (std::invalid_argument when empty).
  CoupledRodStepper(RodModel model, CoupledRodMass mass, const CoupledRodSolveFactory& make);
  ~CoupledRodStepper();

  /// One step of dt; on failure state and m are unchanged.
  CoupledStepReport step(RodState& state, CoupledMassState& m, double dt);

  /// The rod model with the mass's loads.
  const RodModel& model() const { return model_; }
  const CoupledRodMass& coupled_mass() const { return mass_; }
  double tol = 1e-12;
  int max_coupling_iterations = 60;

 private:
  struct Path;
  std::shared_ptr<Path> path_;
  CoupledRodMass mass_;
  RodModel model_;
  std::unique_ptr<CoupledRodSolve> solve_;
  /// The rod carries the point force -c v d3 (a resistance through the air), which reads the path's d3.
  bool air_resistance() const { return mass_.resistance > 0.0 && !mass_.resistance_through_rod; }
  struct Speed;
  Speed new_speed(const RodPointKinematics& ko, const RodPointKinematics& kn, double v_old, double v_iterate,
                  double dt) const;
};

}  // namespace traverse::rod

namespace traverse::rod {

/// The contact force of the rod on the mass over one step [N], fixed frame:
/// C = M (p'_new - p'_old) / dt - M g - (D - c v_mid) d3m - F up (the mass's momentum balance at
/// the step's midpoint; with a suspension F its spring_force, and the body's M_v (I - up up^T)
/// (p'_new - p'_old) / dt added), split along d3m = unit(d3_old + d3_new) into `tangential` (zero without
/// friction, to round-off: the mass's own equation) and `normal`; `up` = C . d2m,
/// d2m = unit(d2_old + d2_new) at sigma: a unilateral mass (on the +d2 side) lifts off where it
/// would turn negative.
struct CoupledContact {
  Vec3 normal = Vec3::Zero();
  double tangential = 0.0;
  double up = 0.0;
};
/// `model`: the rod's (its gravity and its strain).
CoupledContact step_contact(const RodState& old_state, const CoupledMassState& m_old, const RodState& new_state,
                            const CoupledMassState& m_new, const CoupledRodMass& mass, const RodModel& model, double dt);

/// Energies of rod + coupled mass [J] (docs/rod.md, "Coupled mass").
struct CoupledRodEnergies {
  double rod = 0.0;           ///< kinetic + elastic, discrete_energy (cell averages)
  /// mass_kinetic: 1/2 M |p'|^2, with a suspension plus the body's 1/2 M_v |p' across up|^2
  double rod_gravity = 0.0;   ///< sum over cells of ds rhoA (-g . r_cell_average)
  double mass_kinetic = 0.0;  ///< 1/2 M |p'|^2
  double mass_gravity = 0.0;  ///< -M g . r(sigma)
  /// A suspension's body: 1/2 M_v z'^2 + 1/2 k e^2 - M_v g . up z.
  double body = 0.0;
  double drive_work = 0.0, dissipated = 0.0, friction_work = 0.0, damper_work = 0.0;
  double mechanical() const { return rod + rod_gravity + mass_kinetic + mass_gravity + body; }
  /// mechanical - drive work + the losses (constant up to the discretisation).
  double balance() const { return mechanical() - drive_work + dissipated + friction_work + damper_work; }
};
/// `r` is the centreline at the nodes (centreline_in_space or advanced in time).
CoupledRodEnergies coupled_energies(const RodModel& model, const RodState& state, const std::vector<Vec3>& r,
                                    const CoupledMassState& m, const CoupledRodMass& mass);

}  // namespace traverse::rod

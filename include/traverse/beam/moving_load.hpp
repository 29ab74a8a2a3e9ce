#pragma once
// Moving point loads: a moving mass (with inertia) or a moving force (weight only).
#include <optional>
#include <vector>

namespace traverse::beam {

enum class LoadKind {
  Mass,  ///< point mass riding on the beam: inertia (incl. Coriolis/centrifugal) plus force
  Force  ///< moving force: only the vertical force, no inertia
};

enum class BeamEnd {
  Left,  ///< x = 0
  Right  ///< x = L
};

/// Description of one moving load (plain data).
///
/// Kinematics, with tau = t - entry_time >= 0 and x0 = start, or 0 (Left) or L (Right):
///     x(t) = x0 + direction * (speed * tau + acceleration * tau^2 / 2),
/// so the signed velocity and acceleration used in the equations are
/// v = direction * (speed + acceleration * tau), a = direction * acceleration.
/// The load acts on the beam while t >= entry_time and 0 <= x(t) <= L (at a switch-over
/// instant the status of the following step is used); elsewhere it contributes nothing.
/// A negative entry_time puts the load on the beam at the start of the simulation.
struct MovingLoad {
  LoadKind kind = LoadKind::Mass;
  double mass = 0.0;             ///< M [kg]: inertia (kind Mass) and default weight M g
  std::optional<double> force;   ///< vertical force on the beam [N], positive up;
                                 ///< unset: the weight, -M g
  BeamEnd entry = BeamEnd::Left; ///< end at which the load enters
  int direction = +1;            ///< +1 (towards +x) or -1; must point into the beam
  double speed = 0.0;            ///< entry speed v0 >= 0 [m/s] along `direction`
  double acceleration = 0.0;     ///< constant acceleration along `direction` [m/s^2]
  double entry_time = 0.0;       ///< [s]
  /// Position at entry_time [m], in [0, L]; unset: the entry end (x0 = 0 or L). The load is
  /// absent before entry_time.
  std::optional<double> start;

  /// Vertical force [N] (positive up) for gravity g.
  double vertical_force(double g) const { return force ? *force : -mass * g; }
  /// Inertial mass [kg]: mass for kind Mass, 0 for kind Force.
  double inertial_mass() const;
};

/// Kinematics of one load on a beam of length L.
class LoadKinematics {
 public:
  LoadKinematics(const MovingLoad& load, double length);
  double position(double t) const;      ///< x(t) [m] (also outside [0, L])
  double velocity(double t) const;      ///< signed v(t) [m/s]
  double acceleration() const { return acc_; }  ///< signed a [m/s^2]
  /// t >= entry_time and 0 <= x(t) <= L (inclusive; used for observation).
  bool on_beam(double t) const;
  /// Instants in (t0, t1) at which the load enters or leaves the beam, increasing.
  std::vector<double> events(double t0, double t1) const;

 private:
  double L_, x0_, dir_, v0_, acc_, t_entry_;
};

}  // namespace traverse::beam

#pragma once
// End conditions of the rod: 6 scalar rows per end (docs/rod.md, "Discretisation", the table
// of ends). Fixed-frame vectors are transformed to body components with R at the new level.
#include <functional>
#include <string>

#include "traverse/core/end_types.hpp"
#include "traverse/core/types.hpp"
#include "traverse/rod/rod_properties.hpp"

namespace traverse::rod {

/// A dynamic end condition: the scene's parameters (EndSpec: the type, its axes and force;
/// velocity and rotation_rate are read only through u_fixed and omega_fixed) plus the
/// prescribed motion as functions of time. Rows per type (end_condition.cpp, one table entry
/// per EndType holding the dynamic rows, the static rows and the conversion from EndSpec):
///   clamped     u = 0 (3), omega = 0 (3)
///   pinned      u = 0 (3), omega . (R b1) = omega . (R b2) = 0 (2), m . (R a) = 0 (1)
///   sliding     u . (R b1) = u . (R b2) = 0 (2), omega = 0 (3), n . (R e) = 0 (1)
///   free        n = 0 (3), m = K (kappa - kappa0) = 0 (3)
///   prescribed  u = R u_fixed(t) (3), omega = R omega_fixed(t) (3)
///   roller      pin about a sliding along e: u . (R b1_e) = u . (R b2_e) = 0 (2),
///               n . (R e) = axial_force (1), omega . (R b1_a) = omega . (R b2_a) = 0 (2),
///               m . (R a) = 0 (1)
/// `axis`: pin axis a (pinned, roller) or sliding axis e (sliding), fixed frame; normalised
/// internally; b1, b2 complete it to an orthonormal fixed triad (perpendicular_pair).
/// Roller: `slide_axis` e (should be perpendicular to the pin axis) and the contact force
/// component n . e held there [N] (at the right end the external force along e; at the
/// left end minus it).
struct EndCondition : EndSpec {
  using Type = EndType;
  /// Prescribed end velocity [m/s] and rotation rate [rad/s], fixed components, at time t [s].
  std::function<Vec3(double)> u_fixed;
  std::function<Vec3(double)> omega_fixed;

  static EndCondition make_clamped();
  static EndCondition make_pinned(const Vec3& pin_axis);
  static EndCondition make_sliding(const Vec3& slide_axis);
  static EndCondition make_free();
  /// Pinned about `pin_axis`, sliding along `slide_axis`, with n . e = `axial_force` [N].
  static EndCondition make_roller(const Vec3& pin_axis, const Vec3& slide_axis, double axial_force = 0.0);
  static EndCondition make_prescribed(std::function<Vec3(double)> u_fixed,
                                      std::function<Vec3(double)> omega_fixed);

  /// Number of scalar rows this condition contributes (always 6 for a valid condition).
  int num_rows() const;
  /// The condition of the static problem: a prescribed end starts from rest, so clamped.
  Type static_type() const;
  /// Whether the end point can move (its position is then integrated in time from its
  /// velocity): free, sliding, roller and prescribed ends.
  bool end_moves() const;
};

/// The dynamic end condition of a scene end (the conversion of its type's table entry; a
/// prescribed end's constant velocity and rotation rate become u_fixed and omega_fixed).
EndCondition end_condition(const EndSpec& spec);

/// Two unit vectors b1, b2 with (a/|a|, b1, b2) orthonormal; deterministic in a.
void perpendicular_pair(const Vec3& a, Vec3& b1, Vec3& b2);

/// The 6 rows of a condition at a node at time t [s] and their Jacobian with respect to the
/// node's y (12) at the new level, R the new-level orientation and G its sensitivity
/// (d(R v)/d omega_new = hat(R v) G, see NewLevelNode). With a bending and torsion viscosity
/// the moment is m = K (kappa - kappa0) + B_bt kappa_t: kappa_t the node's rate at the new level
/// and `rate` = d kappa_t / d kappa (1/(gt dt)); without one they are not read.
void end_condition_rows(const EndCondition& c, const RodProperties& props, double t,
                        const Vec12& y, const Mat3& R, const Mat3& G, Vec6& r,
                        Eigen::Matrix<double, 6, 12>& J, const Vec3& kappa_t = Vec3::Zero(), double rate = 0.0);

/// Result of validate_end_conditions.
struct EndConditionCheck {
  bool ok = false;
  std::string message;  ///< empty when ok, else what is wrong
};

/// Whether the pair gives a square, well-posed system: each end exactly 6 rows, axes
/// non-zero, prescribed functions present, and the 6 rows of each end independent (their
/// Jacobian with respect to that node's 12 unknowns has rank 6 at a straight rest state), and
/// each row fixes one member of a power-conjugate pair (u_k with n_k, omega_k with m_k), i.e.
/// the end's energy flux u . n + omega . m is prescribed.
EndConditionCheck validate_end_conditions(const EndCondition& left, const EndCondition& right);

}  // namespace traverse::rod

#pragma once
// External loads on the rod: gravity, fixed-frame distributed loads, moving point forces and
// moving masses (docs/rod.md, "Loads").
#include <array>
#include <functional>
#include <vector>

#include "traverse/core/types.hpp"

namespace traverse::rod {

/// A point force F(t) [N] (fixed components) at arclength sigma(t) [m]. Outside [0, L] it
/// is off the rod and contributes nothing.
struct PointForce {
  std::function<Vec3(double)> force_fixed;
  std::function<double(double)> sigma;
};

/// A point mass M [kg] moving along the rod with prescribed motion sigma(t) [m], speed
/// v(t) [m/s], acceleration a(t) [m/s^2]. It exerts M (g - p'') on the rod, p'' the
/// acceleration of the mass: in body components at sigma
/// p'' = u_t + omega x u + 2 v (omega x e3) + v^2 (kappa x e3) + a e3, the material
/// acceleration plus the convective terms 2 v d_s u + v^2 d_s d3 + a d3 of the spec in rod
/// form (d_s U = R^T (u_s + kappa x u) = R^T (omega x e3) by the inextensibility equation).
/// The kernels use the momentum form: M p'' is the rate of the mass's momentum M p',
/// p' = R^T (u + v e3) = U + v d3 (fixed frame), taken for a short line mass of the same total
/// mass on [sigma - ds, sigma + ds], whose impulse over each cell's space-time box enters that
/// cell (docs/rod.md, "Loads"). speed must be the derivative of sigma; accel is not
/// read by the kernels (the change of v carries it).
/// The weight M g is applied like a PointForce. With inertia = false only the weight acts
/// (a moving force).
struct MovingMass {
  double mass = 0.0;
  std::function<double(double)> sigma, speed, accel;
  bool inertia = true;
  /// The part of `mass` that is carried across `carried_axis` only (unit, fixed frame): it has
  /// no weight and no inertia along the axis (a sprung body, whose weight and motion along the
  /// axis reach the rod through its suspension: coupled_mass_rod.hpp). The inertia is then the
  /// tensor mass I - carried a a^T, the weight (mass - carried) g.
  double carried = 0.0;
  Vec3 carried_axis = Vec3::UnitY();
};

/// Everything applied to the rod besides the end conditions.
struct RodLoads {
  Vec3 gravity = Vec3::Zero();  ///< acceleration of gravity, fixed frame [m/s^2] (e.g. (0,-9.8,0))
  std::function<Vec3(double s, double t)> f_fixed;  ///< extra distributed force [N/m], optional
  std::function<Vec3(double s, double t)> l_fixed;  ///< distributed couple [N], optional
  std::vector<PointForce> point_forces;
  std::vector<MovingMass> masses;

  /// Whether gravity acts (some component not exactly zero). Without it the kernels compute
  /// no gravity terms (R g, M R g and their frame sensitivity are skipped, not added as zeros).
  bool has_gravity() const { return gravity.x() != 0.0 || gravity.y() != 0.0 || gravity.z() != 0.0; }
  /// Whether any fixed-frame distributed load acts: gravity, f_fixed or l_fixed. Only then
  /// does node_flux form the body-frame loads R f, R l and their frame sensitivity.
  bool has_frame_loads() const { return has_gravity() || static_cast<bool>(f_fixed) || static_cast<bool>(l_fixed); }
};

/// Nodal weights of a point load at sigma on nodes 0..N at spacing ds (at most two nodes).
struct PointLoadWeights {
  int count = 0;                   ///< 0 (off the rod), 1 or 2
  std::array<int, 2> node{{0, 0}};
  std::array<double, 2> weight{{0.0, 0.0}};
};

/// Weights w such that a nodal load value w_k F / ds at the nodes k of the cell holding
/// sigma gives, through the scheme's spatial cell average (1 - beta) f(j) + beta f(j-1)
/// summed over all cells with factor ds, exactly F. Each node's total spatial weight is
/// E_j = 1 (interior), E_0 = beta, E_N = 1 - beta; with xi = (sigma - s_{k-1}) / ds in the
/// cell (k-1, k): w_{k-1} = (1 - xi) / E_{k-1}, w_k = xi / E_k (linear interpolation
/// corrected at the end nodes; a node with E = 0 takes no load and its neighbour takes all).
/// beta is bs (point forces and the weights of moving masses).
PointLoadWeights point_load_weights(double sigma, int num_cells, double ds, double beta);

/// The part of a moving mass's path during one time step that lies in cell `cell` (nodes
/// cell - 1, cell): the path is sigma(tau) = sigma_old + tau (sigma_new - sigma_old),
/// tau = (t - t_old) / dt in [0, 1], clipped to the rod [0, L], L = num_cells ds. The
/// segment runs from (s_a, tau_a) to (s_b, tau_b), tau_a < tau_b, both points on the
/// boundary of the space-time box of the cell and the step (or the path's ends). A mass at
/// rest on a node belongs to the cell on its right (cell N at s = L), as for
/// point_load_weights. Segments of all cells tile the on-rod path, sharing their end points.
struct MassPathSegment {
  bool valid = false;  ///< whether the path spends time in the cell
  double tau_a = 0.0, tau_b = 0.0;
  double s_a = 0.0, s_b = 0.0;  ///< [m]
};
MassPathSegment mass_path_in_cell(double sigma_old, double sigma_new, int cell, int num_cells, double ds);

/// The part [l, r] of cell `cell` (nodes cell - 1, cell) covered by a moving mass's line
/// mass at sigma: the kernels spread the mass's inertia uniformly over [sigma - ds,
/// sigma + ds] (docs/rod.md, "Loads"). False if the cell gets none, or if the mass is
/// off the rod (the same test as point_load_weights); the part beyond the rod's ends is
/// not in any cell.
bool line_mass_part(double sigma, int cell, int num_cells, double ds, double& l, double& r);

}  // namespace traverse::rod

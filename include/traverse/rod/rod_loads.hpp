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

/// How a point load at sigma is shared by nodes 0..N at spacing ds: the hat functions of
/// the cell (k-1, k) holding it, xi = (sigma - s_{k-1}) / ds, 1 - xi at node k-1 and xi at
/// node k. An interior node's share w F enters the cells' force rows as the nodal load
/// density w F / ds (the scheme's spatial average splits it between the node's two cells,
/// so the rows add up to w F). An end node's share is not a load density but a force on the
/// end itself: the end's rows take it (a free, sliding or roller end carries it in its force
/// rows, a support's reaction absorbs it), as a load at s = 0 or L acts on the continuum.
/// Sharing it into the end cell instead would apply it at the cell's centre, an error of
/// order ds in the moment the rod carries.
struct PointLoadWeights {
  int count = 0;                   ///< interior nodes with a share: 0, 1 or 2
  std::array<int, 2> node{{0, 0}};
  std::array<double, 2> weight{{0.0, 0.0}};
  bool on_rod = false;             ///< sigma in [0, L] (a finite position)
  double left = 0.0, right = 0.0;  ///< the shares of end nodes 0 and N
  int last = 0;                    ///< N, the right end's node
  /// The share of node `node` (0..N), ends included.
  double share(int node) const { return node == 0 ? left : node == last ? right : at(node); }
  /// The share of interior node `node` (0 for the others).
  double at(int node) const {
    double s = 0.0;
    for (int k = 0; k < count; ++k)
      if (this->node[static_cast<size_t>(k)] == node) s += weight[static_cast<size_t>(k)];
    return s;
  }
};

/// The shares of a point load at sigma (PointLoadWeights); none off the rod.
PointLoadWeights point_load_weights(double sigma, int num_cells, double ds);

/// d(share)/d sigma [1/m] of `node` (0..N) for a load at sigma: -1/ds at node k-1 and 1/ds at
/// node k of the cell holding it; at an interior node, where the shares kink, the mean of its
/// two cells' slopes (what a central difference gives).
double point_load_slope(double sigma, int node, int num_cells, double ds);

/// The part of a moving mass's path during one time step that lies in cell `cell` (nodes
/// cell - 1, cell): the path is sigma(tau) = sigma_old + tau (sigma_new - sigma_old),
/// tau = (t - t_old) / dt in [0, 1], clipped to the rod [0, L], L = num_cells ds. The
/// segment runs from (s_a, tau_a) to (s_b, tau_b), tau_a < tau_b, both points on the
/// boundary of the space-time box of the cell and the step (or the path's ends). A mass at
/// rest on a node belongs to the cell on its right (cell N at s = L). Segments of all cells tile the on-rod path, sharing their end points.
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

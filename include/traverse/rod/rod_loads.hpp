#pragma once
// External loads on the rod: gravity, fixed-frame distributed loads, moving point forces and
// moving masses (physics spec section 2, "Moving point load and moving mass").
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
/// v(t) [m/s], acceleration a(t) [m/s^2]. It exerts M (g - a_mass) on the rod, with (body
/// components at sigma) a_mass = u_t + omega x u + 2 v (omega x e3) + v^2 (kappa x e3) + a e3:
/// the material acceleration plus the convective terms 2 v d_s u + v^2 d_s d3 + a d3 of the
/// spec in rod form, where d_s U = R^T (u_s + kappa x u) = R^T (omega x e3) by the
/// inextensibility equation. With inertia = false only the weight M g acts (moving force).
struct MovingMass {
  double mass = 0.0;
  std::function<double(double)> sigma, speed, accel;
  bool inertia = true;
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
/// beta is bs for forces and as for the mass's inertia.
PointLoadWeights point_load_weights(double sigma, int num_cells, double ds, double beta);

}  // namespace traverse::rod

#pragma once
// Section and material data of a uniform Cosserat rod (docs/rod.md).
#include "traverse/core/types.hpp"

namespace traverse::rod {

/// Uniform section. All quantities SI.
struct RodProperties {
  double rhoA = 0.0;            ///< mass per unit length rho A [kg/m]
  Vec3 rhoI = Vec3::Zero();     ///< rotary inertia diagonal rho (I1, I2, J) [kg m]
  Vec3 K = Vec3::Zero();        ///< stiffness diagonal (E I1, E I2, G J) [N m^2]
  Vec3 kappa0 = Vec3::Zero();   ///< intrinsic curvature, body components [1/m]

  /// Contact moment m = K (kappa - kappa0), body components [N m] (the linear constitutive law).
  Vec3 moment(const Vec3& kappa) const { return K.cwiseProduct(kappa - kappa0); }
  /// The smaller bending stiffness min(E I1, E I2) [N m^2].
  double bending_stiffness() const { return K.head<2>().minCoeff(); }
  /// Euler buckling load pi^2 EI / L^2 of a rod of length L [m] pinned at both ends [N].
  double euler_load(double L) const;
  /// The bending rate scale EI / (rhoA L^4) [1/s^2]: omega^2 of the bending modes of a rod of
  /// length L [m] are multiples of it.
  double bending_rate(double L) const;

  /// Solid circular section of radius r [m], Young's modulus E [Pa], Poisson ratio nu,
  /// density rho [kg/m^3]: A = pi r^2, I1 = I2 = pi r^4 / 4, J = pi r^4 / 2, G = E/(2(1+nu)).
  static RodProperties circular(double radius, double E, double nu, double rho);

  /// The rod of the reference scenes: r = 0.005 m, E = 2.5e8 Pa, nu = 0.25, rho = 1500 kg/m^3.
  static RodProperties scene_rod();
};

}  // namespace traverse::rod

#pragma once
// Section and material data of a uniform Cosserat rod (docs/rod.md).
#include "traverse/core/types.hpp"

namespace traverse::rod {

/// Which strains of the centreline the rod admits (docs/rod.md, "Extensible and shearable
/// rods"): none (the strain v = dr/ds in body components is e3), the stretch only
/// (v = e3 (1 + n3 / (E A))), or stretch and shear (v = e3 + C n, the special Cosserat rod).
enum class RodStrain { inextensible, extensible, shearable };

/// Uniform section. All quantities SI, per unit reference (unstretched) length.
struct RodProperties {
  double rhoA = 0.0;            ///< mass per unit length rho A [kg/m]
  Vec3 rhoI = Vec3::Zero();     ///< rotary inertia diagonal rho (I1, I2, J) [kg m]
  Vec3 K = Vec3::Zero();        ///< stiffness diagonal (E I1, E I2, G J) [N m^2]
  Vec3 kappa0 = Vec3::Zero();   ///< intrinsic curvature, body components [1/m]
  /// Compliance diagonal C of the strain, v = e3 + C n_e with n_e the elastic contact force
  /// [1/N]: zero for the inextensible rod, (0, 0, 1/(E A)) extensible, (1/(k G A), 1/(k G A),
  /// 1/(E A)) shearable. A zero entry is a direction the rod does not strain in (its force
  /// component is a multiplier); C -> 0 is the inextensible rod.
  Vec3 C = Vec3::Zero();
  /// Kelvin-Voigt viscosities of the strains (shear, shear, axial) [N s]: n = n_e + B_se v_t
  /// (only where C is not zero).
  Vec3 B_se = Vec3::Zero();
  /// Kelvin-Voigt viscosities of bending and torsion [N m^2 s]: m = K (kappa - kappa0) + B_bt kappa_t.
  Vec3 B_bt = Vec3::Zero();

  /// Contact moment m = K (kappa - kappa0), body components [N m] (the linear constitutive law).
  Vec3 moment(const Vec3& kappa) const { return K.cwiseProduct(kappa - kappa0); }
  /// Whether the centreline strains (some entry of C is not zero).
  bool compliant() const { return (C.array() != 0.0).any(); }
  /// Whether a Kelvin-Voigt viscosity acts.
  bool damped() const { return (B_se.cwiseProduct(C).array() != 0.0).any() || (B_bt.array() != 0.0).any(); }
  /// The retardation times tau = C B_se of the strains [s] (zero where the rod does not strain).
  Vec3 retardation() const { return C.cwiseProduct(B_se); }
  /// The strain v = e3 + C n - tau v_t of a node whose contact force is n [N] and strain rate
  /// v_t [1/s] (n = C^-1 (v - e3) + B_se v_t solved for v).
  Vec3 strain(const Vec3& n, const Vec3& vt) const {
    return Vec3::UnitZ() + C.cwiseProduct(n) - retardation().cwiseProduct(vt);
  }
  /// The model C describes (the entries of C that are not zero).
  RodStrain strain_kind() const;
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

  /// The compliance of a rod of axial stiffness E A [N] and shear stiffness k G A [N] for a
  /// model: zero (inextensible), (0, 0, 1/EA) (extensible), (1/kGA, 1/kGA, 1/EA) (shearable).
  static Vec3 compliance(RodStrain model, double EA, double kGA);
};

/// The Kelvin-Voigt viscosity that gives a mode of circular frequency w [rad/s] the damping
/// ratio zeta, for a stiffness S of the strain the mode stretches (E A, k G A, E I or G J):
/// B = 2 zeta S / w [S s]. Viscosities picked so for every stiffness make the damping
/// proportional to the stiffness: each mode keeps its shape and has the damping ratio
/// zeta w_mode / w, so the mode at w decays as exp(-zeta w t) (docs/rod.md, "Material damping").
double kelvin_voigt_viscosity(double zeta, double w, double S);

}  // namespace traverse::rod

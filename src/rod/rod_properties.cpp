#include "traverse/rod/rod_properties.hpp"

#include <cmath>
#include <stdexcept>

namespace traverse::rod {

double RodProperties::euler_load(double L) const { return constants::pi * constants::pi * bending_stiffness() / (L * L); }

double RodProperties::bending_rate(double L) const { return bending_stiffness() / (rhoA * std::pow(L, 4)); }

RodProperties RodProperties::circular(double radius, double E, double nu, double rho) {
  const double A = constants::pi * radius * radius;
  const double I = constants::pi * radius * radius * radius * radius / 4.0;
  const double J = 2.0 * I;
  const double G = E / (2.0 * (1.0 + nu));
  RodProperties p;
  p.rhoA = rho * A;
  p.rhoI = Vec3(rho * I, rho * I, rho * J);
  p.K = Vec3(E * I, E * I, G * J);
  p.kappa0.setZero();
  return p;
}

RodStrain RodProperties::strain_kind() const {
  if (!compliant()) return RodStrain::inextensible;
  return C.x() == 0.0 && C.y() == 0.0 ? RodStrain::extensible : RodStrain::shearable;
}

Vec3 RodProperties::compliance(RodStrain model, double EA, double kGA) {
  switch (model) {
    case RodStrain::inextensible: return Vec3::Zero();
    case RodStrain::extensible: return Vec3(0.0, 0.0, 1.0 / EA);
    case RodStrain::shearable: return Vec3(1.0 / kGA, 1.0 / kGA, 1.0 / EA);
    default: throw std::logic_error("RodProperties::compliance: unknown model");
  }
}

double kelvin_voigt_viscosity(double zeta, double w, double S) { return 2.0 * zeta * S / w; }

RodProperties RodProperties::scene_rod() { return circular(0.005, 2.5e8, 0.25, 1500.0); }

}  // namespace traverse::rod

#include "traverse/rod/rod_properties.hpp"

#include <cmath>

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

RodProperties RodProperties::scene_rod() { return circular(0.005, 2.5e8, 0.25, 1500.0); }

}  // namespace traverse::rod

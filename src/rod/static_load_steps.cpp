#include "traverse/rod/static_load_steps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace traverse::rod {

std::array<double, 4> static_update_scales(double length, double fscale) { return {length, 1.0, 1.0 / length, fscale}; }

double scaled_update(int index, double d, const std::array<double, 4>& scales, const Vec3& compliance) {
  const double s = std::abs(d) / scales[static_cast<size_t>(index / 3)];
  if (index < svar::n) return s;
  const double C = compliance(index - svar::n);
  return C != 0.0 ? std::min(s, std::abs(C * d)) : s;
}

StaticModel scaled_loads(const StaticModel& m, double factor) {
  StaticModel s = m;
  s.gravity *= factor;
  for (auto& p : s.point_forces) p.force *= factor;
  for (StaticEnd* e : {&s.left, &s.right}) {
    e->axial_force *= factor;
    e->end_force *= factor;
  }
  return s;
}

double static_force_scale(const StaticModel& m) {
  const double EI = m.props.K.head<2>().maxCoeff();
  double fscale = EI / (m.length * m.length) + m.props.rhoA * m.gravity.norm() * m.length;
  for (const auto& p : m.point_forces) fscale = std::max(fscale, p.force.norm());
  for (const StaticEnd* e : {&m.left, &m.right}) fscale = std::max({fscale, std::abs(e->axial_force), e->end_force.norm()});
  return fscale;
}

StaticReport solve_with_load_steps(const StaticModel& m, const StaticNewton& newton, const StaticTolerances& tol) {
  StaticReport total;
  double lambda = 0.0, step = 1.0, tried = 0.0;
  while (lambda < 1.0) {
    if (total.load_steps + 1 > tol.max_load_steps || step < 1e-8) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "load stepping stalled at load factor %.6g of 1 (%d load steps accepted; the last "
                    "increment tried was %.3g)", lambda, total.load_steps, tried);
      total.message = buf;
      total.load_factor = lambda;
      return total;
    }
    const double next = std::min(1.0, lambda + step);
    tried = next - lambda;
    const StaticReport r = newton(scaled_loads(m, next));  // a failed solve restores the state
    total.iterations += r.iterations;
    if (r.converged) {
      lambda = next;
      ++total.load_steps;
      total.residual_norm = r.residual_norm;
      total.load_scale = r.load_scale;
      if (r.iterations <= 6) step *= 2.0;
    } else {
      total.failed_factor = next;
      total.failed_residual = r.residual_norm;
      total.failed_scale = r.load_scale;
      total.failed_reason = r.message;
      step *= 0.5;
    }
  }
  total.load_factor = 1.0;
  total.converged = true;
  return total;
}

}  // namespace traverse::rod

#include "traverse/rod/static_solver.hpp"

#include "traverse/core/stop_request.hpp"

#include <cmath>
#include <cstdio>

namespace traverse::rod {

double static_update_node(StaticNode& node, const Vec12& d, const StaticModel& m, double fscale) {
  node.x += d;
  const double length = m.length;
  double dn = d.segment<3>(svar::n).cwiseAbs().maxCoeff() / fscale;
  if (m.props.compliant()) {
    dn = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double f = std::abs(d(svar::n + i)) / fscale, C = m.props.C(i);
      dn = std::max(dn, C != 0.0 ? std::min(f, std::abs(C * d(svar::n + i))) : f);
    }
  }
  const double s = std::max({d.segment<3>(svar::r).cwiseAbs().maxCoeff() / length,
                             d.segment<3>(svar::theta).cwiseAbs().maxCoeff(),
                             d.segment<3>(svar::kappa).cwiseAbs().maxCoeff() * length, dn});
  if (node.x.segment<3>(svar::theta).norm() > 1.0) node.rebase();  // keep increments small
  return s;
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

StaticReport StaticSolver::newton(const StaticModel& m, StaticNewtonSystem& sys) const {
  StaticReport rep;
  sys.start();
  // Scales: forces by the largest of the weight and the end and point forces, or EI/L^2.
  const double fscale = static_force_scale(m);
  for (int it = 0; it < max_iterations; ++it) {
    throw_if_stop_requested("the static solve (Newton iteration " + std::to_string(it + 1) + ")");
    if (!sys.assemble(m)) break;
    if (!sys.factorize(rep.message)) break;
    ++rep.iterations;
    const double step_max = sys.update(m, fscale);
    if (!std::isfinite(step_max)) break;
    if (step_max <= rtol) {
      rep.residual_norm = sys.residual_max(m);
      if (rep.residual_norm <= ftol * fscale) {
        rep.converged = true;
        rep.load_scale = fscale;
        sys.rebase_all();
        return rep;
      }
    }
  }
  // The residual where Newton stopped (not the one before its last update).
  rep.residual_norm = sys.residual_max(m);
  rep.load_scale = fscale;
  if (rep.message.empty()) {
    char buf[200];
    if (!std::isfinite(rep.residual_norm))
      std::snprintf(buf, sizeof buf, "Newton diverged (the residual is not finite)");
    else if (rep.residual_norm <= ftol * fscale)
      std::snprintf(buf, sizeof buf, "Newton did not converge in %d iterations: the residual test held, but the "
                    "scaled update stayed above %.3g (rounding)", max_iterations, rtol);
    else
      std::snprintf(buf, sizeof buf, "Newton did not converge in %d iterations", max_iterations);
    rep.message = buf;
  }
  sys.restore();
  return rep;
}

StaticReport StaticSolver::solve_with_load_steps(const StaticModel& m, StaticNewtonSystem& sys) const {
  StaticReport total;
  double lambda = 0.0, step = 1.0, tried = 0.0;
  while (lambda < 1.0) {
    if (total.load_steps + 1 > max_load_steps || step < 1e-8) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "load stepping stalled at load factor %.6g of 1 (%d load steps accepted; the last "
                    "increment tried was %.3g)", lambda, total.load_steps, tried);
      total.message = buf;
      total.load_factor = lambda;
      return total;
    }
    const double next = std::min(1.0, lambda + step);
    tried = next - lambda;
    const StaticReport r = newton(scaled_loads(m, next), sys);  // a failed solve restores the state
    total.iterations += r.iterations;
    if (r.converged) {
      lambda = next;
      ++total.load_steps;
      total.residual_norm = r.residual_norm;
      total.load_scale = r.load_scale;
      if (r.iterations <= 4) step *= 2.0;
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

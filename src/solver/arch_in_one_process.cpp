// The arch formed in one process (arch_in_one_process.hpp).
#include "traverse/solver/arch_in_one_process.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "traverse/core/sparse_lu.hpp"
#include "traverse/rod/static_solver.hpp"

namespace traverse::solver {

namespace {

using rod::StaticNode;
using rod::StaticParameter;
using SpMat = Eigen::SparseMatrix<double>;

std::string format(const char* f, double a, double b = 0.0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, f, a, b);
  return buf;
}

/// The straight rod in equilibrium under the compressive end load P: n = -P k on every node
/// (body and fixed frames agree on the straight rod).
std::vector<StaticNode> straight_under(const rod::StaticModel& m, double P) {
  std::vector<StaticNode> nodes = rod::straight_static_state(m);
  for (StaticNode& n : nodes) n.x(rod::svar::n + 2) = -P;
  return nodes;
}

/// The Jacobian of the straight rod under the end load P (the in-plane one when `solver` has a
/// planar split), factorised.
struct StraightJacobian {
  SparseLUSolver lu;
  bool ok = false;
  StraightJacobian(const rod::StaticSolver& solver, const rod::StaticProblem& pr, double P) {
    rod::StaticProblem at = pr;
    at.value(StaticParameter::end_load) = P;
    const rod::StaticModel m = at.model();
    VecX r;
    SpMat J;
    solver.residual_and_jacobian(m, straight_under(m, P), r, J);
    ok = lu.factorize(J);
  }
};

/// det J(P) relative to det J(P0) (= exp(log|det J(P)| - log0) with its sign), or 0 when the
/// factorisation failed (singular to working precision: P is the pitchfork).
double relative_determinant(const rod::StaticSolver& solver, const rod::StaticProblem& pr, double P, double log0) {
  StraightJacobian J(solver, pr, P);
  if (!J.ok) return 0.0;
  return J.lu.sign_determinant() * std::exp(J.lu.log_abs_determinant() - log0);
}

}  // namespace

OneProcessArch form_arch_in_one_process(const rod::RodProperties& props, int num_cells, double length, double dz,
                                        double gravity) {
  OneProcessArch out;
  const double L = length;
  if (props.kappa0.squaredNorm() > 0.0) {
    out.message = "the rod has an intrinsic curvature (the arch is formed from a straight rod)";
    return out;
  }
  const rod::StaticProblem pr = rod::pinned_roller_problem(props, num_cells, L, gravity);
  const double PE = props.euler_load(L);  // the continuum's, to scale the search
  // The in-plane systems (6 unknowns per node) where the problems split about the plane of j
  // and k, as the scene's do: the pitchfork searched is then the first in-plane one.
  rod::StaticSolver straight, solver;
  straight.planar = rod::static_planar_split(pr.model());
  rod::StaticProblem arch = rod::pinned_arch_problem(pr, L);
  solver.planar = rod::static_planar_split(arch.model());
  // Where each of a node's 12 unknowns sits in the straight rod's system (-1: not in it).
  const int q = straight.planar ? 6 : 12;
  std::array<int, 12> at{};
  for (int c = 0; c < 12; ++c) at[static_cast<size_t>(c)] = straight.planar ? -1 : c;
  if (straight.planar) {
    const std::array<int, 6> S = rod::in_plane_components(straight.planar->axis);
    for (int c = 0; c < 6; ++c) at[static_cast<size_t>(S[static_cast<size_t>(c)])] = c;
  }

  // 1. The pitchfork: the first sign change of det J(P) on the straight branch, bracketed in
  // steps of PE / 5 (as the continuation's first steps), then Illinois' regula falsi.
  StraightJacobian J0(straight, pr, 0.0);
  if (!J0.ok) {
    out.message = "the straight rod's Jacobian is singular without load";
    return out;
  }
  const double log0 = J0.lu.log_abs_determinant();
  double a = 0.0, fa = J0.lu.sign_determinant(), b = 0.0, fb = fa;
  for (int k = 1; k <= 8 && fa * fb > 0.0; ++k) {
    a = b;
    fa = fb;
    b = 0.2 * PE * k;
    fb = relative_determinant(straight, pr, b, log0);
  }
  if (fa * fb > 0.0) {
    out.message = format("no Euler pitchfork below %.6g N on the straight rod", b);
    return out;
  }
  double P = b;
  int side = 0;
  for (int it = 0; it < 200 && fb != 0.0 && std::abs(b - a) > 1e-13 * PE; ++it) {
    P = (a * fb - b * fa) / (fb - fa);
    const double fp = relative_determinant(straight, pr, P, log0);
    if (fp == 0.0) break;
    if (fp * fb < 0.0) {
      a = b;
      fa = fb;
      side = 0;
    } else if (++side >= 2) {
      fa *= 0.5;  // Illinois: the end kept twice weighs half
    }
    b = P;
    fb = fp;
  }
  out.euler_load = P;

  // 2. The buckling mode: inverse iteration with J just below the pitchfork; up: +j at midspan.
  StraightJacobian Jm(straight, pr, P * (1.0 - 1e-9));
  if (!Jm.ok) {
    out.message = format("the straight rod's Jacobian at %.6g N is singular", P);
    return out;
  }
  const Eigen::Index n_unknowns = q * static_cast<Eigen::Index>(num_cells + 1);
  VecX v = VecX::Ones(n_unknowns);
  for (int it = 0; it < 3; ++it) {
    v = Jm.lu.solve(v);
    const double scale = v.cwiseAbs().maxCoeff();
    if (!(scale > 0.0) || !std::isfinite(scale)) {
      out.message = "the inverse iteration for the buckling mode failed";
      return out;
    }
    v /= scale;
  }
  const int ry = at[rod::svar::r + 1];
  if (ry < 0) {
    out.message = "the rod's plane is not that of j and k";
    return out;
  }
  const double mid_y = v(q * static_cast<Eigen::Index>(num_cells / 2) + ry);
  double r_max = 0.0;
  for (Eigen::Index j = 0; j <= num_cells; ++j)
    for (int c = rod::svar::r; c < rod::svar::r + 3; ++c)
      if (at[static_cast<size_t>(c)] >= 0) r_max = std::max(r_max, std::abs(v(q * j + at[static_cast<size_t>(c)])));
  if (!(std::abs(mid_y) >= 0.5 * r_max)) {
    out.message = format("the first buckling mode (at %.6g N) does not lift the midpoint along j (it buckles out of "
                         "the plane of j and k)", P);
    return out;
  }
  v /= mid_y;  // midpoint deflection +1 (upwards)

  // 3. The ends pinned and moved together, d = L - delta from delta0 to L - dz. The first
  // guess: the elastica's small deflection, amplitude (2 L / pi) sqrt(delta / L) at midspan.
  const double total = L - dz;
  if (!(total > 0.0)) {
    out.message = format("end_to_end %.6g m is not below the rod's length %.6g m", dz, L);
    return out;
  }
  double delta = std::min(0.005 * L, total);
  std::vector<StaticNode> state = straight_under(pr.model(), P);
  const double amplitude = 2.0 * L / std::acos(-1.0) * std::sqrt(delta / L);
  for (size_t j = 0; j < state.size(); ++j)
    for (int c = 0; c < 12; ++c)
      if (at[static_cast<size_t>(c)] >= 0)
        state[j].x(c) += amplitude * v(q * static_cast<Eigen::Index>(j) + at[static_cast<size_t>(c)]);
  double done = 0.0, step = delta;
  while (done < total) {
    const double next = std::min(total, done + step);
    arch.value(StaticParameter::end_position) = L - next;
    std::vector<StaticNode> trial = state;
    const rod::StaticReport r = solver.newton(arch.model(), trial);
    out.newton_iterations += r.iterations;
    if (!r.converged) {
      if (done == 0.0 && step <= 1e-6 * L) {
        out.message = "the first buckled state did not converge: " + r.message;
        return out;
      }
      step *= 0.5;
      if (step < 1e-9 * L) {
        out.message = format("moving the ends together stalled at %.9g m apart: ", L - done) + r.message;
        return out;
      }
      continue;
    }
    state = std::move(trial);
    done = next;
    ++out.displacement_steps;
    step = r.iterations <= 6 ? std::min(2.0 * step, 0.2 * L) : step;
  }
  const double mid_height = rod::position_at(arch.model(), state, 0.5 * L).y();
  if (!(mid_height > 0.0)) {
    out.message = format("the formed arch's midpoint is at y = %.6g m, not above the ends", mid_height);
    return out;
  }
  out.forming_load = rod::probe_end_compression(Vec3::UnitZ()).eval(arch.model(), state);

  // 4. Gravity from 0 to g.
  arch.value(StaticParameter::gravity_factor) = 1.0;
  const rod::StaticReport g = solver.solve_with_load_steps(arch.model(), state);
  out.newton_iterations += g.iterations;
  if (!g.converged) {
    out.message = "raising gravity failed: " + g.message;
    return out;
  }
  out.problem = arch;
  out.state = std::move(state);
  out.ok = true;
  return out;
}

}  // namespace traverse::solver

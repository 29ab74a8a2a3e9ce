#include "traverse/rod/static_solver.hpp"

#include <Eigen/SparseLU>

#include <cmath>
#include <cstdio>

namespace traverse::rod {

namespace {

void scatter(const LocalBlock& b, VecX& r, std::vector<Eigen::Triplet<double>>* trip) {
  r.segment(b.row, b.residual.size()) += b.residual;
  if (!trip) return;
  for (size_t k = 0; k < b.cols.size(); ++k)
    for (Eigen::Index i = 0; i < b.jac[k].rows(); ++i)
      for (Eigen::Index c = 0; c < b.jac[k].cols(); ++c)
        if (b.jac[k](i, c) != 0.0) trip->emplace_back(b.row + i, b.cols[k] + c, b.jac[k](i, c));
}

void assemble(const StaticModel& m, const std::vector<StaticNode>& nodes, VecX& r,
              std::vector<Eigen::Triplet<double>>* trip) {
  r = VecX::Zero(m.num_unknowns());
  scatter(static_left_block(m, nodes.front()), r, trip);
  for (int j = 1; j <= m.num_cells; ++j)
    scatter(static_cell_block(m, j, nodes[static_cast<size_t>(j - 1)], nodes[static_cast<size_t>(j)]), r, trip);
  scatter(static_right_block(m, nodes.back()), r, trip);
}

}  // namespace

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

VecX StaticSolver::residual(const StaticModel& m, const std::vector<StaticNode>& nodes) const {
  VecX r;
  assemble(m, nodes, r, nullptr);
  return r;
}

void StaticSolver::residual_and_jacobian(const StaticModel& m, const std::vector<StaticNode>& nodes, VecX& r,
                                         Eigen::SparseMatrix<double>& J) const {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<size_t>(m.num_unknowns()) * 30);
  assemble(m, nodes, r, &trip);
  J.resize(m.num_unknowns(), m.num_unknowns());
  J.setFromTriplets(trip.begin(), trip.end());
}

StaticReport StaticSolver::newton(const StaticModel& m, std::vector<StaticNode>& nodes) const {
  StaticReport rep;
  const std::vector<StaticNode> start = nodes;
  // Scales: forces by the largest of the weight and the end and point forces, or EI/L^2.
  const double EI = m.props.K.head<2>().maxCoeff();
  double fscale = EI / (m.length * m.length) + m.props.rhoA * m.gravity.norm() * m.length;
  for (const auto& p : m.point_forces) fscale = std::max(fscale, p.force.norm());
  for (const StaticEnd* e : {&m.left, &m.right}) fscale = std::max({fscale, std::abs(e->axial_force), e->end_force.norm()});
  Eigen::SparseMatrix<double> J;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  bool analysed = false;
  VecX r;
  for (int it = 0; it < max_iterations; ++it) {
    residual_and_jacobian(m, nodes, r, J);
    if (!r.allFinite()) break;
    if (!analysed) {
      lu.analyzePattern(J);
      analysed = true;
    }
    lu.factorize(J);
    if (lu.info() != Eigen::Success) {
      rep.message = "singular static Jacobian";
      break;
    }
    const VecX dx = lu.solve(-r);
    ++rep.iterations;
    double step_max = 0.0;
    for (size_t j = 0; j < nodes.size(); ++j) {
      const auto d = dx.segment<12>(12 * static_cast<Eigen::Index>(j));
      nodes[j].x += d;
      step_max = std::max({step_max, d.segment<3>(svar::r).cwiseAbs().maxCoeff() / m.length,
                           d.segment<3>(svar::theta).cwiseAbs().maxCoeff(),
                           d.segment<3>(svar::kappa).cwiseAbs().maxCoeff() * m.length,
                           d.segment<3>(svar::n).cwiseAbs().maxCoeff() / fscale});
      if (nodes[j].x.segment<3>(svar::theta).norm() > 1.0) nodes[j].rebase();  // keep increments small
    }
    if (!std::isfinite(step_max)) break;
    if (step_max <= rtol) {
      const VecX rn = residual(m, nodes);
      rep.residual_norm = rn.cwiseAbs().maxCoeff();
      if (rep.residual_norm <= ftol * fscale) {
        rep.converged = true;
        rep.load_scale = fscale;
        for (auto& n : nodes) n.rebase();
        return rep;
      }
    }
  }
  // The residual where Newton stopped (not the one before its last update).
  const VecX rn = residual(m, nodes);
  rep.residual_norm = rn.size() ? rn.cwiseAbs().maxCoeff() : 0.0;
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
  nodes = start;
  return rep;
}

StaticReport StaticSolver::solve_with_load_steps(const StaticModel& m, std::vector<StaticNode>& nodes) const {
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
    std::vector<StaticNode> trial = nodes;
    const StaticReport r = newton(scaled_loads(m, next), trial);
    total.iterations += r.iterations;
    if (r.converged) {
      nodes = trial;
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

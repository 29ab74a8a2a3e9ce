#include "reference_statics.hpp"

#include <Eigen/SparseLU>

#include <cmath>
#include <limits>

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

VecX static_residual(const StaticModel& m, const std::vector<StaticNode>& nodes) {
  VecX r;
  assemble(m, nodes, r, nullptr);
  return r;
}

void static_residual_and_jacobian(const StaticModel& m, const std::vector<StaticNode>& nodes, VecX& r,
                                  Eigen::SparseMatrix<double>& J) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<size_t>(m.num_unknowns()) * 30);
  assemble(m, nodes, r, &trip);
  J.resize(r.size(), r.size());
  J.setFromTriplets(trip.begin(), trip.end());
}

StaticReport serial_newton(const StaticModel& m, std::vector<StaticNode>& nodes, const StaticTolerances& tol) {
  StaticReport rep;
  rep.load_scale = static_force_scale(m);
  const std::array<double, 4> scale = static_update_scales(m.length, rep.load_scale);
  const std::vector<StaticNode> start = nodes;
  VecX r;
  Eigen::SparseMatrix<double> J;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  for (int it = 0; it < tol.max_iterations; ++it) {
    static_residual_and_jacobian(m, nodes, r, J);
    if (!r.allFinite()) break;
    lu.compute(J);
    if (lu.info() != Eigen::Success) {
      rep.message = "singular static Jacobian";
      break;
    }
    const VecX dx = lu.solve(-r);
    ++rep.iterations;
    double step = 0.0;  // max(|dr| / L, |dtheta|, |dkappa| L, |dn|'): rod::scaled_update
    for (Eigen::Index i = 0; i < dx.size(); ++i) {
      nodes[static_cast<size_t>(i / 12)].x(i % 12) += dx(i);
      const double s = scaled_update(static_cast<int>(i % 12), dx(i), scale, m.props.C);
      step = std::isfinite(s) ? std::max(step, s) : std::numeric_limits<double>::infinity();
    }
    if (!std::isfinite(step)) break;
    if (step > tol.rtol) continue;
    rep.residual_norm = static_residual(m, nodes).cwiseAbs().maxCoeff();
    if (rep.residual_norm <= tol.ftol * rep.load_scale) {
      rep.converged = true;
      for (auto& n : nodes) n.rebase();
      return rep;
    }
  }
  if (rep.message.empty()) rep.message = "Newton did not converge in " + std::to_string(rep.iterations) + " iterations";
  nodes = start;
  return rep;
}

StaticReport serial_load_steps(const StaticModel& m, std::vector<StaticNode>& nodes, const StaticTolerances& tol) {
  return solve_with_load_steps(m, [&](const StaticModel& scaled) { return serial_newton(scaled, nodes, tol); }, tol);
}

}  // namespace traverse::rod

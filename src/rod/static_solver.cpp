#include "traverse/rod/static_solver.hpp"

#include "traverse/core/sparse_lu.hpp"
#include "traverse/core/stop_request.hpp"

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

/// The residual (and the Jacobian's triplets) of the whole rod, or of its in-plane rows and
/// unknowns when `planar` is given.
void assemble(const StaticModel& m, const std::vector<StaticNode>& nodes, VecX& r,
              std::vector<Eigen::Triplet<double>>* trip, const StaticPlanarSplit* planar = nullptr) {
  r = VecX::Zero(planar ? 6 * static_cast<Eigen::Index>(m.num_cells + 1) : m.num_unknowns());
  LocalBlock in_plane;
  auto add = [&](const LocalBlock& full) {
    if (!planar) return scatter(full, r, trip);
    restrict_static_block(m, *planar, full, in_plane);
    scatter(in_plane, r, trip);
  };
  add(static_left_block(m, nodes.front()));
  for (int j = 1; j <= m.num_cells; ++j)
    add(static_cell_block(m, j, nodes[static_cast<size_t>(j - 1)], nodes[static_cast<size_t>(j)]));
  add(static_right_block(m, nodes.back()));
}

/// The whole rod in this process: the LU in band storage (a rod's Jacobian couples neighbouring
/// nodes only), or Eigen's SparseLU with the pattern analysed once per solve (SparseLUSolver).
class SerialStaticSystem : public StaticNewtonSystem {
 public:
  SerialStaticSystem(const StaticSolver& s, std::vector<StaticNode>& nodes) : solver_(s), nodes_(nodes) {}
  bool assemble(const StaticModel& m) override {
    solver_.residual_and_jacobian(m, nodes_, r_, J_);
    return r_.allFinite();
  }
  bool factorize(std::string& why) override {
    // The pattern is the same through a Newton solve (start() begins one).
    if (lu_.factorize(J_, analysed_)) {
      analysed_ = true;
      return true;
    }
    why = "singular static Jacobian";
    return false;
  }
  double update(double length, double fscale) override {
    const VecX dx = lu_.solve(-r_);
    double step_max = 0.0;
    for (size_t j = 0; j < nodes_.size(); ++j)
      step_max = std::max(step_max, static_update_node(nodes_[j], static_node_update(solver_.planar, dx.data(), j), length, fscale));
    return step_max;
  }
  double residual_max(const StaticModel& m) override {
    const VecX rn = solver_.residual(m, nodes_);
    return rn.size() ? rn.cwiseAbs().maxCoeff() : 0.0;
  }
  void rebase_all() override {
    for (auto& n : nodes_) n.rebase();
  }
  void start() override {
    start_ = nodes_;
    analysed_ = false;
  }
  void restore() override { nodes_ = start_; }

 private:
  const StaticSolver& solver_;
  std::vector<StaticNode>& nodes_;
  std::vector<StaticNode> start_;
  Eigen::SparseMatrix<double> J_;
  SparseLUSolver lu_;  // banded for a rod's Jacobian
  bool analysed_ = false;
  VecX r_;
};

}  // namespace

double static_update_node(StaticNode& node, const Vec12& d, double length, double fscale) {
  node.x += d;
  const double s = std::max({d.segment<3>(svar::r).cwiseAbs().maxCoeff() / length,
                             d.segment<3>(svar::theta).cwiseAbs().maxCoeff(),
                             d.segment<3>(svar::kappa).cwiseAbs().maxCoeff() * length,
                             d.segment<3>(svar::n).cwiseAbs().maxCoeff() / fscale});
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

VecX StaticSolver::residual(const StaticModel& m, const std::vector<StaticNode>& nodes) const {
  VecX r;
  assemble(m, nodes, r, nullptr);
  return r;
}

void StaticSolver::residual_and_jacobian(const StaticModel& m, const std::vector<StaticNode>& nodes, VecX& r,
                                         Eigen::SparseMatrix<double>& J) const {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<size_t>(m.num_unknowns()) * 30);
  assemble(m, nodes, r, &trip, planar ? &*planar : nullptr);
  J.resize(r.size(), r.size());
  J.setFromTriplets(trip.begin(), trip.end());
}

StaticReport StaticSolver::newton(const StaticModel& m, std::vector<StaticNode>& nodes) const {
  SerialStaticSystem sys(*this, nodes);
  return newton(m, sys);
}

StaticReport StaticSolver::solve_with_load_steps(const StaticModel& m, std::vector<StaticNode>& nodes) const {
  SerialStaticSystem sys(*this, nodes);
  return solve_with_load_steps(m, sys);
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
    const double step_max = sys.update(m.length, fscale);
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

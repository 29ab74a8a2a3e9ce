#include "reference_statics.hpp"

#include <Eigen/SparseLU>

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

/// The whole rod in this process, Eigen's sparse LU.
class SerialStaticSystem : public StaticNewtonSystem {
 public:
  explicit SerialStaticSystem(std::vector<StaticNode>& nodes) : nodes_(nodes) {}
  bool assemble(const StaticModel& m) override {
    static_residual_and_jacobian(m, nodes_, r_, J_);
    return r_.allFinite();
  }
  bool factorize(std::string& why) override {
    lu_.compute(J_);
    if (lu_.info() == Eigen::Success) return true;
    why = "singular static Jacobian";
    return false;
  }
  double update(const StaticModel& m, double fscale) override {
    const VecX dx = lu_.solve(-r_);
    double step_max = 0.0;
    for (size_t j = 0; j < nodes_.size(); ++j)
      step_max = std::max(step_max, static_update_node(nodes_[j], dx.segment<12>(12 * static_cast<Eigen::Index>(j)),
                                                       m, fscale));
    return step_max;
  }
  double residual_max(const StaticModel& m) override {
    const VecX rn = static_residual(m, nodes_);
    return rn.size() ? rn.cwiseAbs().maxCoeff() : 0.0;
  }
  void rebase_all() override {
    for (auto& n : nodes_) n.rebase();
  }
  void start() override { start_ = nodes_; }
  void restore() override { nodes_ = start_; }

 private:
  std::vector<StaticNode>& nodes_;
  std::vector<StaticNode> start_;
  Eigen::SparseMatrix<double> J_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu_;
  VecX r_;
};

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

StaticReport serial_newton(const StaticSolver& solver, const StaticModel& m, std::vector<StaticNode>& nodes) {
  SerialStaticSystem sys(nodes);
  return solver.newton(m, sys);
}

StaticReport serial_load_steps(const StaticSolver& solver, const StaticModel& m, std::vector<StaticNode>& nodes) {
  SerialStaticSystem sys(nodes);
  return solver.solve_with_load_steps(m, sys);
}

}  // namespace traverse::rod

#include "reference_stepper.hpp"

#include <Eigen/SparseLU>

#include <Eigen/SparseLU>
#include <stdexcept>

namespace traverse::rod {

ReferenceStepper::ReferenceStepper(RodModel model) : model_(std::move(model)) {
  const EndConditionCheck c = validate_end_conditions(model_.left, model_.right);
  if (!c.ok) throw std::invalid_argument("ReferenceStepper: " + c.message);
}

namespace {
std::vector<VecX> split(const RodModel& m, const VecX& x) {
  const int p = m.unknowns_per_node();
  std::vector<VecX> v(static_cast<size_t>(m.num_cells) + 1);
  for (int j = 0; j <= m.num_cells; ++j) v[j] = x.segment(m.node_col(j), p);
  return v;
}
}  // namespace

VecX ReferenceStepper::unknowns(const RodState& state) const {
  VecX x(model_.num_unknowns());
  for (int j = 0; j <= model_.num_cells; ++j)
    x.segment(model_.node_col(j), model_.unknowns_per_node()) = node_unknowns(model_, state.nodes[j]);
  return x;
}

RodState ReferenceStepper::state_from_unknowns(const RodState& old_state, const VecX& x,
                                               double dt) const {
  RodState s = old_state;
  s.t = old_state.t + dt;
  const int p = model_.unknowns_per_node();
  for (int j = 0; j <= model_.num_cells; ++j)
    s.nodes[j] = advance_node(model_, old_state.nodes[j], x.segment(model_.node_col(j), p), dt);
  return s;
}

VecX ReferenceStepper::residual(const StepTimes& step, const RodState& old_state,
                                const VecX& x) const {
  const auto blocks = assemble_nodes(model_, step, 0, model_.num_cells, 0, old_state.nodes,
                                     split(model_, x));
  VecX r = VecX::Zero(model_.num_unknowns());
  for (const auto& b : blocks) r.segment(b.row, b.residual.size()) += b.residual;
  return r;
}

void ReferenceStepper::residual_and_jacobian(const StepTimes& step, const RodState& old_state,
                                             const VecX& x, VecX& r,
                                             Eigen::SparseMatrix<double>& J) const {
  const auto blocks = assemble_nodes(model_, step, 0, model_.num_cells, 0, old_state.nodes,
                                     split(model_, x));
  const Eigen::Index n = model_.num_unknowns();
  r = VecX::Zero(n);
  std::vector<Eigen::Triplet<double>> t;
  for (const auto& b : blocks) {
    r.segment(b.row, b.residual.size()) += b.residual;
    for (size_t k = 0; k < b.cols.size(); ++k)
      for (Eigen::Index c = 0; c < b.jac[k].cols(); ++c)
        for (Eigen::Index i = 0; i < b.jac[k].rows(); ++i)
          if (b.jac[k](i, c) != 0.0) t.emplace_back(b.row + i, b.cols[k] + c, b.jac[k](i, c));
  }
  J.resize(n, n);
  J.setFromTriplets(t.begin(), t.end());
}

ReferenceStepReport ReferenceStepper::step(RodState& state, double dt) const {
  if (state.num_cells() != model_.num_cells)
    throw std::invalid_argument("ReferenceStepper::step: state and model grids differ");
  const StepTimes st{state.t, dt};
  VecX x = unknowns(state);
  ReferenceStepReport rep;
  VecX r;
  Eigen::SparseMatrix<double> J;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  for (int it = 1; it <= max_iterations; ++it) {
    residual_and_jacobian(st, state, x, r, J);
    if (!r.allFinite()) break;
    lu.compute(J);
    if (lu.info() != Eigen::Success) break;
    const VecX dx = lu.solve(-r);
    if (!dx.allFinite()) break;
    x += dx;
    const double previous = rep.last_correction;
    rep.iterations = it;
    rep.last_correction = dx.cwiseAbs().maxCoeff();
    const double scale = x.cwiseAbs().maxCoeff();
    if (rep.last_correction <= rtol * scale + atol) {
      rep.converged = true;
      break;
    }
    // Round-off floor: a tiny correction that no longer shrinks quadratically.
    if (it > 1 && rep.last_correction <= 1e-9 * scale + atol &&
        rep.last_correction > 0.1 * previous) {
      rep.converged = true;
      break;
    }
  }
  if (!rep.converged) return rep;
  rep.residual_norm = residual(st, state, x).cwiseAbs().maxCoeff();
  state = state_from_unknowns(state, x, dt);
  return rep;
}

namespace {

/// reference_rod_solve: Newton on the whole rod with the criteria of ReferenceStepper::step.
class ReferenceRodSolve final : public CoupledRodSolve {
 public:
  explicit ReferenceRodSolve(RodModel model) : stepper_(std::move(model)) {}
  bool solve(const RodState& old, double dt, bool again, int& iterations) override {
    const StepTimes st{old.t, dt};
    if (!again) x_ = stepper_.unknowns(old);
    if (!newton(st, old, iterations)) return false;
    trial_ = stepper_.state_from_unknowns(old, x_, dt);
    return true;
  }
  RodPointKinematics point(double sigma) const override { return point_kinematics(trial_, sigma, stepper_.model().props); }
  RodState solution() const override { return trial_; }

 private:
  bool newton(const StepTimes& st, const RodState& old, int& iterations) {
    VecX r;
    Eigen::SparseMatrix<double> J;
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    double previous = 0.0;
    for (int it = 1; it <= stepper_.max_iterations; ++it) {
      stepper_.residual_and_jacobian(st, old, x_, r, J);
      if (!r.allFinite()) return false;
      lu.compute(J);
      if (lu.info() != Eigen::Success) return false;
      const VecX dx = lu.solve(-r);
      if (!dx.allFinite()) return false;
      x_ += dx;
      ++iterations;
      const double change = dx.cwiseAbs().maxCoeff(), scale = x_.cwiseAbs().maxCoeff();
      if (change <= stepper_.rtol * scale + stepper_.atol) return true;
      if (it > 1 && change <= 1e-9 * scale + stepper_.atol && change > 0.1 * previous) return true;
      previous = change;
    }
    return false;
  }
  ReferenceStepper stepper_;
  VecX x_;
  RodState trial_;
};

}  // namespace

std::unique_ptr<CoupledRodSolve> reference_rod_solve(RodModel model) {
  return std::make_unique<ReferenceRodSolve>(std::move(model));
}

}  // namespace traverse::rod

#include "traverse/solver/coupled_rod_solve.hpp"

#include <algorithm>
#include <stdexcept>

#include "traverse/core/comm.hpp"
#include "traverse/rod/coupled_mass_rod.hpp"

namespace traverse::solver {

DistributedCoupledRodSolve::DistributedCoupledRodSolve(std::unique_ptr<RodStepper> stepper, MPI_Comm comm)
    : stepper_(std::move(stepper)), comm_(comm) {
  if (!stepper_) throw std::invalid_argument("DistributedCoupledRodSolve: null stepper");
}

bool DistributedCoupledRodSolve::solve(const rod::RodState& old, double dt, bool again, int& iterations) {
  StepReport rep;
  bool ok = false;
  if (again) {
    ok = stepper_->redo_step(rep);
  } else {
    stepper_->set_state(old);
    ok = stepper_->try_step(dt, rep);
  }
  iterations += rep.newton_iterations;
  return ok;
}

rod::RodPointKinematics DistributedCoupledRodSolve::point(double sigma) const {
  const RodStepper& st = *stepper_;
  const int N = st.model().num_cells, first = st.first_owned_node(), owned = st.num_owned_nodes();
  const rod::NodeInterpolation at = rod::locate_on_nodes(sigma, st.model().ds(), N);
  const int nodes[2] = {at.j, std::min(at.j + 1, N)};
  const double w[2] = {1.0 - at.xi, at.xi};
  double local[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, sum[6];
  for (int side = 0; side < 2; ++side) {
    const int k = nodes[side] - first;
    if (k < 0 || k >= owned) continue;
    const rod::RodNode& nd = st.owned_node(k);
    const Vec3 U = w[side] * rod::fixed_velocity(nd), d3 = w[side] * rod::node_tangent(nd, st.model().props);
    for (int c = 0; c < 3; ++c) {
      local[c] += U(c);
      local[3 + c] += d3(c);
    }
  }
  par::allreduce(local, sum, 6, MPI_DOUBLE, MPI_SUM, comm_);
  rod::RodPointKinematics p;
  p.U = Vec3(sum[0], sum[1], sum[2]);
  p.d3 = Vec3(sum[3], sum[4], sum[5]);
  return p;
}

rod::RodState DistributedCoupledRodSolve::solution() const { return stepper_->gather_state(); }

}  // namespace traverse::solver

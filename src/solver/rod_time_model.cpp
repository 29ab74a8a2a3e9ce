#include "traverse/solver/rod_time_model.hpp"

#include <algorithm>
#include <sstream>

#include "traverse/core/comm.hpp"

namespace traverse::solver {

std::vector<rod::NodeLevel> owned_levels(const RodStepper& st) {
  std::vector<rod::NodeLevel> y(static_cast<size_t>(st.num_owned_nodes()));
  for (int k = 0; k < st.num_owned_nodes(); ++k) y[static_cast<size_t>(k)] = rod::node_level(st.owned_node(k));
  return y;
}

Vec3 LeftEnd::velocity() const {
  Vec3 v = Vec3::Zero();
  int root = 0;
  if (st_.first_owned_node() == 0) v = rod::fixed_velocity(st_.owned_node(0));
  const int owner = st_.first_owned_node() == 0 ? par::rank(comm_) : 0;
  par::allreduce(&owner, &root, 1, MPI_INT, MPI_MAX, comm_);
  par::bcast(v.data(), 3, MPI_DOUBLE, root, comm_);
  return v;
}

void RodTimeModel::step(double h) {
  left_.before_step();
  const StepReport rep = st_.step(h);  // StepFailure, PlanarityLost: the state as before
  counts_.newton += rep.newton_iterations;
  counts_.solves += rep.substeps;
  counts_.guess_retries += rep.guess_retries;
  left_.after_step(h);
}

bool RodTimeModel::solve(double h, StepReport& rep, std::string& why) {
  const bool ok = st_.try_step(h, rep);
  counts_.newton += rep.newton_iterations;
  ++counts_.solves;
  counts_.guess_retries += rep.guess_retries;
  if (!ok) {
    std::ostringstream os;
    os << "the Newton solve of a step of dt = " << h << " s did not converge (" << st_.last_newton_report().status << ")";
    why = os.str();
  }
  return ok;
}

time::Attempt RodTimeModel::attempt(double h) {
  h_ = h;
  doubled_ = !est_->has_history();
  return doubled_ ? doubled(h) : extrapolated(h);
}

time::Attempt RodTimeModel::extrapolated(double h) {
  time::Attempt a;
  left_.before_step();
  StepReport rep;
  if (!solve(h, rep, a.why)) return a;
  y_ = owned_levels(st_);
  a.converged = true;
  a.error = est_->extrapolation_error(y_, h);
  a.newton = rep.newton_iterations;
  return a;
}

// One step of h against two of h / 2 from the same state; the two half steps are kept.
time::Attempt RodTimeModel::doubled(double h) {
  time::Attempt a;
  a.estimate = "the error estimate of the first step (step doubling)";
  saved_ = st_.ghosted_piece();
  r_saved_ = left_.position();
  StepReport rep;
  if (!solve(h, rep, a.why)) return a;
  const std::vector<rod::NodeLevel> full = owned_levels(st_);
  st_.undo_step();
  int newton = rep.newton_iterations;
  for (int part = 0; part < 2; ++part) {
    left_.before_step();
    StepReport r;
    bool ok = false;
    try {
      ok = solve(0.5 * h, r, a.why);
    } catch (const PlanarityLost&) {
      restore_start();
      throw;
    }
    if (!ok) {
      restore_start();  // the state of the step's start, for the retry or the restart point
      return a;
    }
    left_.after_step(0.5 * h);
    newton = std::max(newton, r.newton_iterations);
    (part == 0 ? mid_ : y_) = owned_levels(st_);
  }
  a.converged = true;
  a.error = est_->doubling_error(full, mid_, y_, h);
  a.newton = newton;
  return a;
}

void RodTimeModel::restore_start() {
  st_.set_state(saved_, st_.first_ghosted_node());
  left_.set_position(r_saved_);
}

std::vector<double> RodTimeModel::accept() {
  if (doubled_) {
    est_->accept(std::move(mid_), 0.5 * h_);
    est_->accept(std::move(y_), 0.5 * h_);
    return {0.5 * h_, 0.5 * h_};
  }
  left_.after_step(h_);
  est_->accept(std::move(y_), h_);
  return {h_};
}

void RodTimeModel::reject() {
  if (doubled_)
    restore_start();
  else
    st_.undo_step();
}

}  // namespace traverse::solver

// The rod stepper's step logic (rod_stepper.hpp).
#include "traverse/solver/rod_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

#include "traverse/solver/solver_parameters.hpp"

namespace traverse::solver {

RodStepper::RodStepper(rod::RodModel model, const Teuchos::ParameterList& params, int ranks, int rank) {
  const rod::EndConditionCheck check = rod::validate_end_conditions(model.left, model.right);
  if (!check.ok) throw std::invalid_argument("rod stepper: " + check.message);
  model_ = std::make_shared<const rod::RodModel>(std::move(model));
  params_ = validated_solver_parameters(params);
  max_depth_ = params_.get<int>("Max Subdivision Depth");
  guess_ = initial_guess_of(params_);
  choice_ = LinearSolverChoice::resolve(params_, ranks, LinearSolverChoice::Use::time_step);
  if (choice_.rerouted && params_.get<bool>("Verbose") && rank == 0)
    std::cout << "traverse notice: linear solver " << choice_.resolved << std::endl;
  planar_tolerance_ = params_.get<double>("Residual Tolerance");
}

RodStepper::~RodStepper() = default;

void RodStepper::set_partition(int first_ghosted, int num_ghosted, int first_owned, int num_owned) {
  g0_ = first_ghosted;
  ng_ = num_ghosted;
  o0_ = first_owned;
  no_ = num_owned;
}

void RodStepper::set_state(const rod::RodState& full) {
  if (full.num_cells() != model_->num_cells)
    throw std::invalid_argument("RodStepper::set_state: the state has " + std::to_string(full.num_cells()) +
                                " cells, the model " + std::to_string(model_->num_cells));
  nodes_.assign(full.nodes.begin() + g0_, full.nodes.begin() + g0_ + ng_);
  t_ = full.t;
  undo_ready_ = false;
}

void RodStepper::set_state(const rod::RodState& piece, int first_node) {
  if (first_node > g0_ || first_node + static_cast<int>(piece.nodes.size()) < g0_ + ng_)
    throw std::invalid_argument("RodStepper::set_state: the piece holds nodes " + std::to_string(first_node) + ".." +
                                std::to_string(first_node + static_cast<int>(piece.nodes.size()) - 1) +
                                ", this rank needs " + std::to_string(g0_) + ".." + std::to_string(g0_ + ng_ - 1));
  const auto begin = piece.nodes.begin() + (g0_ - first_node);
  nodes_.assign(begin, begin + ng_);
  t_ = piece.t;
  undo_ready_ = false;
}

const rod::RodNode& RodStepper::owned_node(int k) const {
  if (k < 0 || k >= no_) throw std::out_of_range("RodStepper::owned_node: index " + std::to_string(k));
  return nodes_[static_cast<size_t>(o0_ - g0_ + k)];
}

rod::RodState RodStepper::ghosted_piece() const {
  rod::RodState s;
  s.t = t_;
  s.ds = model_->ds();
  s.nodes = nodes_;
  return s;
}

void RodStepper::set_planar(const rod::PlanarSymmetry* symmetry) {
  if (!symmetry && !planar_) return;
  // The partition does not change with the path: each rank keeps its nodes and ghosts.
  planar_ = symmetry ? std::make_shared<const rod::PlanarReduction>(*model_, *symmetry) : nullptr;
  undo_ready_ = false;
  rebuild();
}

std::string RodStepper::path_description() const {
  const int p = unknowns_per_node();
  if (planar_) return "planar (" + std::to_string(p) + " unknowns per node, " + planar_->symmetry().describe() + ")";
  return "3D (" + std::to_string(p) + " unknowns per node)";
}

Teuchos::ParameterList RodStepper::newton_params() const {
  Teuchos::ParameterList p = params_;
  if (planar_) {
    const double c = std::sqrt(double(planar_->full_unknowns_per_node()) / planar_->unknowns_per_node());
    p.set("Update Relative Tolerance", c * params_.get<double>("Update Relative Tolerance"));
    p.set("Update Absolute Tolerance", c * params_.get<double>("Update Absolute Tolerance"));
  }
  return p;
}

/// Planar path: the out-of-plane residual at the converged iterate (max over ranks) must be
/// within the Newton residual tolerance, else the problem was not planar after all.
void RodStepper::check_planarity(double t0, double dt) const {
  if (!planar_) return;
  const double d = dropped_residual_everywhere();
  if (!(d <= planar_tolerance_)) {
    std::ostringstream os;
    os << "planar path: the out-of-plane residual is " << d << " at the converged state of the step from t = " << t0
       << " s (dt = " << dt << " s), above the residual tolerance " << planar_tolerance_
       << ": the problem is not symmetric about the " << planar_->symmetry().describe() << " (run it on the 3D path)";
    throw PlanarityLost(os.str());
  }
}

/// One Newton solve from t0 to t0 + dt. The nodes are moved into the solver as its old level
/// for the solve (one copy of the rod's nodes instead of two) and `nodes_` is refilled from
/// it: with the new level on success, as it was on failure or when the solve throws.
/// `warm` (redo_step): the solver already holds this step's old level and Newton starts from
/// the unknowns of the solve before. Otherwise Newton starts from the guess the parameters
/// name; with 'Initial Guess: auto' from the blend (RodNode::yg) and, if that solve fails, once
/// more from the old level before the caller halves the step (the verdict is global: every rank
/// takes the same branch).
bool RodStepper::attempt(double t0, double dt, StepReport& sr, bool warm) {
  if (!warm) set_old_level(std::move(nodes_), rod::StepTimes{t0, dt});
  nodes_.clear();
  std::vector<VecX>& xg = xg_;  // kept between steps: its node blocks keep their storage
  bool retried = false;  // solved from the old level after the blend failed
  try {
    if (warm) {
      last_ = solve_level(xg, std::nullopt, sr);
    } else {
      last_ = solve_level(xg, guess_, sr);
      if (!last_.converged && guess_ == rod::InitialGuess::blend) {
        ++sr.guess_retries;
        retried = true;
        last_ = solve_level(xg, rod::InitialGuess::old_level, sr);
      }
    }
    if (last_.converged) check_planarity(t0, dt);
  } catch (...) {
    nodes_ = old_level();
    throw;
  }
  const std::vector<rod::RodNode>& old = old_level();
  if (!last_.converged) {
    nodes_ = old;
    return false;
  }
  nodes_.reserve(old.size());
  for (size_t k = 0; k < old.size(); ++k) {
    nodes_.push_back(rod::advance_node(*model_, old[k], xg[k], dt));
    if (retried) nodes_.back().yg.setZero();  // the next step starts from its old level too
  }
  t_ = t0 + dt;
  return true;
}

/// `saved` (depth 0 only): receives the nodes at t0 before the step is subdivided, so that
/// step() can restore them if a later sub-step fails. A failed attempt leaves `nodes_` as they
/// were, so the copy is needed only once the step is split (not on every step).
void RodStepper::advance(double t0, double dt, int depth, StepReport& sr, double t_step, double dt_step,
                         std::vector<rod::RodNode>* saved) {
  if (attempt(t0, dt, sr)) {
    ++sr.substeps;
    sr.max_depth = std::max(sr.max_depth, depth);
    sr.last = last_;
    return;
  }
  ++sr.failed_attempts;
  if (depth >= max_depth_) throw StepFailure(t_step, dt_step, t0, dt, depth, last_);
  if (saved) *saved = nodes_;
  advance(t0, 0.5 * dt, depth + 1, sr, t_step, dt_step);
  advance(t0 + 0.5 * dt, 0.5 * dt, depth + 1, sr, t_step, dt_step);
}

StepReport RodStepper::step(double dt) {
  if (!(dt > 0.0)) throw std::invalid_argument("RodStepper::step: dt must be > 0, found " + std::to_string(dt));
  std::vector<rod::RodNode> saved;  // the nodes at t0, copied only if the step is subdivided
  const double t0 = t_;
  undo_ready_ = false;
  StepReport sr;
  try {
    advance(t0, dt, 0, sr, t0, dt, &saved);
  } catch (const std::exception&) {  // StepFailure, PlanarityLost
    if (!saved.empty()) nodes_ = std::move(saved);  // else no attempt changed the nodes
    t_ = t0;
    throw;
  }
  t_ = t0 + dt;  // exactly, whatever the subdivision did
  return sr;
}

bool RodStepper::try_step(double dt, StepReport& report) {
  if (!(dt > 0.0)) throw std::invalid_argument("RodStepper::try_step: dt must be > 0, found " + std::to_string(dt));
  const double t0 = t_;
  const bool ok = attempt(t0, dt, report);  // on failure (or a throw) the nodes are as they were
  if (ok) {
    ++report.substeps;
    report.last = last_;
    undo_time_ = t0;
    undo_dt_ = dt;
    undo_ready_ = true;
  } else {
    ++report.failed_attempts;
    t_ = t0;
  }
  return ok;
}

bool RodStepper::redo_step(StepReport& report) {
  if (!undo_ready_) throw std::logic_error("RodStepper::redo_step: no step to redo");
  const bool ok = attempt(undo_time_, undo_dt_, report, true);
  if (ok) {
    ++report.substeps;
    report.last = last_;
  } else {  // back at the step's start
    ++report.failed_attempts;
    t_ = undo_time_;
    undo_ready_ = false;
  }
  return ok;
}

void RodStepper::undo_step() {
  if (!undo_ready_) throw std::logic_error("RodStepper::undo_step: no step to undo");
  nodes_ = old_level();  // the solver holds the step's old level
  t_ = undo_time_;
  undo_ready_ = false;
}

double time_step_bytes_per_node(int unknowns) {
  if (unknowns <= 6) return 8800.0;
  if (unknowns <= 12) return 17500.0;
  return 54000.0;
}

}  // namespace traverse::solver

#include "traverse/solver/distributed_stepper.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "block_newton.hpp"
#include "linear_solver_builder.hpp"
#include "reusable_ifpack2_factory.hpp"
#include "traverse/mesh/distributed_mesh.hpp"
#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/solver/newton_solver.hpp"
#include "traverse/solver/rod_step_model.hpp"
#include "traverse/solver/solver_parameters.hpp"

namespace traverse::solver {

namespace {
/// The KLU2 shortcut exactly (no pass-through keys), on the ranks it was asked for.
bool is_plain_klu2(const LinearSolverChoice& choice) {
  const Teuchos::ParameterList& s = choice.stratimikos;
  if (choice.rerouted || !s.isType<std::string>("Linear Solver Type") ||
      s.get<std::string>("Linear Solver Type") != "Amesos2" || !s.isSublist("Linear Solver Types") ||
      !s.sublist("Linear Solver Types").isSublist("Amesos2"))
    return false;
  const Teuchos::ParameterList& a = s.sublist("Linear Solver Types").sublist("Amesos2");
  if (!a.isType<std::string>("Solver Type") || a.get<std::string>("Solver Type") != "KLU2") return false;
  for (auto it = a.begin(); it != a.end(); ++it)
    if (a.name(it) != "Solver Type") return false;
  return true;
}

constexpr int kPacked = 45;  // y (12), R (9), yt (12), ys (12)

void pack(const rod::RodNode& n, double* d) {
  for (int i = 0; i < 12; ++i) d[i] = n.y(i);
  for (int i = 0; i < 9; ++i) d[12 + i] = n.R(i / 3, i % 3);
  for (int i = 0; i < 12; ++i) d[21 + i] = n.yt(i);
  for (int i = 0; i < 12; ++i) d[33 + i] = n.ys(i);
}

rod::RodNode unpack(const double* d) {
  rod::RodNode n;
  for (int i = 0; i < 12; ++i) n.y(i) = d[i];
  for (int i = 0; i < 9; ++i) n.R(i / 3, i % 3) = d[12 + i];
  for (int i = 0; i < 12; ++i) n.yt(i) = d[21 + i];
  for (int i = 0; i < 12; ++i) n.ys(i) = d[33 + i];
  return n;
}
}  // namespace

struct DistributedStepper::Impl {
  std::shared_ptr<const rod::RodModel> model;
  Teuchos::RCP<const Teuchos::Comm<int>> comm;
  Teuchos::ParameterList params;
  LinearSolverChoice choice;
  Teuchos::RCP<const mesh::DistributedMesh> mesh;
  Teuchos::RCP<RodStepModel> me;
  std::unique_ptr<NewtonSolver> newton;
  std::unique_ptr<BlockNewton> block_newton;  ///< instead of NOX where it applies (uses_block_newton)
  std::vector<double> xb;                      ///< its unknowns
  Teuchos::RCP<Tpetra::Vector<double>> x;
  std::vector<rod::RodNode> nodes;  ///< ghosted range, current level
  double t = 0.0;
  NewtonReport last;
  int max_depth = 4;
  int full_newton_retries = 0;
  std::shared_ptr<DirectSolverStats> direct_stats = std::make_shared<DirectSolverStats>();
  bool reusing_klu2 = false;
  std::shared_ptr<const rod::PlanarReduction> planar;  ///< null on the 3D path
  double planar_tolerance = 1e-8;  ///< largest dropped residual accepted at a converged iterate
  double undo_time = 0.0;  ///< try_step: the time before the last successful step
  double undo_dt = 0.0;    ///< and its length
  bool undo_ready = false;

  /// Mesh, model evaluator, linear solver and Newton solver for p unknowns per node (the
  /// model's, or the planar reduction's).
  void build() {
    const rod::RodModel& rm = *model;
    const int p = planar ? planar->unknowns_per_node() : rm.unknowns_per_node();
    newton.reset();
    block_newton.reset();
    me = Teuchos::null;
    direct_stats = std::make_shared<DirectSolverStats>();
    reusing_klu2 = false;
    mesh = Teuchos::rcp(new mesh::DistributedMesh(mesh::Mesh1D(rm.length, rm.num_cells + 1), comm, p));
    me = Teuchos::rcp(new RodStepModel(model, mesh, planar));
    me->set_jacobian_reuse(params.get<bool>("Jacobian Reuse"), params.get<double>("Jacobian Reuse Contraction"));
    if (params.get<std::string>("Direct Solver Path") == "Reuse Symbolic" && comm->getSize() == 1 &&
        is_plain_klu2(choice)) {
      RodStepModel* model_ptr = me.get();  // owned by the stepper, outlives the factory's use
      me->set_W_factory(make_reusing_klu2_factory([model_ptr] { return model_ptr->jacobian_version(); },
                                                  direct_stats));
      reusing_klu2 = true;
    } else if (choice.block_tridiagonal_direct) {
      RodStepModel* model_ptr = me.get();
      me->set_W_factory(make_block_tridiagonal_solve_factory(
          [model_ptr] { return model_ptr->jacobian_version(); }, direct_stats, choice.linear_tolerance));
    } else {
      const LinearSolverObjects ls = build_linear_solver(choice);
      me->set_W_factory(ls.lows);
      me->set_prec_factory(ls.prec);
    }
    x = Teuchos::rcp(new Tpetra::Vector<double>(mesh->dof_map()));
  }

  /// Whether the time steps use BlockNewton (same iterates as NOX, without Tpetra, Thyra and
  /// NOX): one rank, the block-tridiagonal LU as the direct solver, a full Newton step, no NOX
  /// pass-through keys, no modified Newton, and not "Newton Implementation: NOX".
  bool uses_block_newton() const {
    return comm->getSize() == 1 && choice.block_tridiagonal_direct &&
           params.get<std::string>("Newton Implementation") == "auto" &&
           params.get<std::string>("Line Search") == "Full Step" && !params.get<bool>("Jacobian Reuse") &&
           (!params.isSublist("NOX") || params.sublist("NOX").numParams() == 0);
  }

  /// The Newton solver of the time steps (after build() and set_old_level).
  void build_newton() {
    if (uses_block_newton()) {
      const Teuchos::ParameterList np = newton_params();
      BlockNewtonOptions o;
      o.residual_tolerance = np.get<double>("Residual Tolerance");
      o.update_relative_tolerance = np.get<double>("Update Relative Tolerance");
      o.update_absolute_tolerance = np.get<double>("Update Absolute Tolerance");
      o.max_iterations = np.get<int>("Max Newton Iterations");
      o.linear_tolerance = choice.linear_tolerance;
      block_newton = std::make_unique<BlockNewton>(me->assembly(), o);
      xb.assign(static_cast<size_t>(me->assembly().num_owned_nodes()) * me->unknowns_per_node(), 0.0);
      return;
    }
    newton = std::make_unique<NewtonSolver>(me, newton_params());
  }

  /// Newton on the model's old level from its old unknowns (warm: from the unknowns of the
  /// last solve); the converged (or last) iterate's ghosted full unknown blocks in xg.
  NewtonReport solve_step(std::vector<VecX>& xg, bool warm) {
    if (block_newton) {
      if (!warm) me->assembly().old_unknowns(xb.data());
      NewtonReport r = block_newton->solve(xb);
      me->assembly().full_unknowns(xb.data(), xg);
      return r;
    }
    if (!warm) me->old_unknowns(*x);
    NewtonReport r = newton->solve(*x);
    xg = me->ghosted_unknowns(*x);
    return r;
  }

  double dropped_residual() const {
    return block_newton ? block_newton->last_dropped_residual() : me->last_dropped_residual();
  }

  /// The Newton parameters. Planar path: NOX's update test is a WRMS norm, sqrt(sum w_i^2 / n)
  /// over the n unknowns; the 3D solve's out-of-plane updates are zero, so over the in-plane
  /// unknowns only (n / 2) the same updates give a norm sqrt(2) larger. Both update tolerances
  /// are scaled by sqrt(p / q) = sqrt(2) so that the planar solve stops at the same iterate as
  /// the 3D one (the max-norm residual test needs no change).
  Teuchos::ParameterList newton_params() const {
    Teuchos::ParameterList p = params;
    if (planar) {
      const double c = std::sqrt(double(planar->full_unknowns_per_node()) / planar->unknowns_per_node());
      p.set("Update Relative Tolerance", c * params.get<double>("Update Relative Tolerance"));
      p.set("Update Absolute Tolerance", c * params.get<double>("Update Absolute Tolerance"));
    }
    return p;
  }

  /// Planar path: the out-of-plane residual at the converged iterate (max over ranks) must be
  /// within the Newton residual tolerance, else the problem was not planar after all.
  void check_planarity(double t0, double dt) const {
    if (!planar) return;
    const double local = dropped_residual();
    double d = local;
    Teuchos::reduceAll<int, double>(*comm, Teuchos::REDUCE_MAX, 1, &local, &d);
    if (!(d <= planar_tolerance)) {
      std::ostringstream os;
      os << "planar path: the out-of-plane residual is " << d << " at the converged state of the step from t = "
         << t0 << " s (dt = " << dt << " s), above the residual tolerance " << planar_tolerance
         << ": the problem is not symmetric about the " << planar->symmetry().describe()
         << " (run it on the 3D path)";
      throw PlanarityLost(os.str());
    }
  }

  /// One Newton solve from t0 to t0 + dt. The nodes are moved into the model as its old level
  /// for the solve (one copy of the rod's nodes instead of two) and `nodes` is refilled from
  /// it: with the new level on success, as it was on failure or when the solve throws.
  /// `warm` (redo_step): the model already holds this step's old level and Newton starts from
  /// the unknowns of the solve before.
  bool attempt(double t0, double dt, StepReport& sr, bool warm = false) {
    if (!warm) me->set_old_level(std::move(nodes), rod::StepTimes{t0, dt});
    nodes.clear();
    std::vector<VecX> xg;
    try {
      last = solve_step(xg, warm);
      sr.newton_iterations += last.iterations;
      sr.linear_iterations += last.linear_iterations;
      if (!last.converged && me->jacobian_reuse() && me->stale_jacobian_used()) {
        // Modified Newton failed with a kept W: redo this solve with full Newton.
        ++full_newton_retries;
        me->set_full_newton(true);
        me->set_old_level(me->old_ghosted_nodes(), rod::StepTimes{t0, dt});
        last = solve_step(xg, false);
        me->set_full_newton(false);
        sr.newton_iterations += last.iterations;
        sr.linear_iterations += last.linear_iterations;
      }
      if (last.converged) check_planarity(t0, dt);
    } catch (...) {
      nodes = me->old_ghosted_nodes();
      throw;
    }
    const std::vector<rod::RodNode>& old = me->old_ghosted_nodes();
    if (!last.converged) {
      nodes = old;
      return false;
    }
    nodes.resize(old.size());
    for (size_t k = 0; k < nodes.size(); ++k) nodes[k] = rod::advance_node(*model, old[k], xg[k], dt);
    t = t0 + dt;
    return true;
  }

  /// `saved` (depth 0 only): receives the nodes at t0 before the step is subdivided, so that
  /// step() can restore them if a later sub-step fails. A failed attempt leaves `nodes` as they
  /// were, so the copy is needed only once the step is split (not on every step).
  void advance(double t0, double dt, int depth, StepReport& sr, double t_step, double dt_step,
               std::vector<rod::RodNode>* saved = nullptr) {
    if (attempt(t0, dt, sr)) {
      ++sr.substeps;
      sr.max_depth = std::max(sr.max_depth, depth);
      sr.last = last;
      return;
    }
    ++sr.failed_attempts;
    if (depth >= max_depth) throw StepFailure(t_step, dt_step, t0, dt, depth, last);
    if (saved) *saved = nodes;
    advance(t0, 0.5 * dt, depth + 1, sr, t_step, dt_step);
    advance(t0 + 0.5 * dt, 0.5 * dt, depth + 1, sr, t_step, dt_step);
  }
};

DistributedStepper::DistributedStepper(rod::RodModel model,
                                       const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                       const Teuchos::ParameterList& params)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  const rod::EndConditionCheck check = rod::validate_end_conditions(model.left, model.right);
  if (!check.ok) throw std::invalid_argument("DistributedStepper: " + check.message);
  if (comm.is_null()) throw std::invalid_argument("DistributedStepper: null communicator");
  m.model = std::make_shared<const rod::RodModel>(std::move(model));
  m.comm = comm;
  m.params = validated_solver_parameters(params);
  m.max_depth = m.params.get<int>("Max Subdivision Depth");
  m.choice = LinearSolverChoice::resolve(m.params, comm->getSize(), LinearSolverChoice::Use::time_step);
  if (m.choice.rerouted && m.params.get<bool>("Verbose") && comm->getRank() == 0)
    std::cout << "traverse notice: linear solver " << m.choice.resolved << std::endl;

  m.planar_tolerance = m.params.get<double>("Residual Tolerance");
  const rod::RodModel& rm = *m.model;
  m.build();
  set_state(rod::straight_rest_state(rm.num_cells, rm.length));
  m.me->set_old_level(m.nodes, rod::StepTimes{m.t, 0.0});
  m.build_newton();
}

DistributedStepper::~DistributedStepper() = default;

void DistributedStepper::set_planar(const rod::PlanarSymmetry* symmetry) {
  Impl& m = *impl_;
  if (!symmetry && !m.planar) return;
  // The partition does not change with the path: each rank keeps its nodes and ghosts.
  m.planar = symmetry ? std::make_shared<const rod::PlanarReduction>(*m.model, *symmetry) : nullptr;
  m.undo_ready = false;
  m.build();
  m.me->set_old_level(m.nodes, rod::StepTimes{m.t, 0.0});
  m.build_newton();
}

bool DistributedStepper::planar() const { return impl_->planar != nullptr; }

const rod::PlanarSymmetry* DistributedStepper::planar_symmetry() const {
  return impl_->planar ? &impl_->planar->symmetry() : nullptr;
}

int DistributedStepper::unknowns_per_node() const { return impl_->me->unknowns_per_node(); }

std::string DistributedStepper::path_description() const {
  const Impl& m = *impl_;
  const int p = m.me->unknowns_per_node();
  if (m.planar) return "planar (" + std::to_string(p) + " unknowns per node, " + m.planar->symmetry().describe() + ")";
  return "3D (" + std::to_string(p) + " unknowns per node)";
}

void DistributedStepper::set_state(const rod::RodState& full) {
  Impl& m = *impl_;
  if (full.num_cells() != m.model->num_cells)
    throw std::invalid_argument("DistributedStepper::set_state: the state has " +
                                std::to_string(full.num_cells()) + " cells, the model " +
                                std::to_string(m.model->num_cells));
  const int g0 = m.mesh->first_ghosted_node();
  m.nodes.assign(full.nodes.begin() + g0, full.nodes.begin() + g0 + m.mesh->num_ghosted_nodes());
  m.t = full.t;
  m.undo_ready = false;
}

void DistributedStepper::set_state(const rod::RodState& piece, int first_node) {
  Impl& m = *impl_;
  const int g0 = m.mesh->first_ghosted_node(), count = m.mesh->num_ghosted_nodes();
  if (first_node > g0 || first_node + static_cast<int>(piece.nodes.size()) < g0 + count)
    throw std::invalid_argument("DistributedStepper::set_state: the piece holds nodes " + std::to_string(first_node) +
                                ".." + std::to_string(first_node + static_cast<int>(piece.nodes.size()) - 1) +
                                ", this rank needs " + std::to_string(g0) + ".." + std::to_string(g0 + count - 1));
  const auto begin = piece.nodes.begin() + (g0 - first_node);
  m.nodes.assign(begin, begin + count);
  m.t = piece.t;
  m.undo_ready = false;
}

int DistributedStepper::first_ghosted_node() const { return impl_->mesh->first_ghosted_node(); }
int DistributedStepper::num_ghosted_nodes() const { return impl_->mesh->num_ghosted_nodes(); }

StepReport DistributedStepper::step(double dt) {
  Impl& m = *impl_;
  if (!(dt > 0.0)) throw std::invalid_argument("DistributedStepper::step: dt must be > 0, found " + std::to_string(dt));
  std::vector<rod::RodNode> saved;  // the nodes at t0, copied only if the step is subdivided
  const double t0 = m.t;
  m.undo_ready = false;
  StepReport sr;
  try {
    m.advance(t0, dt, 0, sr, t0, dt, &saved);
  } catch (const std::exception&) {  // StepFailure, PlanarityLost
    if (!saved.empty()) m.nodes = std::move(saved);  // else no attempt changed the nodes
    m.t = t0;
    throw;
  }
  m.t = t0 + dt;  // exactly, whatever the subdivision did
  return sr;
}

bool DistributedStepper::try_step(double dt, StepReport& report) {
  Impl& m = *impl_;
  if (!(dt > 0.0)) throw std::invalid_argument("DistributedStepper::try_step: dt must be > 0, found " + std::to_string(dt));
  const double t0 = m.t;
  const bool ok = m.attempt(t0, dt, report);  // on failure (or a throw) the nodes are as they were
  if (ok) {
    ++report.substeps;
    report.last = m.last;
    m.undo_time = t0;
    m.undo_dt = dt;
    m.undo_ready = true;
  } else {
    ++report.failed_attempts;
    m.t = t0;
  }
  return ok;
}

bool DistributedStepper::redo_step(StepReport& report) {
  Impl& m = *impl_;
  if (!m.undo_ready) throw std::logic_error("DistributedStepper::redo_step: no step to redo");
  const bool ok = m.attempt(m.undo_time, m.undo_dt, report, true);
  if (ok) {
    ++report.substeps;
    report.last = m.last;
  } else {  // back at the step's start
    ++report.failed_attempts;
    m.t = m.undo_time;
    m.undo_ready = false;
  }
  return ok;
}

void DistributedStepper::undo_step() {
  Impl& m = *impl_;
  if (!m.undo_ready) throw std::logic_error("DistributedStepper::undo_step: no step to undo");
  m.nodes = m.me->old_ghosted_nodes();  // the model holds the step's old level
  m.t = m.undo_time;
  m.undo_ready = false;
}

rod::RodState DistributedStepper::ghosted_piece() const {
  rod::RodState s;
  s.t = impl_->t;
  s.ds = impl_->model->ds();
  s.nodes = impl_->nodes;
  return s;
}

double DistributedStepper::time() const { return impl_->t; }
const rod::RodModel& DistributedStepper::model() const { return *impl_->model; }
int DistributedStepper::first_owned_node() const { return impl_->mesh->first_owned_node(); }
int DistributedStepper::num_owned_nodes() const { return impl_->mesh->num_owned_nodes(); }

const rod::RodNode& DistributedStepper::owned_node(int k) const {
  const Impl& m = *impl_;
  if (k < 0 || k >= m.mesh->num_owned_nodes())
    throw std::out_of_range("DistributedStepper::owned_node: index " + std::to_string(k));
  return m.nodes[static_cast<size_t>(m.mesh->first_owned_node() - m.mesh->first_ghosted_node() + k)];
}

rod::RodState DistributedStepper::gather_state() const {
  const Impl& m = *impl_;
  const int nodes = m.model->num_cells + 1;
  std::vector<double> local(static_cast<size_t>(nodes) * kPacked, 0.0), all(local.size());
  for (int k = 0; k < num_owned_nodes(); ++k)
    pack(owned_node(k), &local[static_cast<size_t>(first_owned_node() + k) * kPacked]);
  Teuchos::reduceAll<int, double>(*m.comm, Teuchos::REDUCE_SUM, static_cast<int>(local.size()),
                                  local.data(), all.data());
  rod::RodState s;
  s.t = m.t;
  s.ds = m.model->ds();
  s.nodes.resize(static_cast<size_t>(nodes));
  for (int j = 0; j < nodes; ++j) s.nodes[j] = unpack(&all[static_cast<size_t>(j) * kPacked]);
  return s;
}

const std::string& DistributedStepper::resolved_linear_solver() const { return impl_->choice.resolved; }
const std::string& DistributedStepper::requested_linear_solver() const { return impl_->choice.requested; }
bool DistributedStepper::linear_solver_rerouted() const { return impl_->choice.rerouted; }
const NewtonReport& DistributedStepper::last_newton_report() const { return impl_->last; }
std::string DistributedStepper::newton_implementation() const {
  return impl_->block_newton ? "block storage" : "NOX";
}
const Teuchos::ParameterList& DistributedStepper::parameters() const { return impl_->params; }

ReuseCounters DistributedStepper::reuse_counters() const {
  const Impl& m = *impl_;
  ReuseCounters c;
  c.jacobian_evaluations = m.me->jacobian_evaluations();
  c.residual_evaluations = m.me->residual_evaluations();
  c.assembly_seconds = m.me->assembly_seconds();
  c.linear_setup_seconds = m.me->preconditioner_seconds() + m.direct_stats->seconds;
  c.jacobian_reuses = m.me->jacobian_reuses();
  c.full_newton_retries = m.full_newton_retries;
  c.symbolic_factorizations = m.direct_stats->symbolic;
  c.numeric_factorizations = m.direct_stats->numeric;
  if (m.block_newton) {
    const BlockNewton& b = *m.block_newton;
    c.jacobian_evaluations += b.factorizations();
    c.residual_evaluations += b.residual_evaluations();
    c.assembly_seconds += b.assembly_seconds();
    c.linear_setup_seconds += b.factorization_seconds();
    c.numeric_factorizations += b.factorizations();
  }
  if (auto f = Teuchos::rcp_dynamic_cast<const ReusableIfpack2Factory>(m.me->prec_factory()); !f.is_null()) {
    c.preconditioners_created = f->counters().created;
    c.preconditioner_initializations = f->counters().initialized;
    c.preconditioner_computations = f->counters().computed;
  }
  return c;
}

const void* DistributedStepper::jacobian_address() const { return impl_->me->jacobian_matrix().get(); }
const void* DistributedStepper::graph_address() const {
  return impl_->me->jacobian_matrix()->getCrsGraph().get();
}
const void* DistributedStepper::mesh_graph_address() const { return impl_->mesh->graph().get(); }

}  // namespace traverse::solver

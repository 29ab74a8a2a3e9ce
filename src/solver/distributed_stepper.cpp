#include "traverse/solver/distributed_stepper.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <algorithm>
#include <iostream>
#include <stdexcept>

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
  Teuchos::RCP<Tpetra::Vector<double>> x;
  std::vector<rod::RodNode> nodes;  ///< ghosted range, current level
  double t = 0.0;
  NewtonReport last;
  int max_depth = 4;
  int full_newton_retries = 0;
  std::shared_ptr<DirectSolverStats> direct_stats = std::make_shared<DirectSolverStats>();
  bool reusing_klu2 = false;

  bool attempt(double t0, double dt, StepReport& sr) {
    me->set_old_level(nodes, rod::StepTimes{t0, dt});
    me->old_unknowns(*x);
    last = newton->solve(*x);
    sr.newton_iterations += last.iterations;
    sr.linear_iterations += last.linear_iterations;
    if (!last.converged && me->jacobian_reuse() && me->stale_jacobian_used()) {
      // Modified Newton failed with a kept W: redo this solve with full Newton.
      ++full_newton_retries;
      me->set_full_newton(true);
      me->set_old_level(nodes, rod::StepTimes{t0, dt});
      me->old_unknowns(*x);
      last = newton->solve(*x);
      me->set_full_newton(false);
      sr.newton_iterations += last.iterations;
      sr.linear_iterations += last.linear_iterations;
    }
    if (!last.converged) return false;
    const std::vector<VecX> xg = me->ghosted_unknowns(*x);
    for (size_t k = 0; k < nodes.size(); ++k) nodes[k] = rod::advance_node(*model, nodes[k], xg[k], dt);
    t = t0 + dt;
    return true;
  }

  void advance(double t0, double dt, int depth, StepReport& sr, double t_step, double dt_step) {
    if (attempt(t0, dt, sr)) {
      ++sr.substeps;
      sr.max_depth = std::max(sr.max_depth, depth);
      sr.last = last;
      return;
    }
    ++sr.failed_attempts;
    if (depth >= max_depth) throw StepFailure(t_step, dt_step, t0, dt, depth, last);
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
  m.choice = LinearSolverChoice::resolve(m.params, comm->getSize());
  if (m.choice.rerouted && m.params.get<bool>("Verbose") && comm->getRank() == 0)
    std::cout << "traverse notice: linear solver " << m.choice.resolved << std::endl;

  const rod::RodModel& rm = *m.model;
  m.mesh = Teuchos::rcp(new mesh::DistributedMesh(mesh::Mesh1D(rm.length, rm.num_cells + 1), comm,
                                                  rm.unknowns_per_node()));
  m.me = Teuchos::rcp(new RodStepModel(m.model, m.mesh));
  m.me->set_jacobian_reuse(m.params.get<bool>("Jacobian Reuse"), m.params.get<double>("Jacobian Reuse Contraction"));
  if (m.params.get<std::string>("Direct Solver Path") == "Reuse Symbolic" && comm->getSize() == 1 &&
      is_plain_klu2(m.choice)) {
    RodStepModel* model_ptr = m.me.get();  // owned by the stepper, outlives the factory's use
    m.me->set_W_factory(make_reusing_klu2_factory([model_ptr] { return model_ptr->jacobian_version(); },
                                                  m.direct_stats));
    m.reusing_klu2 = true;
  } else {
    const LinearSolverObjects ls = build_linear_solver(m.choice);
    m.me->set_W_factory(ls.lows);
    m.me->set_prec_factory(ls.prec);
  }
  m.x = Teuchos::rcp(new Tpetra::Vector<double>(m.mesh->dof_map()));
  set_state(rod::straight_rest_state(rm.num_cells, rm.length));
  m.me->set_old_level(m.nodes, rod::StepTimes{m.t, 0.0});
  m.newton = std::make_unique<NewtonSolver>(m.me, m.params);
}

DistributedStepper::~DistributedStepper() = default;

void DistributedStepper::set_state(const rod::RodState& full) {
  Impl& m = *impl_;
  if (full.num_cells() != m.model->num_cells)
    throw std::invalid_argument("DistributedStepper::set_state: the state has " +
                                std::to_string(full.num_cells()) + " cells, the model " +
                                std::to_string(m.model->num_cells));
  const int g0 = m.mesh->first_ghosted_node();
  m.nodes.assign(full.nodes.begin() + g0, full.nodes.begin() + g0 + m.mesh->num_ghosted_nodes());
  m.t = full.t;
}

StepReport DistributedStepper::step(double dt) {
  Impl& m = *impl_;
  if (!(dt > 0.0)) throw std::invalid_argument("DistributedStepper::step: dt must be > 0, found " + std::to_string(dt));
  const std::vector<rod::RodNode> saved = m.nodes;
  const double t0 = m.t;
  StepReport sr;
  try {
    m.advance(t0, dt, 0, sr, t0, dt);
  } catch (const StepFailure&) {
    m.nodes = saved;
    m.t = t0;
    throw;
  }
  m.t = t0 + dt;  // exactly, whatever the subdivision did
  return sr;
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

#include "traverse/solver/distributed_stepper.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <functional>
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
  return a.numParams() == 1;  // "Solver Type" alone
}

}  // namespace

struct DistributedStepper::Impl {
  Teuchos::RCP<const Teuchos::Comm<int>> comm;
  Teuchos::RCP<const mesh::DistributedMesh> mesh;
  Teuchos::RCP<RodStepModel> me;
  std::unique_ptr<NewtonSolver> newton;
  Teuchos::RCP<Tpetra::Vector<double>> x;
  int full_newton_retries = 0;
  std::shared_ptr<DirectSolverStats> direct_stats = std::make_shared<DirectSolverStats>();
  bool reusing_klu2 = false;

  /// Mesh, model evaluator and linear solver for p unknowns per node (the model's, or the
  /// planar reduction's).
  void build(const std::shared_ptr<const rod::RodModel>& model, const std::shared_ptr<const rod::PlanarReduction>& planar,
             const Teuchos::ParameterList& params, const LinearSolverChoice& choice) {
    const rod::RodModel& rm = *model;
    const int p = planar ? planar->unknowns_per_node() : rm.unknowns_per_node();
    newton.reset();
    me = Teuchos::null;
    direct_stats = std::make_shared<DirectSolverStats>();
    reusing_klu2 = false;
    mesh = Teuchos::rcp(new mesh::DistributedMesh(mesh::Mesh1D(rm.length, rm.num_cells + 1), comm, p));
    // The linear solver first: the block LU as the direct solver factorises W's blocks, so the
    // model then assembles straight into them. The factories ask the model (made next, owned
    // here, outliving their use) for its Jacobian's version.
    const std::function<long()> version = [this] { return me->jacobian_version(); };
    Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> lows;
    LinearSolverObjects ls;
    if (params.get<std::string>("Direct Solver Path") == "Reuse Symbolic" && comm->getSize() == 1 &&
        is_plain_klu2(choice)) {
      lows = make_reusing_klu2_factory(version, direct_stats);
      reusing_klu2 = true;
    } else {  // through Stratimikos: Belos, Amesos2, or the block-tridiagonal LU (kBlockTridiagonalLu)
      ls = build_linear_solver(choice, version, direct_stats);
      lows = ls.lows;
    }
    me = Teuchos::rcp(new RodStepModel(model, mesh, planar, is_block_tridiagonal_solve_factory(*lows)));
    me->set_jacobian_reuse(params.get<bool>("Jacobian Reuse"), params.get<double>("Jacobian Reuse Contraction"));
    me->set_W_factory(lows);
    me->set_prec_factory(ls.prec);
    x = Teuchos::rcp(new Tpetra::Vector<double>(mesh->dof_map()));
  }

  /// The Newton solver of the time steps (after build() and set_old_level).
  void build_newton(const Teuchos::ParameterList& np) { newton = std::make_unique<NewtonSolver>(me, np); }

  NewtonReport solve_once(std::vector<VecX>& xg, std::optional<rod::InitialGuess> guess) {
    if (guess) me->initial_guess(*x, *guess);
    NewtonReport r = newton->solve(*x);
    xg = me->ghosted_unknowns(*x);
    return r;
  }
};

DistributedStepper::DistributedStepper(rod::RodModel rod_model,
                                       const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                       const Teuchos::ParameterList& params)
    : RodStepper(std::move(rod_model), params, comm.is_null() ? 1 : comm->getSize(), comm.is_null() ? 0 : comm->getRank()),
      impl_(std::make_unique<Impl>()) {
  if (comm.is_null()) throw std::invalid_argument("DistributedStepper: null communicator");
  Impl& m = *impl_;
  m.comm = comm;
  m.build(shared_model(), planar_reduction(), parameters(), choice());
  set_partition(m.mesh->first_ghosted_node(), m.mesh->num_ghosted_nodes(), m.mesh->first_owned_node(),
                m.mesh->num_owned_nodes());
  const rod::RodModel& rm = model();
  set_state(rod::straight_rest_state(rm.num_cells, rm.length));
  m.me->set_old_level(nodes(), rod::StepTimes{time(), 0.0});
  m.build_newton(newton_params());
}

DistributedStepper::~DistributedStepper() = default;

void DistributedStepper::rebuild() {
  Impl& m = *impl_;
  m.build(shared_model(), planar_reduction(), parameters(), choice());
  m.me->set_old_level(nodes(), rod::StepTimes{time(), 0.0});
  m.build_newton(newton_params());
}

void DistributedStepper::set_old_level(std::vector<rod::RodNode> ghosted_old_nodes, const rod::StepTimes& step) {
  impl_->me->set_old_level(std::move(ghosted_old_nodes), step);
}

const std::vector<rod::RodNode>& DistributedStepper::old_level() const { return impl_->me->old_ghosted_nodes(); }

NewtonReport DistributedStepper::solve_level(std::vector<VecX>& xg, std::optional<rod::InitialGuess> guess,
                                             StepReport& sr) {
  Impl& m = *impl_;
  NewtonReport last = m.solve_once(xg, guess);
  sr.newton_iterations += last.iterations;
  sr.linear_iterations += last.linear_iterations;
  if (!last.converged && m.me->jacobian_reuse() && m.me->stale_jacobian_used()) {
    // Modified Newton failed with a kept W: redo this solve with full Newton.
    ++m.full_newton_retries;
    m.me->set_full_newton(true);
    m.me->set_old_level(m.me->old_ghosted_nodes(), m.me->assembly().step());
    last = m.solve_once(xg, guess.value_or(rod::InitialGuess::old_level));
    m.me->set_full_newton(false);
    sr.newton_iterations += last.iterations;
    sr.linear_iterations += last.linear_iterations;
  }
  return last;
}

double DistributedStepper::dropped_residual_everywhere() const {
  const Impl& m = *impl_;
  const double local = m.me->last_dropped_residual();
  double d = local;
  Teuchos::reduceAll<int, double>(*m.comm, Teuchos::REDUCE_MAX, 1, &local, &d);
  return d;
}

rod::RodState DistributedStepper::gather_state() const {
  const Impl& m = *impl_;
  const int nodes = model().num_cells + 1;
  std::vector<double> local(static_cast<size_t>(nodes) * rod::kPackedNodeValues, 0.0), all(local.size());
  for (int k = 0; k < num_owned_nodes(); ++k)
    rod::pack_node(owned_node(k), &local[static_cast<size_t>(first_owned_node() + k) * rod::kPackedNodeValues]);
  Teuchos::reduceAll<int, double>(*m.comm, Teuchos::REDUCE_SUM, static_cast<int>(local.size()),
                                  local.data(), all.data());
  rod::RodState s;
  s.t = time();
  s.ds = model().ds();
  s.nodes.resize(static_cast<size_t>(nodes));
  for (int j = 0; j < nodes; ++j) s.nodes[j] = rod::unpack_node(&all[static_cast<size_t>(j) * rod::kPackedNodeValues]);
  return s;
}

ReuseCounters DistributedStepper::reuse_counters() const {
  const Impl& m = *impl_;
  ReuseCounters c;
  c.jacobian_evaluations = m.me->jacobian_evaluations();
  c.residual_evaluations = m.me->residual_evaluations();
  c.jacobian_fills = m.me->jacobian_version();
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

const void* DistributedStepper::jacobian_address() const { return impl_->me->create_W_op().get(); }
const void* DistributedStepper::graph_address() const {
  const auto& W = impl_->me->jacobian_matrix();
  return W.is_null() ? nullptr : W->getCrsGraph().get();
}
const void* DistributedStepper::mesh_graph_address() const { return impl_->mesh->graph().get(); }

}  // namespace traverse::solver

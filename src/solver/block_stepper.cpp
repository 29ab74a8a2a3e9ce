// The single-process rod stepper on block storage (block_stepper.hpp).
#include "traverse/solver/block_stepper.hpp"

#include "block_newton.hpp"
#include "traverse/solver/solver_parameters.hpp"

namespace traverse::solver {

bool block_stepper_applies(const ParamList& params) {
  const ParamList p = validated_solver_parameters(params);
  return block_newton_applies(p, LinearSolverChoice::resolve(p, 1, LinearSolverChoice::Use::time_step), 1);
}

struct BlockStepper::Impl {
  std::unique_ptr<rod::StepAssembly> assembly;
  std::unique_ptr<BlockNewton> newton;
  std::vector<double> x;  ///< the unknowns of the system solved
  ReuseCounters done;     ///< of the BlockNewtons of earlier paths

  void build(const std::shared_ptr<const rod::RodModel>& model, const std::shared_ptr<const rod::PlanarReduction>& planar) {
    if (newton) add_block_newton_counters(*newton, done);
    newton.reset();
    const int nodes = model->num_cells + 1;
    assembly = std::make_unique<rod::StepAssembly>(model, planar, 0, nodes, 0, nodes);
  }
  void build_newton(const ParamList& np, const LinearSolverChoice& choice) {
    newton = std::make_unique<BlockNewton>(*assembly, block_newton_options(np, choice));
    x.assign(static_cast<size_t>(assembly->num_owned_nodes()) * assembly->unknowns_per_node(), 0.0);
  }
};

BlockStepper::BlockStepper(rod::RodModel rod_model, const ParamList& params)
    : RodStepper(std::move(rod_model), params, 1, 0), impl_(std::make_unique<Impl>()) {
  if (!block_newton_applies(parameters(), choice(), 1))
    throw std::invalid_argument("BlockStepper: the solver parameters ask for more than the block-tridiagonal LU with "
                                "a full Newton step ('" + choice().resolved + "')");
  const int count = model().num_cells + 1;
  set_partition(0, count, 0, count);
  Impl& m = *impl_;
  m.build(shared_model(), planar_reduction());
  const rod::RodModel& rm = model();
  set_state(rod::straight_rest_state(rm.num_cells, rm.length));
  m.assembly->set_old_level(nodes(), rod::StepTimes{time(), 0.0});
  m.build_newton(newton_params(), choice());
}

BlockStepper::~BlockStepper() = default;

void BlockStepper::rebuild() {
  Impl& m = *impl_;
  m.build(shared_model(), planar_reduction());
  m.assembly->set_old_level(nodes(), rod::StepTimes{time(), 0.0});
  m.build_newton(newton_params(), choice());
}

void BlockStepper::set_old_level(std::vector<rod::RodNode> ghosted_old_nodes, const rod::StepTimes& step) {
  impl_->assembly->set_old_level(std::move(ghosted_old_nodes), step);
}

const std::vector<rod::RodNode>& BlockStepper::old_level() const { return impl_->assembly->old_nodes(); }

NewtonReport BlockStepper::solve_level(std::vector<VecX>& xg, std::optional<rod::InitialGuess> guess, StepReport& sr) {
  Impl& m = *impl_;
  if (guess) m.assembly->initial_guess(m.x.data(), *guess);
  NewtonReport r = m.newton->solve(m.x);
  m.assembly->full_unknowns(m.x.data(), xg);
  sr.newton_iterations += r.iterations;
  return r;
}

double BlockStepper::dropped_residual_everywhere() const { return impl_->newton->last_dropped_residual(); }

rod::RodState BlockStepper::gather_state() const { return ghosted_piece(); }

ReuseCounters BlockStepper::reuse_counters() const {
  ReuseCounters c = impl_->done;
  add_block_newton_counters(*impl_->newton, c);
  return c;
}

}  // namespace traverse::solver

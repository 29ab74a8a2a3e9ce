#include "traverse/solver/rod_step_model.hpp"
#include "thyra_tpetra.hpp"

#include <Thyra_DefaultPreconditioner.hpp>
#include <Thyra_LinearOpSourceBase.hpp>
#include <Thyra_DefaultLinearOpSource.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>
#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace traverse::solver {

namespace {
using namespace tt;  // MEB, LO, GO, Node, Extract
}  // namespace

namespace {
// Unknowns per node of x, f and W: the planar layout's or the model's.
int step_unknowns(const std::shared_ptr<const rod::RodModel>& model,
                  const std::shared_ptr<const rod::PlanarReduction>& planar) {
  if (!model) throw std::invalid_argument("RodStepModel: null model");
  return planar ? planar->unknowns_per_node() : model->unknowns_per_node();
}
}  // namespace

RodStepModel::RodStepModel(std::shared_ptr<const rod::RodModel> model,
                           Teuchos::RCP<const mesh::DistributedMesh> mesh,
                           std::shared_ptr<const rod::PlanarReduction> planar, bool block_storage)
    : BlockAssemblyModel(std::move(mesh), step_unknowns(model, planar), "traverse rod time step", block_storage),
      asm_(model, planar, mesh_->first_ghosted_node(), mesh_->num_ghosted_nodes(), mesh_->first_owned_node(),
           mesh_->num_owned_nodes()) {
  if (mesh_->unknowns_per_node() != p_ || mesh_->mesh().num_nodes() != model->num_cells + 1)
    throw std::invalid_argument(
        "RodStepModel: the mesh must have num_cells + 1 nodes and unknowns_per_node() unknowns per node");
  x0_ = Teuchos::rcp(new Vector(mesh_->dof_map()));
  x0_thyra_ = Thyra::createVector(x0_, x_space_);
  W_at_x_ = Teuchos::rcp(new Vector(mesh_->dof_map()));
}

bool RodStepModel::same_x(const Vector& x) const {
  if (!W_valid_) return false;
  const auto a = x.getData();
  const auto b = W_at_x_->getData();
  int differ = 0;
  for (size_t i = 0; i < static_cast<size_t>(a.size()); ++i)
    if (a[i] != b[i]) {
      differ = 1;
      break;
    }
  int any = 0;
  Teuchos::reduceAll<int, int>(*mesh_->dof_map()->getComm(), Teuchos::REDUCE_MAX, differ, Teuchos::outArg(any));
  return any == 0;
}

void RodStepModel::set_old_level(std::vector<rod::RodNode> ghosted_old_nodes,
                                 const rod::StepTimes& step) {
  asm_.set_old_level(std::move(ghosted_old_nodes), step);
  if (W_requests_ > 0) expected_iterations_ = W_requests_;
  W_requests_ = 0;
  f_evaluations_ = 0;
  W_valid_ = false;  // W at the same x differs now (it depends on the old level)
  f_norms_.clear();
  stale_used_ = false;
}

void RodStepModel::initial_guess(Vector& x, rod::InitialGuess g) const {
  auto data = x.getDataNonConst();
  asm_.initial_guess(data.getRawPtr(), g);
}

std::vector<VecX> RodStepModel::ghosted_unknowns(const Vector& x) const {
  std::vector<VecX> out;
  ghosted_unknowns_into(x, out);
  return out;
}

void RodStepModel::ghosted_unknowns_into(const Vector& x, std::vector<VecX>& out) const {
  auto data = ghosted(x).getData();
  asm_.full_unknowns(data.getRawPtr(), out);
}

void RodStepModel::fill(const Vector& x, Vector* f, bool own_W, Matrix* other_W) const {
  const auto data = ghosted(x).getData();
  // Each block is added into f and W as soon as it is computed (same blocks in the same order
  // as when all were computed first, so the same sums).
  Scatter scatter = other_W ? Scatter(*this, f, other_W) : Scatter(*this, f, own_W);
  const double dropped =
      asm_.for_each_block(data.getRawPtr(), [&](const rod::LocalBlock& b) { scatter.add(b); }, own_W || other_W);
  scatter.finish();
  if (f) {
    dropped_ = dropped;
    ++n_f_;
  }
  if (own_W || other_W) ++W_version_;
}

Thyra::ModelEvaluatorBase::InArgs<double> RodStepModel::getNominalValues() const {
  MEB::InArgs<double> in = createInArgs();
  if (!asm_.old_nodes().empty()) initial_guess(*x0_, rod::InitialGuess::old_level);  // formed when asked for
  in.set_x(x0_thyra_);
  return in;
}

Thyra::ModelEvaluatorBase::InArgs<double> RodStepModel::createInArgs() const {
  MEB::InArgsSetup<double> in;
  in.setModelEvalDescription("traverse rod time step");
  in.setSupports(MEB::IN_ARG_x);
  return std::move(in);
}

Thyra::ModelEvaluatorBase::OutArgs<double> RodStepModel::createOutArgsImpl() const { return out_args_setup(0); }

void RodStepModel::evalModelImpl(const Thyra::ModelEvaluatorBase::InArgs<double>& in,
                                 const Thyra::ModelEvaluatorBase::OutArgs<double>& out) const {
  const Request req = request(in, out);
  const Teuchos::RCP<const Vector>& x = req.x;
  const Teuchos::RCP<Vector>& f = req.f;
  const bool want_prec = req.want_prec;
  const bool want_W = req.W_own || req.W_other || want_prec;
  if (want_W) {
    ++n_W_;
    ++W_requests_;
  }

  // Modified Newton: keep the W already filled (at an earlier iterate or step) unless the last
  // residual contraction of this solve was too weak or full Newton is forced.
  bool keep_W = false;
  if (want_W && reuse_ && W_filled_ && !full_newton_ && !req.W_other) {
    const size_t n = f_norms_.size();
    const bool weak = n >= 2 && f_norms_[n - 1] > contraction_ * f_norms_[n - 2];
    keep_W = !weak;
  }

  // Which W this evaluation fills: another matrix on the graph, or our own unless it was
  // filled at this very x.
  bool fill_own = false;
  Matrix* fill_other = nullptr;
  if (want_W && !keep_W) {
    if (req.W_other) fill_other = req.W_other;
    else fill_own = !same_x(*x);
  }
  // Without Jacobian reuse, a residual evaluation also fills our W: NOX asks for W at the same
  // x next unless the solve has converged there. Solves of consecutive steps take about as many
  // iterations, so at the iterate where the last solve converged the residual alone is
  // evaluated (should NOX ask for W there after all, W is filled then).
  if (f && !want_W) {
    if (!reuse_) fill_own = f_evaluations_ != expected_iterations_;
    ++f_evaluations_;
  }

  const auto t0 = std::chrono::steady_clock::now();
  if (f || fill_own || fill_other) fill(*x, f.get(), fill_own, fill_other);
  const auto t1 = std::chrono::steady_clock::now();
  t_fill_ += std::chrono::duration<double>(t1 - t0).count();
  if (fill_own) {
    Tpetra::deep_copy(*W_at_x_, *x);
    W_valid_ = true;
    W_filled_ = true;
  } else if (fill_other) {
    W_valid_ = false;  // someone else's matrix on our graph: ours is not at x
  }
  if (f && reuse_) f_norms_.push_back(f->normInf());
  if (keep_W) {
    ++n_reused_;
    stale_used_ = true;
    return;  // the preconditioner built from the kept W stays valid
  }
  if (want_prec) {
    initialize_prec(out);
    t_prec_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  }
}

}  // namespace traverse::solver

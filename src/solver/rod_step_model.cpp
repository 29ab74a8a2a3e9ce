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
                           std::shared_ptr<const rod::PlanarReduction> planar)
    : BlockAssemblyModel(std::move(mesh), step_unknowns(model, planar), "traverse rod time step"),
      model_(std::move(model)), planar_(std::move(planar)) {
  full_p_ = model_->unknowns_per_node();
  if (planar_ && planar_->full_unknowns_per_node() != full_p_)
    throw std::invalid_argument("RodStepModel: the planar reduction belongs to another layout");
  if (mesh_->unknowns_per_node() != p_ || mesh_->mesh().num_nodes() != model_->num_cells + 1)
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
  if (static_cast<int>(ghosted_old_nodes.size()) != mesh_->num_ghosted_nodes())
    throw std::invalid_argument("RodStepModel::set_old_level: expected one node per ghosted node");
  old_nodes_ = std::move(ghosted_old_nodes);
  step_ = step;
  // Old-level fluxes: fixed during the step's Newton iterations (the cells use F only).
  F_old_.resize(old_nodes_.size());
  const int g0 = mesh_->first_ghosted_node();
  for (size_t k = 0; k < old_nodes_.size(); ++k)
    F_old_[k] = rod::old_level_flux(*model_, step_, g0 + static_cast<int>(k), old_nodes_[k]).F;
  old_unknowns(*x0_);
  W_valid_ = false;  // W at the same x differs now (it depends on the old level)
  f_norms_.clear();
  stale_used_ = false;
}

void RodStepModel::old_unknowns(Vector& x) const {
  const int off = mesh_->first_owned_node() - mesh_->first_ghosted_node();
  auto data = x.getDataNonConst();
  for (int k = 0; k < mesh_->num_owned_nodes(); ++k) {
    VecX u = rod::node_unknowns(*model_, old_nodes_[static_cast<size_t>(off + k)]);
    if (planar_) u = planar_->restrict_unknowns(u);
    for (int c = 0; c < p_; ++c) data[static_cast<size_t>(k) * p_ + c] = u(c);
  }
}

std::vector<VecX> RodStepModel::ghosted_unknowns(const Vector& x) const {
  std::vector<VecX> out;
  ghosted_unknowns_into(x, out);
  return out;
}

void RodStepModel::ghosted_unknowns_into(const Vector& x, std::vector<VecX>& out) const {
  auto data = ghosted(x).getData();
  out.resize(static_cast<size_t>(mesh_->num_ghosted_nodes()));
  for (size_t k = 0; k < out.size(); ++k) {
    if (planar_) {
      planar_->embed(&data[k * p_], out[k]);
      continue;
    }
    out[k].resize(p_);
    for (int c = 0; c < p_; ++c) out[k](c) = data[k * p_ + c];
  }
}

double RodStepModel::for_each_block(const std::vector<VecX>& xg,
                                    const std::function<void(const rod::LocalBlock&)>& visit) const {
  const int N = model_->num_cells;
  const int first = mesh_->first_owned_node(), last = first + mesh_->num_owned_nodes() - 1;
  const int g0 = mesh_->first_ghosted_node();
  auto O = [&](int j) -> const rod::RodNode& { return old_nodes_[static_cast<size_t>(j - g0)]; };
  auto X = [&](int j) -> const VecX& { return xg[static_cast<size_t>(j - g0)]; };
  // Rows of node k are [p k, p (k+1)): they come from the end blocks and cells k, k+1.
  const int c0 = std::max(1, first), c1 = std::min(N, last + 1);
  // Node j's new-level frame and flux (and its old-level flux), computed once and shared by
  // cells j and j + 1: a window of two nodes, node j in window_[j % 2]. Same arithmetic as
  // cell_block.
  auto levels = [&](int j) -> rod::NodeLevels& {
    rod::NodeLevels& L = window_[static_cast<size_t>(j & 1)];
    rod::new_level_quantities(*model_, step_, j, O(j), X(j), L);
    L.F_old.F = F_old_[static_cast<size_t>(j - g0)];
    return L;
  };
  if (!planar_) {
    if (first == 0) visit(rod::left_block(*model_, step_, O(0), X(0)));
    if (c0 <= c1) levels(c0 - 1);
    for (int j = c0; j <= c1; ++j) {
      const rod::NodeLevels& cur = levels(j);
      rod::cell_block_into(block_, *model_, step_, j, O(j - 1), O(j), X(j - 1), X(j),
                           window_[static_cast<size_t>((j - 1) & 1)], cur);
      visit(block_);
    }
    if (last == N) visit(rod::right_block(*model_, step_, O(N), X(N)));
    return 0.0;
  }
  // Planar layout (row r still belongs to node r / q): the in-plane rows and columns, the cells
  // computed directly in-plane; note the largest dropped (out-of-plane) residual.
  double dropped = 0.0;
  if (first == 0) {
    dropped = std::max(dropped, planar_->restrict_block(rod::left_block(*model_, step_, O(0), X(0)), block_));
    visit(block_);
  }
  if (c0 <= c1) levels(c0 - 1);
  for (int j = c0; j <= c1; ++j) {
    const rod::NodeLevels& cur = levels(j);
    dropped = std::max(dropped, planar_->cell_block_into(block_, *model_, step_, j, O(j - 1), O(j), X(j - 1), X(j),
                                                         window_[static_cast<size_t>((j - 1) & 1)], cur));
    visit(block_);
  }
  if (last == N) {
    dropped = std::max(dropped, planar_->restrict_block(rod::right_block(*model_, step_, O(N), X(N)), block_));
    visit(block_);
  }
  return dropped;
}

void RodStepModel::fill(const Vector& x, Vector* f, Matrix* W) const {
  if (old_nodes_.empty()) throw std::logic_error("RodStepModel: evaluated before set_old_level");
  ghosted_unknowns_into(x, xg_);
  // Each block is added into f and W as soon as it is computed (same blocks in the same order
  // as when all were computed first, so the same sums).
  Scatter scatter(*this, f, W);
  const double dropped = for_each_block(xg_, [&](const rod::LocalBlock& b) { scatter.add(b); });
  scatter.finish();
  if (f) {
    dropped_ = dropped;
    ++n_f_;
  }
  if (W) ++W_version_;
}

Thyra::ModelEvaluatorBase::InArgs<double> RodStepModel::getNominalValues() const {
  MEB::InArgs<double> in = createInArgs();
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
  Matrix* W = req.W;
  const bool want_prec = req.want_prec;
  const bool want_W = W || want_prec;
  if (want_W) ++n_W_;

  // Modified Newton: keep the W already filled (at an earlier iterate or step) unless the last
  // residual contraction of this solve was too weak or full Newton is forced.
  bool keep_W = false;
  if (want_W && reuse_ && W_filled_ && !full_newton_ && (!W || W == W_.get())) {
    const size_t n = f_norms_.size();
    const bool weak = n >= 2 && f_norms_[n - 1] > contraction_ * f_norms_[n - 2];
    keep_W = !weak;
  }

  Matrix* W_fill = nullptr;
  if (want_W && !keep_W) {
    W_fill = W ? W : W_.get();
    if (W_fill == W_.get() && same_x(*x)) W_fill = nullptr;  // W was filled at this very x
  }
  // Without Jacobian reuse, a residual evaluation also fills our W (the kernels compute the
  // Jacobian blocks anyway): NOX asks for W at the same x next, which is then free.
  if (f && !want_W && !reuse_) W_fill = W_.get();

  const auto t0 = std::chrono::steady_clock::now();
  if (f || W_fill) fill(*x, f.get(), W_fill);
  const auto t1 = std::chrono::steady_clock::now();
  t_fill_ += std::chrono::duration<double>(t1 - t0).count();
  if (W_fill == W_.get()) {
    Tpetra::deep_copy(*W_at_x_, *x);
    W_valid_ = true;
    W_filled_ = true;
  } else if (W_fill) {
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

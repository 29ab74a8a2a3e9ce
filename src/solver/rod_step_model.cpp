#include "traverse/solver/rod_step_model.hpp"

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
using MEB = Thyra::ModelEvaluatorBase;
using LO = mesh::LO;
using GO = mesh::GO;
using Node = mesh::Map::node_type;
using Extract = Thyra::TpetraOperatorVectorExtraction<double, LO, GO, Node>;
}  // namespace

RodStepModel::RodStepModel(std::shared_ptr<const rod::RodModel> model,
                           Teuchos::RCP<const mesh::DistributedMesh> mesh,
                           std::shared_ptr<const rod::PlanarReduction> planar)
    : model_(std::move(model)), mesh_(std::move(mesh)), planar_(std::move(planar)) {
  if (!model_ || mesh_.is_null()) throw std::invalid_argument("RodStepModel: null model or mesh");
  full_p_ = model_->unknowns_per_node();
  p_ = planar_ ? planar_->unknowns_per_node() : full_p_;
  if (planar_ && planar_->full_unknowns_per_node() != full_p_)
    throw std::invalid_argument("RodStepModel: the planar reduction belongs to another layout");
  if (mesh_->unknowns_per_node() != p_ || mesh_->mesh().num_nodes() != model_->num_cells + 1)
    throw std::invalid_argument(
        "RodStepModel: the mesh must have num_cells + 1 nodes and unknowns_per_node() unknowns per node");
  row_begin_ = static_cast<Eigen::Index>(p_) * mesh_->first_owned_node();
  row_end_ = row_begin_ + static_cast<Eigen::Index>(p_) * mesh_->num_owned_nodes();
  x_space_ = Thyra::createVectorSpace<double, LO, GO, Node>(mesh_->dof_map());
  W_ = Teuchos::rcp(new Matrix(mesh_->graph()));
  W_->fillComplete();
  W_op_ = Thyra::tpetraLinearOp<double, LO, GO, Node>(x_space_, x_space_, W_);
  x0_ = Teuchos::rcp(new Vector(mesh_->dof_map()));
  x0_thyra_ = Thyra::createVector(x0_, x_space_);
  x_ghosted_ = Teuchos::rcp(new Vector(mesh_->ghosted_dof_map()));
  W_at_x_ = Teuchos::rcp(new Vector(mesh_->dof_map()));
  build_offsets();
}

void RodStepModel::build_offsets() {
  offsets_.clear();
  const auto lcl = W_->getLocalMatrixHost();
  const auto colmap = W_->getColMap();
  const LO rows = static_cast<LO>(row_end_ - row_begin_);
  std::vector<int> off(static_cast<size_t>(rows / p_) * 3, -1);
  for (LO r = 0; r < rows; ++r) {
    const GO node = (static_cast<GO>(row_begin_) + r) / p_;
    const size_t b = lcl.graph.row_map(r), e = lcl.graph.row_map(r + 1);
    int pos[3] = {-1, -1, -1};
    for (size_t k = b; k < e; ++k) {
      const GO g = colmap->getGlobalElement(lcl.graph.entries(k));
      if (g % p_ != 0) continue;
      const GO rel = g / p_ - node + 1;
      if (rel < 0 || rel > 2) return;  // not the expected stencil: keep the generic path
      // The node's p columns must follow in order.
      if (k + static_cast<size_t>(p_) > e) return;
      for (int c = 1; c < p_; ++c)
        if (colmap->getGlobalElement(lcl.graph.entries(k + static_cast<size_t>(c))) != g + c) return;
      pos[rel] = static_cast<int>(k - b);
    }
    // Every row of the node must hold the node blocks at the same positions.
    int* o = &off[static_cast<size_t>(r / p_) * 3];
    for (int rel = 0; rel < 3; ++rel) {
      if (r % p_ == 0) o[rel] = pos[rel];
      else if (o[rel] != pos[rel]) return;
    }
  }
  offsets_ = std::move(off);
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

void RodStepModel::set_W_factory(
    const Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>>& f) {
  W_factory_ = f;
}

void RodStepModel::set_prec_factory(const Teuchos::RCP<Thyra::PreconditionerFactoryBase<double>>& f) {
  prec_factory_ = f;
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
  x_ghosted_->doImport(x, *mesh_->dof_importer(), Tpetra::INSERT);
  auto data = x_ghosted_->getData();
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
  Teuchos::ArrayRCP<double> fd;
  if (f) {
    f->putScalar(0.0);
    fd = f->getDataNonConst();
  }
  // Direct path: add each kernel row's node blocks into W's local values at the precomputed
  // offsets (same graph, same sums as sumIntoGlobalValues; no fillComplete needed since
  // neither the graph nor the maps change). Otherwise sumIntoGlobalValues.
  const bool direct = W && !offsets_.empty() && W == W_.get();
  Matrix::local_matrix_host_type lcl;
  if (direct) {
    lcl = W->getLocalMatrixHost();
    auto vals = lcl.values;
    const size_t nnz = vals.extent(0);
    for (size_t k = 0; k < nnz; ++k) vals(k) = 0.0;
  } else if (W) {
    W->resumeFill();
    W->setAllToScalar(0.0);
  }
  std::vector<GO> cols;
  std::vector<double> gvals;
  const auto visit = [&](const rod::LocalBlock& b) {
    if (f)
      for (Eigen::Index i = 0; i < b.residual.size(); ++i) {
        const Eigen::Index g = b.row + i;
        if (g >= row_begin_ && g < row_end_) fd[static_cast<size_t>(g - row_begin_)] += b.residual(i);
      }
    if (direct) {
      auto vals = lcl.values;
      for (Eigen::Index i = 0; i < b.residual.size(); ++i) {
        const Eigen::Index g = b.row + i;
        if (g < row_begin_ || g >= row_end_) continue;
        const size_t r = static_cast<size_t>(g - row_begin_);
        const size_t row_start = lcl.graph.row_map(r);
        const Eigen::Index node = g / p_;
        for (size_t k = 0; k < b.cols.size(); ++k) {
          const Eigen::Index rel = b.cols[k] / p_ - node + 1;
          const int pos = rel >= 0 && rel <= 2 ? offsets_[r / static_cast<size_t>(p_) * 3 + static_cast<size_t>(rel)] : -1;
          if (pos < 0 || b.cols[k] % p_ != 0 || b.jac[k].cols() != p_)
            throw std::logic_error("RodStepModel: a kernel entry lies outside the mesh graph");
          const size_t o = row_start + static_cast<size_t>(pos);
          const MatX& J = b.jac[k];
          for (int c = 0; c < p_; ++c) vals(o + static_cast<size_t>(c)) += J(i, c);
        }
      }
    } else if (W) {
      for (Eigen::Index i = 0; i < b.residual.size(); ++i) {
        const Eigen::Index g = b.row + i;
        if (g < row_begin_ || g >= row_end_) continue;
        cols.clear();
        gvals.clear();
        for (size_t k = 0; k < b.cols.size(); ++k)
          for (Eigen::Index c = 0; c < b.jac[k].cols(); ++c) {
            cols.push_back(static_cast<GO>(b.cols[k] + c));
            gvals.push_back(b.jac[k](i, c));
          }
        const LO n = W->sumIntoGlobalValues(static_cast<GO>(g), static_cast<LO>(cols.size()), gvals.data(),
                                            cols.data());
        if (n != static_cast<LO>(cols.size()))
          throw std::logic_error("RodStepModel: a kernel entry lies outside the mesh graph");
      }
    }
  };
  const double dropped = for_each_block(xg_, visit);
  if (f) {
    dropped_ = dropped;
    ++n_f_;
  }
  if (W) ++W_version_;
  if (W && !direct) W->fillComplete();
}

Teuchos::RCP<const Thyra::VectorSpaceBase<double>> RodStepModel::get_x_space() const { return x_space_; }
Teuchos::RCP<const Thyra::VectorSpaceBase<double>> RodStepModel::get_f_space() const { return x_space_; }

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

Thyra::ModelEvaluatorBase::OutArgs<double> RodStepModel::createOutArgsImpl() const {
  MEB::OutArgsSetup<double> out;
  out.setModelEvalDescription("traverse rod time step");
  out.setSupports(MEB::OUT_ARG_f);
  out.setSupports(MEB::OUT_ARG_W_op);
  out.setSupports(MEB::OUT_ARG_W_prec, !prec_factory_.is_null());
  return std::move(out);
}

Teuchos::RCP<Thyra::LinearOpBase<double>> RodStepModel::create_W_op() const { return W_op_; }

Teuchos::RCP<Thyra::PreconditionerBase<double>> RodStepModel::create_W_prec() const {
  if (prec_factory_.is_null()) return Teuchos::null;
  return prec_factory_->createPrec();
}

Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> RodStepModel::get_W_factory() const {
  return W_factory_;
}

void RodStepModel::evalModelImpl(const Thyra::ModelEvaluatorBase::InArgs<double>& in,
                                 const Thyra::ModelEvaluatorBase::OutArgs<double>& out) const {
  const Teuchos::RCP<const Vector> x = Extract::getConstTpetraVector(in.get_x());
  Teuchos::RCP<Vector> f;
  if (!out.get_f().is_null()) f = Extract::getTpetraVector(out.get_f());
  Matrix* W = nullptr;
  if (!out.get_W_op().is_null()) {
    auto op = Extract::getTpetraOperator(out.get_W_op());
    W = dynamic_cast<Matrix*>(op.get());
    if (!W || W->getCrsGraph().get() != mesh_->graph().get())
      throw std::invalid_argument("RodStepModel: W_op must be a CrsMatrix on the mesh graph (use create_W_op)");
  }
  const bool want_prec = out.supports(MEB::OUT_ARG_W_prec) && !out.get_W_prec().is_null();
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
    const auto src = Thyra::defaultLinearOpSource<double>(W_op_);
    prec_factory_->initializePrec(src, out.get_W_prec().get(), Thyra::SUPPORT_SOLVE_UNSPECIFIED);
    t_prec_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  }
}

}  // namespace traverse::solver

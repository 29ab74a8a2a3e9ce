#include "traverse/solver/block_assembly_model.hpp"
#include "thyra_tpetra.hpp"
#include "traverse/solver/block_tridiagonal_operator.hpp"

#include <Thyra_DefaultLinearOpSource.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>
#include <algorithm>
#include <stdexcept>

namespace traverse::solver {

namespace {
using namespace tt;  // MEB, LO, GO, Node, Extract
}  // namespace

BlockAssemblyModel::BlockAssemblyModel(Teuchos::RCP<const mesh::DistributedMesh> mesh, int unknowns_per_node,
                                       std::string name, bool block_storage)
    : mesh_(std::move(mesh)), p_(unknowns_per_node), name_(std::move(name)) {
  if (mesh_.is_null()) throw std::invalid_argument(name_ + ": null mesh");
  row_begin_ = static_cast<Eigen::Index>(p_) * mesh_->first_owned_node();
  row_end_ = row_begin_ + static_cast<Eigen::Index>(p_) * mesh_->num_owned_nodes();
  x_space_ = Thyra::createVectorSpace<double, LO, GO, Node>(mesh_->dof_map());
  x_ghosted_ = Teuchos::rcp(new Vector(mesh_->ghosted_dof_map()));
  if (block_storage) {
    W_blocks_ = Teuchos::rcp(new BlockTridiagonalOperator(mesh_, x_space_));
    W_op_ = W_blocks_;
    return;
  }
  W_ = new_matrix();
  W_op_ = Thyra::tpetraLinearOp<double, LO, GO, Node>(x_space_, x_space_, W_);
  build_offsets();
}

Teuchos::RCP<BlockAssemblyModel::Matrix> BlockAssemblyModel::new_matrix() const {
  auto M = Teuchos::rcp(new Matrix(mesh_->graph()));
  M->fillComplete();
  return M;
}

void BlockAssemblyModel::build_offsets() {
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

BlockAssemblyModel::Scatter::Scatter(const BlockAssemblyModel& model, Vector* f, Matrix* W)
    : m_(model), f_(f), W_(W), direct_(W && !model.offsets_.empty() && W == model.W_.get()) {
  if (f_) {
    f_->putScalar(0.0);
    fd_ = f_->getDataNonConst();
  }
  if (direct_) {
    lcl_ = W_->getLocalMatrixHost();
    auto vals = lcl_.values;
    const size_t nnz = vals.extent(0);
    for (size_t k = 0; k < nnz; ++k) vals(k) = 0.0;
  } else if (W_) {
    W_->resumeFill();
    W_->setAllToScalar(0.0);
  }
}

BlockAssemblyModel::Scatter::Scatter(const BlockAssemblyModel& model, Vector* f, bool own_W)
    : Scatter(model, f, own_W && model.W_blocks_.is_null() ? model.W_.get() : nullptr) {
  if (own_W && !model.W_blocks_.is_null()) {
    blocks_ = model.W_blocks_.get();
    blocks_->begin_fill();
  }
}

void BlockAssemblyModel::Scatter::add(const rod::LocalBlock& b) {
  const Eigen::Index r0 = m_.row_begin_, r1 = m_.row_end_;
  const int p = m_.p_;
  if (f_)
    for (Eigen::Index i = 0; i < b.residual.size(); ++i) {
      const Eigen::Index g = b.row + i;
      if (g >= r0 && g < r1) fd_[static_cast<size_t>(g - r0)] += b.residual(i);
    }
  if (blocks_) {
    add_to_blocks(b);
    return;
  }
  if (!W_) return;
  for (Eigen::Index i = 0; i < b.residual.size(); ++i) {
    const Eigen::Index g = b.row + i;
    if (g < r0 || g >= r1) continue;
    if (direct_) {
      auto vals = lcl_.values;
      const size_t r = static_cast<size_t>(g - r0);
      const size_t row_start = lcl_.graph.row_map(r);
      const Eigen::Index node = g / p;
      for (size_t k = 0; k < b.cols.size(); ++k) {
        const Eigen::Index rel = b.cols[k] / p - node + 1;
        const int pos = rel >= 0 && rel <= 2 ? m_.offsets_[r / static_cast<size_t>(p) * 3 + static_cast<size_t>(rel)] : -1;
        if (pos < 0 || b.cols[k] % p != 0 || b.jac[k].cols() != p)
          throw std::logic_error(m_.name_ + ": a kernel entry lies outside the mesh graph");
        const size_t o = row_start + static_cast<size_t>(pos);
        const MatX& J = b.jac[k];
        for (int c = 0; c < p; ++c) vals(o + static_cast<size_t>(c)) += J(i, c);
      }
      continue;
    }
    cols_.clear();
    vals_.clear();
    for (size_t k = 0; k < b.cols.size(); ++k)
      for (Eigen::Index c = 0; c < b.jac[k].cols(); ++c) {
        cols_.push_back(static_cast<GO>(b.cols[k] + c));
        vals_.push_back(b.jac[k](i, c));
      }
    const LO n = W_->sumIntoGlobalValues(static_cast<GO>(g), static_cast<LO>(cols_.size()), vals_.data(), cols_.data());
    if (n != static_cast<LO>(cols_.size()))
      throw std::logic_error(m_.name_ + ": a kernel entry lies outside the mesh graph");
  }
}

void BlockAssemblyModel::Scatter::add_to_blocks(const rod::LocalBlock& b) {
  // The block's owned rows a node at a time: rows [i0, i1) of column block k go to the chunks
  // of their node's block rel (0: previous node, 1: itself, 2: next node).
  const Eigen::Index r0 = m_.row_begin_, r1 = m_.row_end_;
  const int p = m_.p_;
  const Eigen::Index rows = b.residual.size();
  for (Eigen::Index i0 = 0; i0 < rows;) {
    const Eigen::Index g0 = b.row + i0;
    const Eigen::Index i1 = std::min(rows, i0 + p - g0 % p);  // the rows of g0's node
    if (g0 >= r0 && g0 < r1) {
      const Eigen::Index node = g0 / p;
      for (size_t k = 0; k < b.cols.size(); ++k) {
        const Eigen::Index rel = b.cols[k] / p - node + 1;
        const MatX& J = b.jac[k];
        if (rel < 0 || rel > 2 || b.cols[k] % p != 0 || J.cols() != p)
          throw std::logic_error(m_.name_ + ": a kernel entry lies outside the block-tridiagonal pattern");
        blocks_->add_chunk_rows(static_cast<long>(g0 - r0), static_cast<int>(i1 - i0), static_cast<int>(rel),
                                J.data() + i0, static_cast<long>(J.rows()));
      }
    }
    i0 = i1;
  }
}

void BlockAssemblyModel::Scatter::finish() {
  if (blocks_) blocks_->end_fill();
  if (W_ && !direct_) W_->fillComplete();
}

Teuchos::RCP<Thyra::PreconditionerBase<double>> BlockAssemblyModel::create_W_prec() const {
  if (prec_factory_.is_null()) return Teuchos::null;
  return prec_factory_->createPrec();
}

BlockAssemblyModel::Request BlockAssemblyModel::request(const MEB::InArgs<double>& in,
                                                        const MEB::OutArgs<double>& out) const {
  Request r;
  r.x = Extract::getConstTpetraVector(in.get_x());
  if (!out.get_f().is_null()) r.f = Extract::getTpetraVector(out.get_f());
  if (!out.get_W_op().is_null()) {
    if (out.get_W_op().get() == W_op_.get()) {
      r.W_own = true;
    } else {
      auto op = Extract::getTpetraOperator(out.get_W_op());
      r.W_other = dynamic_cast<Matrix*>(op.get());
      if (!r.W_other || r.W_other->getCrsGraph().get() != mesh_->graph().get())
        throw std::invalid_argument(name_ + ": W_op must be a CrsMatrix on the mesh graph (use create_W_op)");
      if (r.W_other == W_.get()) {
        r.W_own = true;
        r.W_other = nullptr;
      }
    }
  }
  r.want_prec = out.supports(MEB::OUT_ARG_W_prec) && !out.get_W_prec().is_null();
  return r;
}

void BlockAssemblyModel::initialize_prec(const MEB::OutArgs<double>& out) const {
  if (W_.is_null())
    throw std::logic_error(name_ + ": a preconditioner factory needs W as a CrsMatrix, not in block storage");
  const auto src = Thyra::defaultLinearOpSource<double>(W_op_);
  prec_factory_->initializePrec(src, out.get_W_prec().get(), Thyra::SUPPORT_SOLVE_UNSPECIFIED);
}

MEB::OutArgsSetup<double> BlockAssemblyModel::out_args_setup(int np) const {
  MEB::OutArgsSetup<double> out;
  out.setModelEvalDescription(name_);
  if (np > 0) out.set_Np_Ng(np, 0);
  out.setSupports(MEB::OUT_ARG_f);
  out.setSupports(MEB::OUT_ARG_W_op);
  out.setSupports(MEB::OUT_ARG_W_prec, !prec_factory_.is_null());
  return out;
}

const BlockAssemblyModel::Vector& BlockAssemblyModel::ghosted(const Vector& x) const {
  x_ghosted_->doImport(x, *mesh_->dof_importer(), Tpetra::INSERT);
  return *x_ghosted_;
}

}  // namespace traverse::solver

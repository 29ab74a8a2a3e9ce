#include "traverse/solver/block_tridiagonal_operator.hpp"
#include "thyra_tpetra.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <stdexcept>

namespace traverse::solver {

namespace {

using tt::Extract;

/// y_k = L_k x_{k-1} + D_k x_k + U_k x_{k+1} for the owned nodes k, x on the ghosted nodes
/// (g0: ghosted index of the first owned node), the chain's ends without the missing term.
/// `half`: L_k's rows past b/2 and U_k's before it are zero and left out.
template <int B>
void block_matvec(const double* blocks, int b, int n, const double* xg, int g0, int ng, bool half, double* y) {
  using Mat = Eigen::Matrix<double, B, B>;
  using Vec = Eigen::Matrix<double, B, 1>;
  // Fixed sizes: coefficient-based products (unrolled), not Eigen's general kernels.
  auto times = [](const double* M, const double* v, int b_, auto&& out, bool add) {
    const Eigen::Map<const Mat> A(M, b_, b_);
    const Eigen::Map<const Vec> x(v, b_);
    if constexpr (B == Eigen::Dynamic) {
      if (add) out.noalias() += A * x;
      else out.noalias() = A * x;
    } else {
      if (add) out.noalias() += A.lazyProduct(x);
      else out.noalias() = A.lazyProduct(x);
    }
  };
  const long bb = static_cast<long>(b) * b;
  for (int k = 0; k < n; ++k) {
    const double* base = blocks + 3 * bb * k;
    const int g = g0 + k;
    Eigen::Map<Vec> yk(y + static_cast<long>(k) * b, b);
    times(base + bb, xg + static_cast<long>(g) * b, b, yk, false);
    if constexpr (B != Eigen::Dynamic && B % 2 == 0) {
      if (half) {
        constexpr int H = B / 2;
        const Eigen::Map<const Mat> L(base), U(base + 2 * bb);
        if (g > 0)
          yk.template head<H>().noalias() +=
              L.template topRows<H>().lazyProduct(Eigen::Map<const Vec>(xg + static_cast<long>(g - 1) * b));
        if (g + 1 < ng)
          yk.template tail<H>().noalias() +=
              U.template bottomRows<H>().lazyProduct(Eigen::Map<const Vec>(xg + static_cast<long>(g + 1) * b));
        continue;
      }
    }
    if (g > 0) times(base, xg + static_cast<long>(g - 1) * b, b, yk, true);
    if (g + 1 < ng) times(base + 2 * bb, xg + static_cast<long>(g + 1) * b, b, yk, true);
  }
}

}  // namespace

BlockTridiagonalOperator::BlockTridiagonalOperator(Teuchos::RCP<const mesh::DistributedMesh> mesh,
                                                   Teuchos::RCP<const Thyra::VectorSpaceBase<double>> space)
    : mesh_(std::move(mesh)), space_(std::move(space)) {
  if (mesh_.is_null() || space_.is_null()) throw std::invalid_argument("BlockTridiagonalOperator: null mesh or space");
  b_ = mesh_->unknowns_per_node();
  n_ = mesh_->num_owned_nodes();
  const size_t size = 3 * static_cast<size_t>(b_) * static_cast<size_t>(b_) * static_cast<size_t>(n_);
  const size_t chunks = 3 * static_cast<size_t>(b_) * static_cast<size_t>(n_);
  for (int k = 0; k < 2; ++k) {
    buf_[k] = std::make_shared<std::vector<double>>(size, 0.0);
    dirty_[k].assign(chunks, 0);
  }
  written_.assign(chunks, 0);
}

void BlockTridiagonalOperator::begin_fill() {
  if (buf_[cur_].use_count() > 1) {  // held by a factorisation: fill the other buffer
    cur_ = 1 - cur_;
    if (buf_[cur_].use_count() > 1) {  // both held: a fresh one for this fill
      buf_[cur_] = std::make_shared<std::vector<double>>(buf_[1 - cur_]->size(), 0.0);
      std::fill(dirty_[cur_].begin(), dirty_[cur_].end(), 0);
      half_[cur_] = false;
      n_dirty_[cur_] = 0;
    }
  }
  std::fill(written_.begin(), written_.end(), 0);
  n_written_ = 0;
  new_chunks_ = false;
}

namespace {

/// dst[c b + i] (=|+=) src[c ld + i] for i < R, c < B: the common chunk shapes (half a node's
/// rows, as a cell's rows split between its two nodes) with loops of fixed length.
template <int R, int B, bool Add>
void copy_chunks(double* dst, const double* src, long ld) {
  for (int c = 0; c < B; ++c)
    for (int i = 0; i < R; ++i) {
      if constexpr (Add) dst[c * B + i] += src[c * ld + i];
      else dst[c * B + i] = src[c * ld + i];
    }
}

template <bool Add>
bool copy_fixed(int b, int rows, double* dst, const double* src, long ld) {
  if (b == 12 && rows == 6) copy_chunks<6, 12, Add>(dst, src, ld);
  else if (b == 6 && rows == 3) copy_chunks<3, 6, Add>(dst, src, ld);
  else return false;
  return true;
}

}  // namespace

void BlockTridiagonalOperator::add_chunk_rows(long r, int rows, int rel, const double* src, long ld) {
  const long b = b_, bb = b * b;
  double* first = buf_[cur_]->data() + 3 * bb * (r / b) + rel * bb + r % b;
  std::uint8_t* w = written_.data() + 3 * r + rel;
  const std::uint8_t* d = dirty_[cur_].data() + 3 * r + rel;
  bool all_new = true, all_old = true;
  for (int i = 0; i < rows; ++i) {
    if (w[3 * i]) {
      all_new = false;
    } else {
      all_old = false;
      ++n_written_;
      if (!d[3 * i]) new_chunks_ = true;
    }
  }
  if (all_new) {
    if (!copy_fixed<false>(b_, rows, first, src, ld))
      for (long c = 0; c < b; ++c)
        for (int i = 0; i < rows; ++i) first[c * b + i] = src[c * ld + i];
  } else if (all_old) {
    if (!copy_fixed<true>(b_, rows, first, src, ld))
      for (long c = 0; c < b; ++c)
        for (int i = 0; i < rows; ++i) first[c * b + i] += src[c * ld + i];
  } else {
    for (int i = 0; i < rows; ++i)
      for (long c = 0; c < b; ++c) first[c * b + i] = (w[3 * i] ? first[c * b + i] : 0.0) + src[c * ld + i];
  }
  for (int i = 0; i < rows; ++i) w[3 * i] = 1;
}

void BlockTridiagonalOperator::end_fill() {
  // The same chunks as the fill before (the kernels' rows do not move): nothing to zero, and
  // the dirty set and half_couplings() stay as they are.
  if (!new_chunks_ && n_written_ == n_dirty_[cur_]) return;
  const long b = b_, bb = b * b;
  double* v = buf_[cur_]->data();
  std::vector<std::uint8_t>& dirty = dirty_[cur_];
  bool half = b % 2 == 0;
  for (size_t k = 0; k < written_.size(); ++k) {
    if (written_[k]) {
      dirty[k] = 1;
      const long row = static_cast<long>(k / 3) % b, rel = static_cast<long>(k % 3);
      if ((rel == 0 && 2 * row >= b) || (rel == 2 && 2 * row < b)) half = false;
    } else if (dirty[k]) {  // reached by an earlier fill, not by this one
      const long r = static_cast<long>(k / 3), rel = static_cast<long>(k % 3);
      double* first = v + 3 * bb * (r / b) + rel * bb + r % b;
      for (long c = 0; c < b; ++c) first[c * b] = 0.0;
      dirty[k] = 0;
    }
  }
  half_[cur_] = half;
  n_dirty_[cur_] = n_written_;
}

void BlockTridiagonalOperator::apply_values(const std::vector<double>& blocks, bool half, const MV& x,
                                            MV& y) const {
  const size_t nv = x.getNumVectors();
  if (ghosted_.is_null() || ghosted_->getNumVectors() != nv)
    ghosted_ = Teuchos::rcp(new MV(mesh_->ghosted_dof_map(), nv));
  ghosted_->doImport(x, *mesh_->dof_importer(), Tpetra::INSERT);
  const int g0 = mesh_->first_owned_node() - mesh_->first_ghosted_node();
  const int ng = mesh_->num_ghosted_nodes();
  for (size_t j = 0; j < nv; ++j) {
    const auto xg = ghosted_->getData(j);
    auto yj = y.getDataNonConst(j);
    switch (b_) {
      case 12: block_matvec<12>(blocks.data(), b_, n_, xg.getRawPtr(), g0, ng, half, yj.getRawPtr()); break;
      case 6: block_matvec<6>(blocks.data(), b_, n_, xg.getRawPtr(), g0, ng, half, yj.getRawPtr()); break;
      default: block_matvec<Eigen::Dynamic>(blocks.data(), b_, n_, xg.getRawPtr(), g0, ng, false, yj.getRawPtr());
    }
  }
}

void BlockTridiagonalOperator::applyImpl(Thyra::EOpTransp t, const Thyra::MultiVectorBase<double>& X,
                                         const Teuchos::Ptr<Thyra::MultiVectorBase<double>>& Y, double alpha,
                                         double beta) const {
  TEUCHOS_TEST_FOR_EXCEPTION(t != Thyra::NOTRANS, std::invalid_argument,
                             "BlockTridiagonalOperator: only NOTRANS is supported");
  const auto x = Extract::getConstTpetraMultiVector(Teuchos::rcpFromRef(X));
  const auto y = Extract::getTpetraMultiVector(Teuchos::rcpFromPtr(Y));
  if (tmp_.is_null() || tmp_->getNumVectors() != x->getNumVectors())
    tmp_ = Teuchos::rcp(new MV(mesh_->dof_map(), x->getNumVectors()));
  apply_values(*buf_[cur_], half_[cur_], *x, *tmp_);
  y->update(alpha, *tmp_, beta);
}

}  // namespace traverse::solver

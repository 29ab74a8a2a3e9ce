#include "block_tridiagonal_preconditioner.hpp"
#include "block_tridiagonal_factors.hpp"
#include "traverse/solver/block_tridiagonal_operator.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace traverse::solver {

namespace {


constexpr int kMaxBlock = 64;

}  // namespace

struct BlockTridiagonalPreconditioner::Impl {
  Teuchos::RCP<const Matrix> A;                    ///< CrsMatrix input (else null)
  Teuchos::RCP<const BlockTridiagonalOperator> op; ///< block-storage input (else null)
  std::shared_ptr<const std::vector<double>> held; ///< op's values last factorised
  bool half = false;                               ///< their couplings are halved (half_coupled)
  Teuchos::RCP<const Teuchos::Comm<int>> comm;
  int b = 1;     ///< block size
  int n = 0;     ///< blocks (nodes) on this rank
  bool exact = false;
  std::string layout;           ///< why the couplings between ranks are dropped (when they are)
  /// Per local matrix entry: its index in its row's three blocks (L, D, U: 3 b^2 values
  /// from the row's block on), or -1 (dropped). 2 bytes per entry (b <= 64).
  std::vector<std::int16_t> dest;
  std::vector<double> blocks;   ///< 3 b^2 per block: L, D, U (copied from A)
  const double* values() const { return op.is_null() ? blocks.data() : held->data(); }
  std::unique_ptr<BlockTridiagonalFactors> factors;
  mutable std::vector<double> tmp;
  /// set_left_end_clamp: the rows replaced (b/2, or 0: none); on the rank holding the first
  /// node, D = (clamp - original) rows over its unknowns and the LU of I - D Z; on every rank
  /// Z_i = (clamped matrix)^-1 e_i, i < rows.
  bool clamp = false;
  int clamp_rows = 0;
  Eigen::MatrixXd D;
  Eigen::PartialPivLU<Eigen::MatrixXd> K;
  std::vector<std::vector<double>> Z;
  bool holds_first() const { return comm->getRank() == 0 && n > 0; }

  int rank() const { return exact ? comm->getRank() : 0; }
  int ranks() const { return exact ? comm->getSize() : 1; }
  /// Every rank's `mine` (all the same length), in rank order.
  std::vector<double> gather(const std::vector<double>& mine) const {
    std::vector<double> all(mine.size() * static_cast<size_t>(comm->getSize()));
    Teuchos::gatherAll<int, double>(*comm, static_cast<int>(mine.size()), mine.data(),
                                    static_cast<int>(all.size()), all.data());
    return all;
  }
};

namespace {

/// 1 on every rank when `ok` holds on every rank.
bool all_ranks(const Teuchos::Comm<int>& comm, bool ok) {
  const int mine = ok ? 1 : 0;
  int all = 0;
  Teuchos::reduceAll<int, int>(comm, Teuchos::REDUCE_MIN, 1, &mine, &all);
  return all == 1;
}

}  // namespace

namespace {

using LO = BlockTridiagonalPreconditioner::LO;
using GO = BlockTridiagonalPreconditioner::GO;

// Block sizes c = 1 .. kMaxBlock (index c) for which this rank's owned rows [first, first +
// nrows) are block tridiagonal (couplings to other ranks' rows are not looked at here).
template <class LocalMatrix, class ColMap>
std::vector<int> fitting_block_sizes(const LocalMatrix& lcl, const ColMap& colmap, GO first, LO nrows) {
  std::vector<int> fits(kMaxBlock + 1, 0);
  for (int c = 1; c <= kMaxBlock; ++c) {
    if (nrows % c != 0 || first % c != 0 || (nrows == 0 && c > 1)) continue;
    const GO b0 = first / c, b1 = (first + nrows) / c;  // owned blocks [b0, b1)
    bool ok = true;
    for (LO r = 0; r < nrows && ok; ++r) {
      const GO br = (first + r) / c;
      for (size_t k = lcl.graph.row_map(r); k < lcl.graph.row_map(r + 1); ++k) {
        const GO bc = colmap->getGlobalElement(lcl.graph.entries(k)) / c;
        if (bc >= b0 && bc < b1 && (bc < br - 1 || bc > br + 1)) {
          ok = false;
          break;
        }
      }
    }
    fits[static_cast<size_t>(c)] = ok ? 1 : 0;
  }
  return fits;
}

// The smallest block size that fits every rank; throws std::invalid_argument saying whose rows
// do not fit.
int agreed_block_size(const Teuchos::Comm<int>& comm, std::vector<int> fits) {
  std::vector<int> fits_all(kMaxBlock + 1, 0);
  Teuchos::reduceAll<int, int>(comm, Teuchos::REDUCE_MIN, kMaxBlock + 1, fits.data(), fits_all.data());
  for (int c = 1; c <= kMaxBlock; ++c)
    if (fits_all[static_cast<size_t>(c)] == 1) return c;
  int c_mine = 0;
  for (int c = 1; c <= kMaxBlock && c_mine == 0; ++c)
    if (fits[static_cast<size_t>(c)] == 1) c_mine = c;
  throw std::invalid_argument("BlockTridiagonalPreconditioner: the rows of " +
                              std::string(c_mine > 0 ? "another rank" : "this rank") +
                              " are not block tridiagonal for any block size up to " + std::to_string(kMaxBlock) +
                              (c_mine > 0 ? " that fits every rank" : ""));
}

// Whether every owned row couples only to its own and the neighbouring blocks of size b.
template <class LocalMatrix, class ColMap>
bool couples_to_neighbours_only(const LocalMatrix& lcl, const ColMap& colmap, GO first, LO nrows, int b) {
  for (LO r = 0; r < nrows; ++r) {
    const GO br = (first + r) / b;
    for (size_t k = lcl.graph.row_map(r); k < lcl.graph.row_map(r + 1); ++k) {
      const GO bc = colmap->getGlobalElement(lcl.graph.entries(k)) / b;
      if (bc < br - 1 || bc > br + 1) return false;
    }
  }
  return true;
}

}  // namespace

namespace {

// Why the ranks' blocks [b0, b1) do not form one chain in rank order (empty when they do).
std::string layout_problem(const Teuchos::Comm<int>& comm, GO b0, GO b1) {
  const int P = comm.getSize();
  const double mine[2] = {static_cast<double>(b0), static_cast<double>(b1)};
  std::vector<double> all(2 * static_cast<size_t>(P));
  Teuchos::gatherAll<int, double>(comm, 2, mine, static_cast<int>(all.size()), all.data());
  for (int r = 0; r < P; ++r) {
    if (all[2 * r + 1] - all[2 * r] < 1) return "rank " + std::to_string(r) + " holds no rows";
    if (r + 1 < P && all[2 * (r + 1)] != all[2 * r + 1]) return "the ranks' blocks are not consecutive in rank order";
  }
  return "";
}

}  // namespace

BlockTridiagonalPreconditioner::BlockTridiagonalPreconditioner() : impl_(std::make_unique<Impl>()) {}

Teuchos::RCP<BlockTridiagonalPreconditioner> BlockTridiagonalPreconditioner::on_blocks(
    Teuchos::RCP<const BlockTridiagonalOperator> A) {
  if (A.is_null()) throw std::invalid_argument("BlockTridiagonalPreconditioner: null operator");
  Teuchos::RCP<BlockTridiagonalPreconditioner> p(new BlockTridiagonalPreconditioner);
  Impl& I = *p->impl_;
  const mesh::DistributedMesh& mesh = A->mesh();
  I.comm = mesh.dof_map()->getComm();
  I.op = A;
  I.b = A->block_size();
  I.n = A->num_nodes();
  const GO b0 = mesh.first_owned_node(), b1 = b0 + mesh.num_owned_nodes();
  I.layout = layout_problem(*I.comm, b0, b1);
  I.exact = I.layout.empty();
  I.factors = make_block_tridiagonal_factors(I.b);
  I.tmp.resize(static_cast<size_t>(I.n) * static_cast<size_t>(I.b));
  return p;
}

BlockTridiagonalPreconditioner::BlockTridiagonalPreconditioner(Teuchos::RCP<const Matrix> A)
    : impl_(std::make_unique<Impl>()) {
  if (A.is_null()) throw std::invalid_argument("BlockTridiagonalPreconditioner: null matrix");
  if (!A->isFillComplete())
    throw std::invalid_argument("BlockTridiagonalPreconditioner: the matrix must be fill-complete");
  const auto rows = A->getRowMap();
  const auto comm = rows->getComm();
  impl_->comm = comm;
  const LO nrows = static_cast<LO>(rows->getNodeNumElements());
  const GO first = nrows > 0 ? rows->getGlobalElement(0) : 0;
  auto same_rows = [&](const Map& m) {
    if (static_cast<LO>(m.getNodeNumElements()) != nrows) return false;
    for (LO i = 0; i < nrows; ++i)
      if (rows->getGlobalElement(i) != first + i || m.getGlobalElement(i) != first + i) return false;
    return true;
  };
  if (!all_ranks(*comm, same_rows(*A->getDomainMap()) && same_rows(*A->getRangeMap())))
    throw std::invalid_argument("BlockTridiagonalPreconditioner: each rank's rows must be one contiguous "
                                "range of global indices, the same in the row, domain and range maps");
  impl_->A = A;
  const auto lcl = A->getLocalMatrixHost();
  const auto colmap = A->getColMap();
  const size_t nnz = lcl.graph.entries.extent(0);
  // Global column of a local entry (looked up when needed: a table of them would be
  // 8 bytes per entry, as much as the values).
  auto gcol = [&](size_t k) { return colmap->getGlobalElement(lcl.graph.entries(k)); };

  // The smallest block size that makes every rank's owned rows block tridiagonal, agreed by
  // all ranks.
  const int b = agreed_block_size(*comm, fitting_block_sizes(lcl, colmap, first, nrows));
  impl_->b = b;
  impl_->n = static_cast<int>(nrows / b);
  const GO b0 = first / b, b1 = (first + nrows) / b;

  // Exact across ranks when the ranks hold consecutive, non-empty pieces of one chain of
  // blocks, in rank order, and couplings to other ranks only between neighbouring blocks;
  // else block Jacobi.
  const bool near = couples_to_neighbours_only(lcl, colmap, first, nrows, b);
  std::string why = layout_problem(*comm, b0, b1);
  if (why.empty() && !all_ranks(*comm, near)) why = "a row couples to a block more than one block away";
  impl_->exact = why.empty();
  impl_->layout = why;
  const long bb = static_cast<long>(b) * b;
  impl_->dest.assign(nnz, -1);
  const GO lo = impl_->exact ? b0 - 1 : b0, hi = impl_->exact ? b1 + 1 : b1;  // kept column blocks [lo, hi)
  for (LO r = 0; r < nrows; ++r) {
    const GO g = first + r;
    const GO br = g / b;
    for (size_t k = lcl.graph.row_map(r); k < lcl.graph.row_map(r + 1); ++k) {
      const GO col = gcol(k);
      const GO bc = col / b;
      if (bc < lo || bc >= hi) continue;  // another rank's node: dropped (block Jacobi)
      const long slot = static_cast<long>(bc - br + 1);
      impl_->dest[k] = static_cast<std::int16_t>(slot * bb + static_cast<long>(col % b) * b + static_cast<long>(g % b));
    }
  }
  impl_->blocks.assign(static_cast<size_t>(3 * bb * impl_->n), 0.0);
  impl_->factors = make_block_tridiagonal_factors(b);
  impl_->tmp.resize(static_cast<size_t>(nrows));
}

BlockTridiagonalPreconditioner::~BlockTridiagonalPreconditioner() = default;

void BlockTridiagonalPreconditioner::compute() {
  auto& I = *impl_;
  if (!I.op.is_null()) {
    I.held = I.op->values();
    I.half = I.op->half_couplings();
  } else {
    std::fill(I.blocks.begin(), I.blocks.end(), 0.0);
    const auto lcl = I.A->getLocalMatrixHost();
    const auto vals = lcl.values;
    if (vals.extent(0) != I.dest.size())
      throw std::logic_error("BlockTridiagonalPreconditioner: the matrix graph changed since construction");
    const size_t bb3 = 3 * static_cast<size_t>(I.b) * static_cast<size_t>(I.b);
    const LO nrows = static_cast<LO>(lcl.graph.row_map.extent(0)) - 1;
    for (LO r = 0; r < nrows; ++r) {
      double* row_blocks = I.blocks.data() + bb3 * static_cast<size_t>(r / I.b);  // the row's L, D, U
      for (size_t k = lcl.graph.row_map(r); k < lcl.graph.row_map(r + 1); ++k)
        if (I.dest[k] >= 0) row_blocks[static_cast<size_t>(I.dest[k])] += vals(k);
    }
    I.clamp_rows = 0;
    if (I.clamp && (I.exact || I.comm->getSize() == 1)) {
      // The first node's first b/2 rows become the clamp [I 0] (they must not couple to the
      // next node); D keeps what the Woodbury correction in apply() needs.
      const int h = I.b / 2;
      const size_t bb = static_cast<size_t>(I.b) * static_cast<size_t>(I.b);
      bool ok = true;
      if (I.holds_first()) {
        double* d0 = I.blocks.data() + bb;
        const double* u0 = I.blocks.data() + 2 * bb;
        I.D.setZero(h, I.b);
        for (int r = 0; r < h; ++r)
          for (int c = 0; c < I.b; ++c) {
            ok = ok && u0[static_cast<size_t>(c * I.b + r)] == 0.0;
            double& a = d0[static_cast<size_t>(c * I.b + r)];
            I.D(r, c) = (r == c ? 1.0 : 0.0) - a;
            a = r == c ? 1.0 : 0.0;
          }
      }
      if (!all_ranks(*I.comm, ok))
        throw std::invalid_argument("block-tridiagonal LU: the left end's rows couple to the next node");
      I.clamp_rows = h;
    }
    I.half = half_coupled(I.blocks.data(), I.n, I.b);
  }
  const auto gather = [&I](const std::vector<double>& v) { return I.gather(v); };
  I.factors->factor(I.values(), I.n, I.b, I.rank(), I.ranks(), gather, I.half);
  if (I.clamp_rows > 0) {
    const size_t len = static_cast<size_t>(I.n) * static_cast<size_t>(I.b);
    I.Z.resize(static_cast<size_t>(I.clamp_rows));  // kept between factorisations, overwritten by each solve
    for (auto& z : I.Z) z.resize(len);
    std::vector<double> e(len, 0.0);
    for (int i = 0; i < I.clamp_rows; ++i) {
      if (I.holds_first()) {
        std::fill(e.begin(), e.end(), 0.0);
        e[static_cast<size_t>(i)] = 1.0;
      }
      I.factors->solve(e.data(), I.Z[static_cast<size_t>(i)].data(), I.values(), gather);
    }
    if (I.holds_first()) {
      Eigen::MatrixXd Z0(I.b, I.clamp_rows);
      for (int i = 0; i < I.clamp_rows; ++i)
        for (int c = 0; c < I.b; ++c) Z0(c, i) = I.Z[static_cast<size_t>(i)][static_cast<size_t>(c)];
      I.K.compute(Eigen::MatrixXd::Identity(I.clamp_rows, I.clamp_rows) - I.D * Z0);
    }
  }
}

void BlockTridiagonalPreconditioner::set_left_end_clamp(bool on) { impl_->clamp = on && impl_->op.is_null(); }

int BlockTridiagonalPreconditioner::block_size() const { return impl_->b; }
bool BlockTridiagonalPreconditioner::exact() const { return impl_->exact; }
const std::string& BlockTridiagonalPreconditioner::why_not_exact() const { return impl_->layout; }
double BlockTridiagonalPreconditioner::min_rcond() const { return impl_->factors->min_rcond(); }
bool BlockTridiagonalPreconditioner::half_couplings() const { return impl_->half; }
const void* BlockTridiagonalPreconditioner::source() const {
  return impl_->op.is_null() ? static_cast<const void*>(impl_->A.get()) : static_cast<const void*>(impl_->op.get());
}

void BlockTridiagonalPreconditioner::apply_matrix(const MV& x, MV& y) const {
  const auto& I = *impl_;
  if (I.op.is_null()) I.A->apply(x, y);
  else I.op->apply_values(*I.held, I.half, x, y);
}

Teuchos::RCP<const BlockTridiagonalPreconditioner::Map> BlockTridiagonalPreconditioner::getDomainMap() const {
  return impl_->op.is_null() ? impl_->A->getDomainMap() : impl_->op->mesh().dof_map();
}
Teuchos::RCP<const BlockTridiagonalPreconditioner::Map> BlockTridiagonalPreconditioner::getRangeMap() const {
  return getDomainMap();
}

void BlockTridiagonalPreconditioner::apply(const MV& X, MV& Y, Teuchos::ETransp mode, double alpha,
                                           double beta) const {
  if (mode != Teuchos::NO_TRANS)
    throw std::invalid_argument("BlockTridiagonalPreconditioner::apply: only NO_TRANS is supported");
  const auto& I = *impl_;
  for (size_t j = 0; j < X.getNumVectors(); ++j) {
    const auto x = X.getData(j);
    auto y = Y.getDataNonConst(j);
    I.factors->solve(x.getRawPtr(), I.tmp.data(), I.values(),
                     [&I](const std::vector<double>& v) { return I.gather(v); });
    if (I.clamp_rows > 0) {  // x = y + Z (I - D Z)^-1 D y, y the clamped matrix's solution
      std::vector<double> c(static_cast<size_t>(I.clamp_rows), 0.0);
      if (I.holds_first()) {
        const Eigen::VectorXd w = I.K.solve(I.D * Eigen::Map<const Eigen::VectorXd>(I.tmp.data(), I.b));
        std::copy(w.data(), w.data() + w.size(), c.begin());
      }
      Teuchos::broadcast<int, double>(*I.comm, 0, I.clamp_rows, c.data());
      for (size_t i = 0; i < c.size(); ++i) {
        const std::vector<double>& z = I.Z[i];
        for (size_t k = 0; k < I.tmp.size(); ++k) I.tmp[k] += c[i] * z[k];
      }
    }
    for (size_t i = 0; i < I.tmp.size(); ++i)
      y[i] = beta == 0.0 ? alpha * I.tmp[i] : beta * y[i] + alpha * I.tmp[i];
  }
}

}  // namespace traverse::solver

#include "block_tridiagonal_preconditioner.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace traverse::solver {

namespace {

/// The block Thomas algorithm for one block size. `blocks` holds, per node k, the three
/// b x b column-major blocks L_k (coupling to node k-1), D_k, U_k (node k+1).
struct FactorsBase {
  virtual ~FactorsBase() = default;
  virtual void factor(const double* blocks, int n, int b) = 0;
  virtual void solve(const double* x, double* y, const double* blocks, int n, int b) const = 0;
  virtual double min_rcond() const = 0;
};

template <int B>
struct Factors final : FactorsBase {
  using Mat = Eigen::Matrix<double, B, B>;
  using Vec = Eigen::Matrix<double, B, 1>;
  using CMap = Eigen::Map<const Mat>;

  std::vector<Eigen::PartialPivLU<Mat>> lu;  ///< LU of the Schur complements S_k
  std::vector<Mat> C;                        ///< S_k^{-1} U_k

  void factor(const double* blocks, int n, int b) override {
    const Eigen::Index bb = static_cast<Eigen::Index>(b) * b;
    lu.resize(static_cast<size_t>(n));
    C.resize(static_cast<size_t>(n));
    Mat S(b, b);
    for (int k = 0; k < n; ++k) {
      const double* base = blocks + 3 * bb * k;
      S = CMap(base + bb, b, b);
      if (k > 0) S.noalias() -= CMap(base, b, b) * C[static_cast<size_t>(k - 1)];
      auto& f = lu[static_cast<size_t>(k)];
      f.compute(S);
      if (k + 1 < n) C[static_cast<size_t>(k)] = f.solve(CMap(base + 2 * bb, b, b));
    }
  }

  void solve(const double* x, double* y, const double* blocks, int n, int b) const override {
    const Eigen::Index bb = static_cast<Eigen::Index>(b) * b;
    Vec z(b);
    for (int k = 0; k < n; ++k) {
      z = Eigen::Map<const Vec>(x + static_cast<Eigen::Index>(k) * b, b);
      if (k > 0)
        z.noalias() -= CMap(blocks + 3 * bb * k, b, b) *
                       Eigen::Map<const Vec>(y + static_cast<Eigen::Index>(k - 1) * b, b);
      Eigen::Map<Vec>(y + static_cast<Eigen::Index>(k) * b, b) = lu[static_cast<size_t>(k)].solve(z);
    }
    for (int k = n - 2; k >= 0; --k)
      Eigen::Map<Vec>(y + static_cast<Eigen::Index>(k) * b, b).noalias() -=
          C[static_cast<size_t>(k)] * Eigen::Map<const Vec>(y + static_cast<Eigen::Index>(k + 1) * b, b);
  }

  double min_rcond() const override {  // a diagnostic: estimated on request, not per factorisation
    double r = 1.0;
    for (const auto& f : lu) r = std::min(r, f.rcond());
    return r;
  }
};

std::unique_ptr<FactorsBase> make_factors(int b) {
  switch (b) {
    case 6: return std::make_unique<Factors<6>>();
    case 12: return std::make_unique<Factors<12>>();
    case 24: return std::make_unique<Factors<24>>();
    default: return std::make_unique<Factors<Eigen::Dynamic>>();
  }
}

constexpr int kMaxBlock = 64;

}  // namespace

struct BlockTridiagonalPreconditioner::Impl {
  Teuchos::RCP<const Matrix> A;
  int b = 1;     ///< block size
  int n = 0;     ///< blocks (nodes) on this rank
  std::vector<long> dest;       ///< per local matrix entry: index in `blocks`, or -1 (other rank)
  std::vector<double> blocks;   ///< 3 b^2 per block: L, D, U
  std::unique_ptr<FactorsBase> factors;
  mutable std::vector<double> tmp;
};

BlockTridiagonalPreconditioner::BlockTridiagonalPreconditioner(Teuchos::RCP<const Matrix> A)
    : impl_(std::make_unique<Impl>()) {
  if (A.is_null()) throw std::invalid_argument("BlockTridiagonalPreconditioner: null matrix");
  if (!A->isFillComplete())
    throw std::invalid_argument("BlockTridiagonalPreconditioner: the matrix must be fill-complete");
  const auto rows = A->getRowMap();
  const LO nrows = static_cast<LO>(rows->getNodeNumElements());
  const GO first = nrows > 0 ? rows->getGlobalElement(0) : 0;
  auto same_rows = [&](const Map& m) {
    if (static_cast<LO>(m.getNodeNumElements()) != nrows) return false;
    for (LO i = 0; i < nrows; ++i)
      if (rows->getGlobalElement(i) != first + i || m.getGlobalElement(i) != first + i) return false;
    return true;
  };
  if (!same_rows(*A->getDomainMap()) || !same_rows(*A->getRangeMap()))
    throw std::invalid_argument("BlockTridiagonalPreconditioner: each rank's rows must be one contiguous "
                                "range of global indices, the same in the row, domain and range maps");
  impl_->A = A;
  const auto lcl = A->getLocalMatrixHost();
  const auto colmap = A->getColMap();
  const size_t nnz = lcl.graph.entries.extent(0);
  std::vector<GO> gcol(nnz);
  for (size_t k = 0; k < nnz; ++k) gcol[k] = colmap->getGlobalElement(lcl.graph.entries(k));

  // The smallest block size that makes the owned rows block tridiagonal.
  int b = 0;
  for (int c = 1; c <= std::min<LO>(kMaxBlock, std::max<LO>(nrows, 1)) && b == 0; ++c) {
    if (nrows % c != 0 || first % c != 0) continue;
    const GO b0 = first / c, b1 = (first + nrows) / c;  // owned blocks [b0, b1)
    bool ok = true;
    for (LO r = 0; r < nrows && ok; ++r) {
      const GO br = (first + r) / c;
      for (size_t k = lcl.graph.row_map(r); k < lcl.graph.row_map(r + 1); ++k) {
        const GO bc = gcol[k] / c;
        if (bc >= b0 && bc < b1 && (bc < br - 1 || bc > br + 1)) {
          ok = false;
          break;
        }
      }
    }
    if (ok) b = c;
  }
  if (b == 0)
    throw std::invalid_argument("BlockTridiagonalPreconditioner: the rows of this rank are not block "
                                "tridiagonal for any block size up to " +
                                std::to_string(kMaxBlock));
  impl_->b = b;
  impl_->n = static_cast<int>(nrows / b);
  const long bb = static_cast<long>(b) * b;
  impl_->dest.assign(nnz, -1);
  const GO b0 = first / b, b1 = (first + nrows) / b;
  for (LO r = 0; r < nrows; ++r) {
    const GO g = first + r;
    const GO br = g / b;
    for (size_t k = lcl.graph.row_map(r); k < lcl.graph.row_map(r + 1); ++k) {
      const GO bc = gcol[k] / b;
      if (bc < b0 || bc >= b1) continue;  // another rank's node: dropped (block Jacobi)
      const long slot = static_cast<long>(bc - br + 1);
      impl_->dest[k] = (3 * static_cast<long>(br - b0) + slot) * bb + static_cast<long>(gcol[k] % b) * b +
                       static_cast<long>(g % b);
    }
  }
  impl_->blocks.assign(static_cast<size_t>(3 * bb * impl_->n), 0.0);
  impl_->factors = make_factors(b);
  impl_->tmp.resize(static_cast<size_t>(nrows));
}

BlockTridiagonalPreconditioner::~BlockTridiagonalPreconditioner() = default;

void BlockTridiagonalPreconditioner::compute() {
  auto& I = *impl_;
  std::fill(I.blocks.begin(), I.blocks.end(), 0.0);
  const auto lcl = I.A->getLocalMatrixHost();
  const auto vals = lcl.values;
  if (vals.extent(0) != I.dest.size())
    throw std::logic_error("BlockTridiagonalPreconditioner: the matrix graph changed since construction");
  for (size_t k = 0; k < I.dest.size(); ++k)
    if (I.dest[k] >= 0) I.blocks[static_cast<size_t>(I.dest[k])] += vals(k);
  I.factors->factor(I.blocks.data(), I.n, I.b);
}

int BlockTridiagonalPreconditioner::block_size() const { return impl_->b; }
double BlockTridiagonalPreconditioner::min_rcond() const { return impl_->factors->min_rcond(); }
const Teuchos::RCP<const BlockTridiagonalPreconditioner::Matrix>& BlockTridiagonalPreconditioner::matrix() const {
  return impl_->A;
}

Teuchos::RCP<const BlockTridiagonalPreconditioner::Map> BlockTridiagonalPreconditioner::getDomainMap() const {
  return impl_->A->getDomainMap();
}
Teuchos::RCP<const BlockTridiagonalPreconditioner::Map> BlockTridiagonalPreconditioner::getRangeMap() const {
  return impl_->A->getRangeMap();
}

void BlockTridiagonalPreconditioner::apply(const MV& X, MV& Y, Teuchos::ETransp mode, double alpha,
                                           double beta) const {
  if (mode != Teuchos::NO_TRANS)
    throw std::invalid_argument("BlockTridiagonalPreconditioner::apply: only NO_TRANS is supported");
  const auto& I = *impl_;
  for (size_t j = 0; j < X.getNumVectors(); ++j) {
    const auto x = X.getData(j);
    auto y = Y.getDataNonConst(j);
    I.factors->solve(x.getRawPtr(), I.tmp.data(), I.blocks.data(), I.n, I.b);
    for (size_t i = 0; i < I.tmp.size(); ++i)
      y[i] = beta == 0.0 ? alpha * I.tmp[i] : beta * y[i] + alpha * I.tmp[i];
  }
}

}  // namespace traverse::solver

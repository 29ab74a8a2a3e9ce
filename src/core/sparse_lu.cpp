// Direct solves with a sparse square matrix (sparse_lu.hpp).
#include "traverse/core/sparse_lu.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace traverse {

void BandedLU::bandwidths(const Eigen::SparseMatrix<double>& A, int& kl, int& ku) {
  kl = 0;
  ku = 0;
  for (int c = 0; c < A.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) {
      const int r = static_cast<int>(it.row());
      kl = std::max(kl, r - c);
      ku = std::max(ku, c - r);
    }
}

bool BandedLU::factorize(const Eigen::SparseMatrix<double>& A) {
  int kl = 0, ku = 0;
  bandwidths(A, kl, ku);
  return factorize(A, kl, ku);
}

bool BandedLU::factorize(const Eigen::SparseMatrix<double>& A, int kl, int ku) {
  if (A.rows() != A.cols()) throw std::invalid_argument("BandedLU: the matrix is not square");
  n_ = static_cast<int>(A.rows());
  kl_ = kl;
  ku_ = ku;
  kv_ = kl_ + ku_;  // U's super-diagonals after the row interchanges
  ld_ = static_cast<size_t>(2 * kl_ + ku_ + 1);
  ab_.assign(ld_ * static_cast<size_t>(n_), 0.0);
  pivot_.assign(static_cast<size_t>(n_), 0);
  swaps_ = 0;
  for (int c = 0; c < A.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) at(static_cast<int>(it.row()), c) += it.value();
  int last = 0;  // the last column the interchanges so far reach
  for (int j = 0; j < n_; ++j) {
    const int below = std::min(kl_, n_ - 1 - j);
    int p = 0;
    double biggest = std::abs(at(j, j));
    for (int i = 1; i <= below; ++i)
      if (std::abs(at(j + i, j)) > biggest) {
        biggest = std::abs(at(j + i, j));
        p = i;
      }
    if (!(biggest > 0.0) || !std::isfinite(biggest)) return false;
    pivot_[static_cast<size_t>(j)] = j + p;
    last = std::max(last, std::min(j + ku_ + p, n_ - 1));
    if (p != 0) {
      ++swaps_;
      for (int c = j; c <= last; ++c) std::swap(at(j, c), at(j + p, c));
    }
    const double inverse = 1.0 / at(j, j);
    for (int i = 1; i <= below; ++i) at(j + i, j) *= inverse;
    for (int c = j + 1; c <= last; ++c) {
      const double u = at(j, c);
      if (u == 0.0) continue;
      for (int i = 1; i <= below; ++i) at(j + i, c) -= at(j + i, j) * u;
    }
  }
  return true;
}

VecX BandedLU::solve(const VecX& b) const {
  VecX x = b;
  for (int j = 0; j < n_; ++j) {  // L y = P b
    const int p = pivot_[static_cast<size_t>(j)];
    if (p != j) std::swap(x(j), x(p));
    const int below = std::min(kl_, n_ - 1 - j);
    for (int i = 1; i <= below; ++i) x(j + i) -= at(j + i, j) * x(j);
  }
  for (int j = n_ - 1; j >= 0; --j) {  // U x = y
    x(j) /= at(j, j);
    for (int i = std::max(0, j - kv_); i < j; ++i) x(i) -= at(i, j) * x(j);
  }
  return x;
}

double BandedLU::log_abs_determinant() const {
  double s = 0.0;
  for (int j = 0; j < n_; ++j) s += std::log(std::abs(at(j, j)));
  return s;
}

double BandedLU::sign_determinant() const {
  int negative = swaps_;
  for (int j = 0; j < n_; ++j) negative += at(j, j) < 0.0;
  return negative % 2 ? -1.0 : 1.0;
}

bool SparseLUSolver::factorize(const Eigen::SparseMatrix<double>& A, bool same_pattern) {
  int kl = 0, ku = 0;
  BandedLU::bandwidths(A, kl, ku);
  const double band = static_cast<double>(2 * kl + ku + 1) * static_cast<double>(A.rows());
  banded_ = band <= 16.0 * static_cast<double>(std::max<Eigen::Index>(A.nonZeros(), 1));
  if (banded_) {
    analysed_ = false;  // the pattern analysis (if any) was of another matrix
    return band_.factorize(A, kl, ku);
  }
  if (!A.isCompressed()) {
    Eigen::SparseMatrix<double> C = A;
    C.makeCompressed();
    return factorize(C, same_pattern);
  }
  if (!same_pattern || !analysed_) sparse_.analyzePattern(A);
  analysed_ = true;
  sparse_.factorize(A);
  return sparse_.info() == Eigen::Success;
}

VecX SparseLUSolver::solve(const VecX& b) const {
  return banded_ ? band_.solve(b) : VecX(sparse_.solve(b));
}

double SparseLUSolver::log_abs_determinant() const {
  return banded_ ? band_.log_abs_determinant() : sparse_.logAbsDeterminant();
}

double SparseLUSolver::sign_determinant() const {
  return banded_ ? band_.sign_determinant() : sparse_.signDeterminant();
}

}  // namespace traverse

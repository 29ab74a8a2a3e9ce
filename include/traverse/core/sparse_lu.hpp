#pragma once
// Direct solves with a sparse square matrix in one process: an LU with partial pivoting in
// band storage when the nonzeros lie in a narrow band about the diagonal (the static Jacobians
// of a rod, whose rows couple the unknowns of neighbouring nodes), Eigen's SparseLU otherwise.
// For a rod's few hundred to few thousand unknowns the banded LU is 5 to 16 times cheaper than
// SparseLU's factorisation alone and 16 to 25 times cheaper with its pattern analysis
// (docs/benchmarks.md, "The static solves in band storage"). No Trilinos, no MPI.
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <vector>

#include "traverse/core/types.hpp"

namespace traverse {

/// LU with partial pivoting (row interchanges within the band, as LAPACK's dgbtrf) of a
/// matrix with kl sub- and ku super-diagonals; U then has kl + ku super-diagonals. Work
/// n kl (kl + ku), storage n (2 kl + ku + 1).
class BandedLU {
 public:
  /// The lower and upper bandwidths of `A`'s nonzero pattern.
  static void bandwidths(const Eigen::SparseMatrix<double>& A, int& kl, int& ku);
  /// Factorises `A` (square). False when a pivot is zero or not finite (`A` singular to
  /// working precision or not finite); solve and the determinant are then meaningless.
  bool factorize(const Eigen::SparseMatrix<double>& A);
  /// The same with `A`'s bandwidths already known (bandwidths()).
  bool factorize(const Eigen::SparseMatrix<double>& A, int kl, int ku);
  /// x with A x = b.
  VecX solve(const VecX& b) const;
  /// log |det A| and the sign of det A (+1 or -1).
  double log_abs_determinant() const;
  double sign_determinant() const;
  int lower() const { return kl_; }
  int upper() const { return ku_; }

 private:
  double& at(int row, int col) { return ab_[static_cast<size_t>(kv_ + row - col) + static_cast<size_t>(col) * ld_]; }
  double at(int row, int col) const {
    return ab_[static_cast<size_t>(kv_ + row - col) + static_cast<size_t>(col) * ld_];
  }
  int n_ = 0, kl_ = 0, ku_ = 0, kv_ = 0;
  size_t ld_ = 1;
  std::vector<double> ab_;
  std::vector<int> pivot_;
  int swaps_ = 0;
};

/// The LU of a sparse square matrix: BandedLU when the band storage holds at most 16 times
/// the nonzeros (a rod's Jacobians: about 7), else Eigen's SparseLU (COLAMD ordering).
class SparseLUSolver {
 public:
  /// Factorises `A`; `same_pattern`: `A` has the nonzero pattern of the previous call (Eigen's
  /// pattern analysis is then reused). False when `A` is singular to working precision.
  bool factorize(const Eigen::SparseMatrix<double>& A, bool same_pattern = false);
  VecX solve(const VecX& b) const;
  double log_abs_determinant() const;
  double sign_determinant() const;
  /// Whether the last factorisation was the banded one.
  bool banded() const { return banded_; }

 private:
  bool banded_ = false, analysed_ = false;
  BandedLU band_;
  mutable Eigen::SparseLU<Eigen::SparseMatrix<double>> sparse_;  // its signDeterminant() is not const
};

}  // namespace traverse

// The banded LU with partial pivoting against Eigen's dense LU, and the choice between it and
// Eigen's SparseLU (include/traverse/core/sparse_lu.hpp).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "traverse/core/sparse_lu.hpp"

using traverse::BandedLU;
using traverse::SparseLUSolver;
using traverse::VecX;
using SpMat = Eigen::SparseMatrix<double>;

namespace {

// A random n x n matrix with kl sub- and ku super-diagonals; with both, every third diagonal
// entry zero, so that the LU must interchange rows (a triangular one would be singular); the
// other diagonal entries at least 2 in magnitude (random triangular matrices are ill-conditioned).
SpMat random_band(int n, int kl, int ku, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < n; ++j)
    for (int i = std::max(0, j - ku); i <= std::min(n - 1, j + kl); ++i)
      if (i != j) {
        t.emplace_back(i, j, u(gen));
      } else if (!(j % 3 == 0 && kl > 0 && ku > 0)) {
        const double d = u(gen);
        t.emplace_back(i, j, d + std::copysign(2.0, d));  // well conditioned where it is kept
      }
  SpMat A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

double relative_residual(const SpMat& A, const VecX& x, const VecX& b) {
  const Eigen::MatrixXd D(A);
  return (D * x - b).cwiseAbs().maxCoeff() / (D.cwiseAbs().rowwise().sum().maxCoeff() * x.cwiseAbs().maxCoeff());
}

}  // namespace

TEST(BandedLU, SolvesAndDeterminantAsTheDenseLU) {
  for (const auto& [kl, ku] : {std::pair{3, 5}, std::pair{7, 7}, std::pair{0, 2}, std::pair{4, 0}}) {
    const int n = 200;
    const SpMat A = random_band(n, kl, ku, 17u + static_cast<unsigned>(kl * 10 + ku));
    BandedLU lu;
    ASSERT_TRUE(lu.factorize(A));
    EXPECT_EQ(lu.lower(), kl);
    EXPECT_EQ(lu.upper(), ku);
    const VecX b = VecX::LinSpaced(n, -1.0, 2.0);
    const VecX x = lu.solve(b);
    const Eigen::PartialPivLU<Eigen::MatrixXd> dense{Eigen::MatrixXd(A)};
    const VecX xd = dense.solve(b);
    const double res = relative_residual(A, x, b), diff = (x - xd).cwiseAbs().maxCoeff() / xd.cwiseAbs().maxCoeff();
    std::printf("kl %d ku %d: relative residual %.2e, against the dense LU %.2e\n", kl, ku, res, diff);
    EXPECT_LT(res, 1e-13);
    EXPECT_LT(diff, 1e-12);
    // det from the dense LU's diagonal and its permutation's sign
    const Eigen::MatrixXd U = dense.matrixLU().triangularView<Eigen::Upper>();
    double log_det = 0.0, sign = dense.permutationP().determinant();
    for (int j = 0; j < n; ++j) {
      log_det += std::log(std::abs(U(j, j)));
      if (U(j, j) < 0.0) sign = -sign;
    }
    EXPECT_NEAR(lu.log_abs_determinant(), log_det, 1e-10 * std::abs(log_det) + 1e-10);
    EXPECT_EQ(lu.sign_determinant(), sign);
  }
}

TEST(BandedLU, SingularAndNotSquareRefused) {
  SpMat A = random_band(50, 2, 2, 3u);
  // column 10 zero: singular
  for (SpMat::InnerIterator it(A, 10); it; ++it) it.valueRef() = 0.0;
  BandedLU lu;
  EXPECT_FALSE(lu.factorize(A));
  EXPECT_THROW(lu.factorize(SpMat(4, 5)), std::invalid_argument);
}

TEST(SparseLUSolver, BandedWhereTheBandIsNarrowSparseLUElsewhere) {
  const int n = 400;
  const SpMat A = random_band(n, 2, 3, 5u);
  SparseLUSolver s;
  ASSERT_TRUE(s.factorize(A));
  EXPECT_TRUE(s.banded());
  const VecX b = VecX::Ones(n);
  EXPECT_LT(relative_residual(A, s.solve(b), b), 1e-13);
  // One entry far from the diagonal (a periodic coupling): the band would be the whole matrix.
  SpMat W = A;
  W.coeffRef(0, n - 1) = 0.5;
  W.coeffRef(n - 1, 0) = -0.25;
  ASSERT_TRUE(s.factorize(W));
  EXPECT_FALSE(s.banded());
  const VecX x = s.solve(b);
  EXPECT_LT(relative_residual(W, x, b), 1e-13);
  // again with the same pattern (the analysis reused), new values
  SpMat W2 = W * 2.0;
  ASSERT_TRUE(s.factorize(W2, true));
  EXPECT_LT((s.solve(b) - 0.5 * x).cwiseAbs().maxCoeff(), 1e-12 * x.cwiseAbs().maxCoeff());
  // Both give the dense LU's determinant.
  const double dense = std::log(std::abs(Eigen::MatrixXd(W).determinant()));
  ASSERT_TRUE(s.factorize(W));
  EXPECT_NEAR(s.log_abs_determinant(), dense, 1e-9 * std::abs(dense));
  BandedLU band;
  ASSERT_TRUE(band.factorize(W));  // the banded LU solves it too, with a band as wide as the matrix
  EXPECT_NEAR(band.log_abs_determinant(), dense, 1e-9 * std::abs(dense));
  EXPECT_EQ(band.sign_determinant(), s.sign_determinant());
  EXPECT_LT(relative_residual(W, band.solve(b), b), 1e-13);
}

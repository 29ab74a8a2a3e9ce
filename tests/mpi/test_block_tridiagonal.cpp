// The block-tridiagonal LU preconditioner (src/solver/block_tridiagonal_preconditioner.*) on
// 1 and 2 ranks: block size found from the graph, exact solve of each rank's rows (the
// couplings to other ranks dropped), pivoting inside a block, refactorisation on new values,
// and a clear error for a matrix that is not block tridiagonal.
#include <gtest/gtest.h>

#include <Teuchos_DefaultMpiComm.hpp>
#include <Tpetra_Core.hpp>

#include <cmath>
#include <random>
#include <stdexcept>

#include "block_tridiagonal_preconditioner.hpp"

namespace traverse::solver {
namespace {

using Prec = BlockTridiagonalPreconditioner;
using Matrix = Prec::Matrix;
using LO = Prec::LO;
using GO = Prec::GO;
using MV = Prec::MV;
using Map = Prec::Map;

Teuchos::RCP<const Teuchos::Comm<int>> comm() { return Tpetra::getDefaultComm(); }

/// Nodes split contiguously over the ranks, b unknowns per node.
Teuchos::RCP<const Map> node_map(int nodes, int b) {
  const int p = comm()->getSize(), r = comm()->getRank();
  const int mine = nodes / p + (r < nodes % p ? 1 : 0);
  return Teuchos::rcp(new Map(static_cast<GO>(nodes) * b, static_cast<size_t>(mine) * b, 0, comm()));
}

/// A random block-tridiagonal matrix (b x b blocks). keep_off_rank = false drops the
/// entries whose column belongs to another rank (the matrix the preconditioner inverts).
/// zero_diagonal: each diagonal block has zeros on its diagonal (LU needs row exchanges).
Teuchos::RCP<Matrix> random_matrix(const Teuchos::RCP<const Map>& map, int b, double scale,
                                   bool keep_off_rank, bool zero_diagonal, unsigned seed) {
  const GO n = static_cast<GO>(map->getGlobalNumElements());
  const GO nodes = n / b;
  auto A = Teuchos::rcp(new Matrix(map, 3 * b));
  const GO lo = map->getMinGlobalIndex(), hi = map->getMaxGlobalIndex();
  for (LO i = 0; i < static_cast<LO>(map->getNodeNumElements()); ++i) {
    const GO g = map->getGlobalElement(i), k = g / b;
    std::mt19937 gen(seed + static_cast<unsigned>(g));  // the same row on any rank count
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    std::vector<GO> cols;
    std::vector<double> vals;
    for (GO m = std::max<GO>(0, k - 1); m <= std::min<GO>(nodes - 1, k + 1); ++m)
      for (int c = 0; c < b; ++c) {
        const GO col = m * b + c;
        double v = U(gen);
        if (m == k && col == g) v = zero_diagonal ? 0.0 : v + scale;
        if (m == k && zero_diagonal && (g % b + 1) % b == c) v += scale;  // a shifted "diagonal"
        if (!keep_off_rank && (col < lo || col > hi)) continue;
        cols.push_back(col);
        vals.push_back(v);
      }
    A->insertGlobalValues(g, static_cast<LO>(cols.size()), vals.data(), cols.data());
  }
  A->fillComplete();
  return A;
}

/// max |A y - x| / max |x| for y = M^{-1} x with a random x.
double solve_residual(const Prec& M, const Matrix& A_local) {
  MV x(A_local.getRowMap(), 1), y(A_local.getRowMap(), 1), r(A_local.getRowMap(), 1);
  x.randomize();
  M.apply(x, y);
  A_local.apply(y, r);
  r.update(-1.0, x, 1.0);
  std::vector<double> nr(1), nx(1);
  r.normInf(Teuchos::ArrayView<double>(nr));
  x.normInf(Teuchos::ArrayView<double>(nx));
  return nr[0] / nx[0];
}

TEST(BlockTridiagonal, FindsTheBlockSizeAndSolvesEachRanksRowsExactly) {
  for (int b : {6, 12, 5}) {
    const auto map = node_map(200, b);
    const auto A = random_matrix(map, b, 8.0, true, false, 11);
    const auto A_local = random_matrix(map, b, 8.0, false, false, 11);
    Prec M(A);
    M.compute();
    EXPECT_EQ(M.block_size(), b);
    const double res = solve_residual(M, *A_local);
    if (comm()->getRank() == 0)
      std::printf("[%d ranks] b = %d: found block size %d, max|A_rank y - x|/max|x| = %.2e, min rcond %.2e\n",
                  comm()->getSize(), b, M.block_size(), res, M.min_rcond());
    EXPECT_LT(res, 1e-12) << "b = " << b;
    if (comm()->getSize() == 1) {
      EXPECT_LT(solve_residual(M, *A), 1e-12);  // one rank: a direct solve
    }
  }
}

TEST(BlockTridiagonal, PivotsInsideBlocksAndRefactorisesNewValues) {
  const int b = 12;
  const auto map = node_map(150, b);
  const auto A = random_matrix(map, b, 4.0, true, true, 21);
  Prec M(A);
  M.compute();
  const auto A_local = random_matrix(map, b, 4.0, false, true, 21);
  EXPECT_LT(solve_residual(M, *A_local), 1e-11);
  // New values on the same graph (what a Newton iteration does): refactorise, still exact.
  A->resumeFill();
  A->scale(-2.5);
  A->fillComplete();
  A_local->resumeFill();
  A_local->scale(-2.5);
  A_local->fillComplete();
  M.compute();
  const double res = solve_residual(M, *A_local);
  if (comm()->getRank() == 0)
    std::printf("[%d ranks] zero diagonal, rescaled: residual %.2e, min rcond %.2e\n", comm()->getSize(),
                res, M.min_rcond());
  EXPECT_LT(res, 1e-11);
}

TEST(BlockTridiagonal, RejectsAMatrixThatIsNotBlockTridiagonal) {
  // An arrow matrix: every row couples to global index 0 and to its own node.
  const auto map = node_map(400, 1);
  auto A = Teuchos::rcp(new Matrix(map, 3));
  for (LO i = 0; i < static_cast<LO>(map->getNodeNumElements()); ++i) {
    const GO g = map->getGlobalElement(i);
    std::vector<GO> cols{g};
    std::vector<double> vals{4.0};
    if (g != 0) {
      cols.push_back(0);
      vals.push_back(1.0);
    }
    A->insertGlobalValues(g, static_cast<LO>(cols.size()), vals.data(), cols.data());
  }
  A->fillComplete();
  if (comm()->getRank() == 0) {
    // Rank 0 owns index 0 and rows far from it: no block size up to 64 fits.
    EXPECT_THROW(Prec M(A), std::invalid_argument);
  }
}

}  // namespace
}  // namespace traverse::solver

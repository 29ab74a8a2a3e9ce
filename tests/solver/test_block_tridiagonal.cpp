// The block-tridiagonal LU (src/solver/block_tridiagonal_preconditioner.*) on 1, 2 and 3
// ranks (3: a rank in the middle, with separators on both sides): block size found from the
// graph, exact solve of the whole system across ranks (separator system), pivoting inside a
// block, singular diagonal blocks at the rod's ends (merged start), refactorisation on new
// values, a rank holding a single node, block Jacobi when the
// pieces are not in rank order, a clear error on every rank for a matrix that is not
// block tridiagonal, and the same matrix in block storage (BlockTridiagonalOperator).
#include <gtest/gtest.h>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultMpiComm.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include <Thyra_TpetraThyraWrappers.hpp>

#include "block_tridiagonal_preconditioner.hpp"
#include "traverse/solver/block_tridiagonal_operator.hpp"

namespace traverse::solver {
namespace {

using Prec = BlockTridiagonalPreconditioner;
using Matrix = Prec::Matrix;
using LO = Prec::LO;
using GO = Prec::GO;
using MV = Prec::MV;
using Map = Prec::Map;

Teuchos::RCP<const Teuchos::Comm<int>> comm() { return Tpetra::getDefaultComm(); }

/// Nodes split contiguously over the ranks in rank order, b unknowns per node; `single` >= 0
/// gives that rank a single node and splits the rest; `reversed` gives rank r the piece
/// that rank P-1-r would have (pieces no longer in rank order).
Teuchos::RCP<const Map> node_map(int nodes, int b, int single = -1, bool reversed = false) {
  const int p = comm()->getSize();
  std::vector<int> count(static_cast<size_t>(p));
  for (int r = 0; r < p; ++r) count[static_cast<size_t>(r)] = nodes / p + (r < nodes % p ? 1 : 0);
  if (single >= 0 && p > 1) {
    const int rest = nodes - 1;
    for (int r = 0, k = 0; r < p; ++r)
      count[static_cast<size_t>(r)] = r == single ? 1 : rest / (p - 1) + (k++ < rest % (p - 1) ? 1 : 0);
  }
  const int r = reversed ? p - 1 - comm()->getRank() : comm()->getRank();
  GO first = 0;
  for (int q = 0; q < r; ++q) first += static_cast<GO>(count[static_cast<size_t>(q)]) * b;
  std::vector<GO> mine(static_cast<size_t>(count[static_cast<size_t>(r)]) * b);
  for (size_t i = 0; i < mine.size(); ++i) mine[i] = first + static_cast<GO>(i);
  return Teuchos::rcp(new Map(static_cast<GO>(nodes) * b, Teuchos::ArrayView<const GO>(mine), 0, comm()));
}

/// A random block-tridiagonal matrix (b x b blocks). keep_off_rank = false drops the
/// entries whose column belongs to another rank (the matrix the preconditioner inverts).
/// zero_diagonal: each diagonal block has zeros on its diagonal (LU needs row exchanges).
/// halved: a node's first b/2 rows do not couple to the next node, its last b/2 not to the
/// previous one (the rod's layout: each row is one cell's).
Teuchos::RCP<Matrix> random_matrix(const Teuchos::RCP<const Map>& map, int b, double scale,
                                   bool keep_off_rank, bool zero_diagonal, unsigned seed, bool halved = false) {
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
        if (halved && ((m == k - 1 && 2 * (g % b) >= b) || (m == k + 1 && 2 * (g % b) < b))) continue;
        cols.push_back(col);
        vals.push_back(v);
      }
    A->insertGlobalValues(g, static_cast<LO>(cols.size()), vals.data(), cols.data());
  }
  A->fillComplete();
  return A;
}

/// Zeroes the last b/2 columns of the diagonal blocks of the first and the last node (their
/// rows on this rank): those blocks are then singular on their own.
void make_end_blocks_singular(Matrix& A, int nodes, int b) {
  const auto map = A.getRowMap();
  A.resumeFill();
  for (GO node : {GO(0), GO(nodes - 1)})
    for (int i = 0; i < b; ++i) {
      const GO row = node * b + i;
      if (!map->isNodeGlobalElement(row)) continue;
      for (int c = b / 2; c < b; ++c) {
        const GO col = node * b + c;
        const double zero = 0.0;
        A.replaceGlobalValues(row, 1, &zero, &col);
      }
    }
  A.fillComplete();
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
  // A NaN in r can come back from normInf as -inf: anything not finite is a failed solve.
  const double q = nr[0] / nx[0];
  return std::isfinite(q) && q >= 0.0 ? q : std::numeric_limits<double>::infinity();
}

TEST(BlockTridiagonal, FindsTheBlockSizeAndSolvesExactlyAcrossRanks) {
  for (int b : {6, 12, 5}) {
    for (int nodes : {200, 7}) {  // 7 nodes on 3 ranks: 3 + 2 + 2, interiors of one block
      const auto map = node_map(nodes, b);
      const auto A = random_matrix(map, b, 8.0, true, false, 11);
      Prec M(A);
      M.compute();
      EXPECT_EQ(M.block_size(), b);
      EXPECT_TRUE(M.exact()) << M.why_not_exact();
      const double res = solve_residual(M, *A);
      if (comm()->getRank() == 0)
        std::printf("[%d ranks] b = %d, %d nodes: found block size %d, max|A y - x|/max|x| = %.2e, min rcond %.2e\n",
                    comm()->getSize(), b, nodes, M.block_size(), res, M.min_rcond());
      EXPECT_LT(res, 1e-12) << "b = " << b << ", " << nodes << " nodes";
    }
  }
}

TEST(BlockTridiagonal, HalfCouplingsAreFoundAndSolvedExactlyAcrossRanks) {
  // The rod's layout (L zero past row b/2, U zero before it): found from the values, and the
  // factorisation on the halves solves exactly, also from merged singular end blocks (the
  // right end's reversed elimination on the last rank) and after refactorisation.
  for (int b : {6, 12}) {
    for (int nodes : {200, 7}) {
      const auto map = node_map(nodes, b);
      const auto A = random_matrix(map, b, 8.0, true, false, 31, true);
      Prec M(A);
      M.compute();
      EXPECT_TRUE(M.half_couplings()) << "b = " << b;
      const double res = solve_residual(M, *A);
      if (comm()->getRank() == 0)
        std::printf("[%d ranks] half couplings, b = %d, %d nodes: max|A y - x|/max|x| = %.2e\n",
                    comm()->getSize(), b, nodes, res);
      EXPECT_LT(res, 1e-12) << "b = " << b << ", " << nodes << " nodes";
      A->resumeFill();
      A->scale(-0.5);
      A->fillComplete();
      M.compute();
      EXPECT_LT(solve_residual(M, *A), 1e-12) << "refactorised, b = " << b << ", " << nodes << " nodes";
    }
    const int nodes = 60;
    const auto map = node_map(nodes, b);
    const auto A = random_matrix(map, b, 8.0, true, true, 32, true);  // pivoting inside blocks
    make_end_blocks_singular(*A, nodes, b);  // as in SingularEndBlocksStartWithMergedNodes
    Prec M(A);
    M.compute();
    EXPECT_TRUE(M.half_couplings());
    EXPECT_LT(solve_residual(M, *A), 1e-11) << "singular ends, b = " << b;
    // A dense random matrix is not taken for halved.
    Prec D(random_matrix(map, b, 8.0, true, false, 33));
    D.compute();
    EXPECT_FALSE(D.half_couplings());
  }
}

TEST(BlockTridiagonal, WeakCouplingBetweenRanksStillExact) {
  // Diagonal blocks barely dominant: the separator system carries the whole coupling (block
  // Jacobi would be far off here); several right-hand sides at once.
  const int b = 12;
  const auto map = node_map(120, b);
  const auto A = random_matrix(map, b, 1.5, true, false, 5);
  const auto A_local = random_matrix(map, b, 1.5, false, false, 5);
  Prec M(A);
  M.compute();
  MV x(map, 3), y(map, 3), r(map, 3), r_local(map, 3);
  x.randomize();
  M.apply(x, y);
  A->apply(y, r);
  r.update(-1.0, x, 1.0);
  A_local->apply(y, r_local);
  r_local.update(-1.0, x, 1.0);
  std::vector<double> nr(3), nl(3), nx(3);
  r.normInf(Teuchos::ArrayView<double>(nr));
  r_local.normInf(Teuchos::ArrayView<double>(nl));
  x.normInf(Teuchos::ArrayView<double>(nx));
  // A backward-stable solve leaves a residual of about eps / rcond relative to x: here
  // rcond is about 2e-6, so 1e-10; 50 eps / rcond allows for the growth of the elimination.
  const double rcond_here = M.min_rcond();
  double rcond = rcond_here;
  Teuchos::reduceAll<int, double>(*comm(), Teuchos::REDUCE_MIN, 1, &rcond_here, &rcond);
  const double bound = 50.0 * std::numeric_limits<double>::epsilon() / rcond;
  for (int j = 0; j < 3; ++j) {
    EXPECT_TRUE(std::isfinite(nr[j]) && nr[j] >= 0.0) << nr[j];
    EXPECT_LT(nr[j] / nx[j], bound) << "column " << j;
    // The solution is that of the coupled system, not of each rank's rows alone.
    if (comm()->getSize() > 1) {
      EXPECT_GT(nl[j] / nx[j], 1e-3) << "column " << j;
    }
  }
  if (comm()->getRank() == 0)
    std::printf("[%d ranks] weak diagonal: residual %.2e (of the rank-local system %.2e), min rcond %.2e\n",
                comm()->getSize(), nr[0] / nx[0], nl[0] / nx[0], M.min_rcond());
}

TEST(BlockTridiagonal, ExactWhenARankHoldsOneNode) {
  // A rank with a single node has no interior (its node is its separator): still exact,
  // whichever rank it is (first, middle, last).
  const int b = 6;
  for (int single = 0; single < comm()->getSize(); ++single) {
    const auto map = node_map(40, b, single);
    const auto A = random_matrix(map, b, 8.0, true, false, 3);
    Prec M(A);
    M.compute();
    EXPECT_TRUE(M.exact()) << M.why_not_exact();
    const double res = solve_residual(M, *A);
    EXPECT_LT(res, 1e-12) << "rank " << single << " with one node";
    if (comm()->getRank() == 0)
      std::printf("[%d ranks] rank %d holds one node: residual %.2e\n", comm()->getSize(), single, res);
  }
}

TEST(BlockTridiagonal, BlockJacobiWhenThePiecesAreNotInRankOrder) {
  // Rank r holds the piece of rank P-1-r: no separator system; the couplings between ranks
  // are dropped and each rank's rows are solved exactly.
  const int b = 6;
  const auto map = node_map(40, b, -1, true);
  const auto A = random_matrix(map, b, 8.0, true, false, 3);
  const auto A_local = random_matrix(map, b, 8.0, false, false, 3);
  Prec M(A);
  M.compute();
  if (comm()->getSize() == 1) {
    EXPECT_TRUE(M.exact());
    EXPECT_LT(solve_residual(M, *A), 1e-12);
  } else {
    EXPECT_FALSE(M.exact());
    EXPECT_NE(M.why_not_exact().find("not consecutive in rank order"), std::string::npos) << M.why_not_exact();
    EXPECT_LT(solve_residual(M, *A_local), 1e-12);
  }
}

TEST(BlockTridiagonal, SingularEndBlocksStartWithMergedNodes) {
  // The diagonal blocks of both end nodes lose half their columns (as the rod's right end
  // does: its end conditions and the last cell's kinematic rows leave the forces out), so
  // an elimination that starts at an end must merge it with its neighbour.
  const int b = 12, nodes = 60;
  const auto map = node_map(nodes, b);
  const auto A = random_matrix(map, b, 8.0, true, false, 8);
  make_end_blocks_singular(*A, nodes, b);
  Prec M(A);
  M.compute();
  EXPECT_TRUE(M.exact()) << M.why_not_exact();
  const double res = solve_residual(M, *A);
  if (comm()->getRank() == 0)
    std::printf("[%d ranks] singular end blocks: residual %.2e\n", comm()->getSize(), res);
  EXPECT_LT(res, 1e-11);
}

TEST(BlockTridiagonal, PivotsInsideBlocksAndRefactorisesNewValues) {
  const int b = 12;
  const auto map = node_map(150, b);
  const auto A = random_matrix(map, b, 4.0, true, true, 21);
  Prec M(A);
  M.compute();
  EXPECT_LT(solve_residual(M, *A), 1e-11);
  // New values on the same graph (what a Newton iteration does): refactorise, still exact.
  A->resumeFill();
  A->scale(-2.5);
  A->fillComplete();
  M.compute();
  const double res = solve_residual(M, *A);
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
  // Rank 0 owns index 0 and rows far from it: no block size up to 64 fits; every rank
  // throws (the analysis is collective, so no rank is left waiting).
  EXPECT_THROW(Prec M(A), std::invalid_argument);
}

/// Writes A (block tridiagonal with b = op.block_size()) into op's block storage, a row at a
/// time; `halves`: each row as two contributions of half its values (the first assigns, the
/// second adds); `diagonal_only`: only the blocks D (L and U are then not reached).
void fill_blocks(BlockTridiagonalOperator& op, const Matrix& A, bool halves = false, bool diagonal_only = false) {
  const int b = op.block_size();
  op.begin_fill();
  const auto map = A.getRowMap();
  const GO first = map->getGlobalElement(0);
  std::vector<GO> cols(A.getNodeMaxNumRowEntries());
  std::vector<double> vals(cols.size());
  for (LO i = 0; i < static_cast<LO>(map->getNodeNumElements()); ++i) {
    const GO g = map->getGlobalElement(i);
    size_t n = 0;
    A.getGlobalRowCopy(g, Teuchos::ArrayView<GO>(cols), Teuchos::ArrayView<double>(vals), n);
    std::vector<double> row(3 * static_cast<size_t>(b), 0.0);  // the row's part of L, D, U
    bool reached[3] = {false, false, false};
    for (size_t k = 0; k < n; ++k) {
      const long rel = static_cast<long>(cols[k] / b - g / b + 1);
      row[static_cast<size_t>(rel * b + cols[k] % b)] += vals[k];
      reached[rel] = true;
    }
    if (halves)
      for (double& v : row) v *= 0.5;  // exact: the two halves sum to the value
    for (int pass = 0; pass < (halves ? 2 : 1); ++pass)
      for (int rel = 0; rel < 3; ++rel)
        if (reached[rel] && (!diagonal_only || rel == 1))
          op.add_chunk_rows(static_cast<long>(g - first), 1, rel, row.data() + rel * b, 1);
  }
  op.end_fill();
}

double max_difference(const MV& a, const MV& b) {
  MV d(a, Teuchos::Copy);
  d.update(-1.0, b, 1.0);
  std::vector<double> n(a.getNumVectors());
  d.normInf(Teuchos::ArrayView<double>(n));
  return *std::max_element(n.begin(), n.end());
}

TEST(BlockTridiagonal, BlockStorageIsTheSameMatrixAndKeepsTheFactorisedValues) {
  // The same random matrix as a CrsMatrix and in block storage on the mesh's layout: the same
  // products and the same factorisation (bit for bit: the same values in the same blocks);
  // a refill of the blocks after compute() leaves the factorisation and its residual check on
  // the values it factorised, until the next compute(). With dense couplings and with halved
  // ones (a fill that reaches L only in the first b/2 rows and U only in the last: the operator
  // says so, its product and both factorisations take the halves).
  for (const auto& [b, halved] : {std::pair{12, false}, std::pair{6, false}, std::pair{12, true}, std::pair{6, true}}) {
    const int nodes = 150;
    const auto mesh = Teuchos::rcp(new mesh::DistributedMesh(mesh::Mesh1D(1.0, nodes), comm(), b));
    const auto space = Thyra::createVectorSpace<double>(mesh->dof_map());
    const auto op = Teuchos::rcp(new BlockTridiagonalOperator(mesh, space));
    const auto A = random_matrix(mesh->dof_map(), b, 8.0, true, false, 21, halved);
    const auto A2 = random_matrix(mesh->dof_map(), b, 8.0, true, false, 22, halved);
    fill_blocks(*op, *A);
    EXPECT_EQ(op->half_couplings(), halved);
    MV x(mesh->dof_map(), 2), y_crs(mesh->dof_map(), 2), y_blocks(mesh->dof_map(), 2);
    x.randomize();
    A->apply(x, y_crs);
    op->apply_values(*op->values(), op->half_couplings(), x, y_blocks);
    EXPECT_LT(max_difference(y_crs, y_blocks), 1e-14) << "b = " << b;

    Prec crs(A);
    crs.compute();
    const auto blocks = Prec::on_blocks(op);
    blocks->compute();
    EXPECT_TRUE(blocks->exact()) << blocks->why_not_exact();
    EXPECT_EQ(blocks->block_size(), b);
    EXPECT_EQ(crs.half_couplings(), halved);
    EXPECT_EQ(blocks->half_couplings(), halved);
    MV s_crs(mesh->dof_map(), 2), s_blocks(mesh->dof_map(), 2);
    crs.apply(x, s_crs);
    blocks->apply(x, s_blocks);
    EXPECT_EQ(max_difference(s_crs, s_blocks), 0.0) << "b = " << b;

    fill_blocks(*op, *A2);  // the factorisation holds A's values: the fill goes elsewhere
    MV again(mesh->dof_map(), 2), Ay(mesh->dof_map(), 2);
    blocks->apply(x, again);
    EXPECT_EQ(max_difference(again, s_blocks), 0.0) << "b = " << b;
    blocks->apply_matrix(s_blocks, Ay);  // A (not A2) times A^{-1} x
    EXPECT_LT(max_difference(Ay, x), 1e-12) << "b = " << b;
    op->apply_values(*op->values(), op->half_couplings(), x, y_blocks);  // the operator itself has A2 now
    A2->apply(x, y_crs);
    EXPECT_LT(max_difference(y_crs, y_blocks), 1e-14) << "b = " << b;

    blocks->compute();  // now A2
    Prec crs2(A2);
    crs2.compute();
    crs2.apply(x, s_crs);
    blocks->apply(x, s_blocks);
    EXPECT_EQ(max_difference(s_crs, s_blocks), 0.0) << "b = " << b;

    // A fill in two contributions per row (assign, then add) gives the same matrix; a fill
    // that reaches only the diagonal blocks leaves zeros in L and U, not an earlier fill's values.
    fill_blocks(*op, *A, true);
    op->apply_values(*op->values(), op->half_couplings(), x, y_blocks);
    A->apply(x, y_crs);
    EXPECT_LT(max_difference(y_crs, y_blocks), 1e-14) << "b = " << b;
    const auto full = op->values();  // held: the next fill goes to the other buffer
    fill_blocks(*op, *A2);
    fill_blocks(*op, *A, false, true);  // into the buffer that held A2, A's D blocks only
    const std::vector<double>& v = *op->values();
    const size_t bb = static_cast<size_t>(b) * static_cast<size_t>(b);
    size_t wrong = 0;
    for (size_t k = 0; k < v.size(); ++k) {
      const bool diagonal = (k / bb) % 3 == 1;
      if (diagonal ? v[k] != (*full)[k] : v[k] != 0.0) ++wrong;
    }
    EXPECT_EQ(wrong, 0u) << "b = " << b;
    EXPECT_TRUE(op->half_couplings()) << "b = " << b;  // no L or U chunk reached
    fill_blocks(*op, *random_matrix(mesh->dof_map(), b, 8.0, true, false, 23));  // all of L and U
    EXPECT_FALSE(op->half_couplings()) << "b = " << b;
  }
}

}  // namespace
}  // namespace traverse::solver

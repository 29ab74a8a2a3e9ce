#pragma once
// Exact block-tridiagonal LU of the rod Jacobian across ranks, as a Tpetra operator (the
// direct time-step solver, or the preconditioner of GMRES, which then stops after one
// iteration).
//
// The rod's unknowns are node-major and the rows of node k couple nodes k-1..k+1 only
// (docs/solver.md, "The default linear solver: block-tridiagonal LU"), so with the node's unknowns as one block the
// matrix is block tridiagonal. The block size is found from the graph (the smallest b for
// which every rank's owned rows couple only the neighbouring b-blocks: 12 for the 3D rod, 6
// for the planar one), so nothing else needs to tell it. One rank: the block Thomas algorithm
// (Schur complements S_k = D_k - L_k S_{k-1}^{-1} U_{k-1}, each factorised by LU with
// partial pivoting inside the block), about 8 b^3 / 3 flops per node: the
// "block-tridiagonal LU floor" of docs/benchmarks.md; about half that when the coupling blocks
// are halved, as the rod's are (BlockTridiagonalFactors::factor).
//
// Several ranks (each holding a consecutive piece of the chain, in rank order, as
// mesh::DistributedMesh partitions the rod): the last node of every rank but the last is a
// separator. Removing the separators splits the chain into independent interiors, one per
// rank; each rank factorises its interior (forward when a separator follows it, backward from
// its end when one precedes it, both for a rank in the middle) and forms its part of the
// Schur complement on the separators, which needs only the corner blocks of its interior's
// inverse: (A^-1)_{last,last} = S_last^-1 and (A^-1)_{first,first} from the two directions,
// the off-diagonal corners by one sweep of b x b products. The separator system (block
// tridiagonal, ranks - 1 blocks) is gathered and solved on every rank; a solve is an interior
// solve, an exchange of 2 b numbers per rank, the separator solve and a second interior solve
// with the separators' values on the right-hand side. A rod end eliminated first (the reversed
// order on the last rank) is singular on its own, so each elimination starts with the first q
// nodes merged into one block, q the smallest (up to 4) with no pivot below 1e-13 of the
// largest. Arithmetic per rank: the first and
// last rank about one factorisation of their nodes (no overlap, no Krylov iterations), a
// middle rank about two (a rank holding one node has no interior: its node is its separator).
// When the layout does not allow it (pieces not consecutive in rank order, a rank without
// rows, a row coupling to a block two or more away on another rank), the couplings between
// ranks are dropped instead (block Jacobi: exact() is false). The graph analysis is
// done once in the constructor (collective); compute() copies the values and factorises
// (collective), apply() is collective on several ranks.
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Operator.hpp>

#include <memory>
#include <string>

namespace traverse::solver {

class BlockTridiagonalOperator;

class BlockTridiagonalPreconditioner : public Tpetra::Operator<double> {
 public:
  using Matrix = Tpetra::CrsMatrix<double>;
  using LO = Matrix::local_ordinal_type;
  using GO = Matrix::global_ordinal_type;
  using Node = Matrix::node_type;
  using MV = Tpetra::MultiVector<double, LO, GO, Node>;
  using Map = Tpetra::Map<LO, GO, Node>;

  /// Analyses A's graph (fill-complete, contiguous row map equal to its domain and range
  /// maps). Collective. Throws std::invalid_argument (on every rank) when no block size
  /// makes some rank's owned rows block tridiagonal.
  explicit BlockTridiagonalPreconditioner(Teuchos::RCP<const Matrix> A);
  /// On a matrix in block storage (its blocks are factorised as they are, without a copy:
  /// compute() holds the operator's current values). Collective.
  static Teuchos::RCP<BlockTridiagonalPreconditioner> on_blocks(Teuchos::RCP<const BlockTridiagonalOperator> A);
  ~BlockTridiagonalPreconditioner() override;

  /// Takes A's current values (a copy from a CrsMatrix, whose graph must not have changed;
  /// the values themselves in block storage) and factorises.
  void compute();

  /// Factorise with the first b/2 rows of the first node (a static rod's left-end rows)
  /// replaced by a clamp on its first b/2 unknowns (the position and rotation), and correct every
  /// solve exactly for the rows replaced (Woodbury, rank b/2: b/2 more solves per
  /// factorisation, b/2 vector updates per solve). For a static rod whose left end is not
  /// clamped: every piece of the chain from that end would be a mechanism, and the elimination
  /// from the left singular. A CrsMatrix input on one rank or with the couplings kept across
  /// ranks, whose left-end rows couple to the first node only; from the next compute().
  void set_left_end_clamp(bool on);
  int block_size() const;
  /// True when the solve is exact across ranks (always on one rank); otherwise the
  /// couplings between ranks are dropped and why_not_exact() says why.
  bool exact() const;
  const std::string& why_not_exact() const;
  /// Smallest reciprocal condition estimate of the factorised diagonal blocks (this rank),
  /// estimated when asked (about b^2 work per block), 1 when there are none.
  double min_rcond() const;
  /// Whether the last compute() found the couplings halved (BlockTridiagonalFactors::factor):
  /// from the fill in block storage, from the values of a CrsMatrix.
  bool half_couplings() const;
  /// The matrix this was built on (a CrsMatrix or a BlockTridiagonalOperator).
  const void* source() const;
  /// y = A x with the values last factorised (collective).
  void apply_matrix(const MV& x, MV& y) const;

  Teuchos::RCP<const Map> getDomainMap() const override;
  Teuchos::RCP<const Map> getRangeMap() const override;
  /// Y = beta Y + alpha M^{-1} X (NO_TRANS only).
  void apply(const MV& X, MV& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS, double alpha = 1.0,
             double beta = 0.0) const override;

 private:
  BlockTridiagonalPreconditioner();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace traverse::solver

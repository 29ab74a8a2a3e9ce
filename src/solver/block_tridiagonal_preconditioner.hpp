#pragma once
// Exact block-tridiagonal LU of each rank's rows of the rod Jacobian, as a Tpetra operator
// (used as the preconditioner of GMRES: on one rank it is a direct solve, so GMRES stops
// after one iteration; across ranks it is block Jacobi, one block per rank).
//
// The rod's unknowns are node-major and the rows of node k couple nodes k-1..k+1 only
// (docs/solver.md, "Row/unknown mapping"), so with the node's unknowns as one block the
// matrix is block tridiagonal. The block size is found from the graph (the smallest b for
// which every owned row couples only the neighbouring b-blocks: 12 for the 3D rod, 6 for
// the planar one), so nothing else needs to tell it. Factorisation: the block Thomas
// algorithm (Schur complements S_k = D_k - L_k S_{k-1}^{-1} U_{k-1}, each factorised by LU
// with partial pivoting inside the block), about 8 b^3 / 3 flops per node: the
// "block-tridiagonal LU floor" of docs/benchmarks.md. Couplings to other ranks' nodes are
// dropped (block Jacobi). The graph analysis (block size and where each matrix entry goes)
// is done once in the constructor; compute() only copies the values and factorises.
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Operator.hpp>

#include <memory>

namespace traverse::solver {

class BlockTridiagonalPreconditioner : public Tpetra::Operator<double> {
 public:
  using Matrix = Tpetra::CrsMatrix<double>;
  using LO = Matrix::local_ordinal_type;
  using GO = Matrix::global_ordinal_type;
  using Node = Matrix::node_type;
  using MV = Tpetra::MultiVector<double, LO, GO, Node>;
  using Map = Tpetra::Map<LO, GO, Node>;

  /// Analyses A's graph (fill-complete, contiguous row map equal to its domain and range
  /// maps). Throws std::invalid_argument when no block size makes the owned rows block
  /// tridiagonal.
  explicit BlockTridiagonalPreconditioner(Teuchos::RCP<const Matrix> A);
  ~BlockTridiagonalPreconditioner() override;

  /// Copies A's current values and factorises (A's graph must not have changed).
  void compute();

  int block_size() const;
  /// Smallest reciprocal condition estimate of the factorised diagonal blocks (this rank),
  /// estimated when asked (about b^2 work per block), 1 when there are none.
  double min_rcond() const;
  const Teuchos::RCP<const Matrix>& matrix() const;

  Teuchos::RCP<const Map> getDomainMap() const override;
  Teuchos::RCP<const Map> getRangeMap() const override;
  /// Y = beta Y + alpha M^{-1} X (NO_TRANS only).
  void apply(const MV& X, MV& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS, double alpha = 1.0,
             double beta = 0.0) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace traverse::solver

#pragma once
// A block-tridiagonal system on block storage in one process: f and the L, D, U blocks of
// each node (block_tridiagonal_factors.hpp layout) filled from kernel blocks, factorised by
// the block-tridiagonal LU and solved with its residual check and at most two refinements (as
// the block-tridiagonal direct solver over Tpetra does). What BlockNewton (the time step) and
// the single-process static start (block_static_start.hpp) share. Eigen and the rod kernels.
#include <memory>
#include <vector>

#include "block_tridiagonal_factors.hpp"
#include "traverse/rod/rod_kernels.hpp"

namespace traverse::solver {

class BlockSystem {
 public:
  /// `nodes` nodes of `b` unknowns each.
  BlockSystem(int nodes, int b);
  int nodes() const { return n_; }
  int block_size() const { return b_; }
  /// f = 0 and every block 0.
  void clear();
  /// Adds a kernel block (its rows and its columns' blocks; every column block must lie in the
  /// block tridiagonal: std::logic_error otherwise).
  void add(const rod::LocalBlock& blk);
  const std::vector<double>& f() const { return f_; }
  std::vector<double>& f() { return f_; }
  /// Factorises the blocks (throws when the LU fails).
  void factor();
  /// d = J^{-1} f with the residual check and the refinements; returns max|f - J d| / nb, nb =
  /// max|f| (infinite when not finite). `tolerance`: no refinement below it. J is the current
  /// blocks. After clear() and add() without a new factor(), the last factorisation (its
  /// Schur complements, with the current sub-diagonal blocks) is only an approximate inverse:
  /// the refinements then iterate towards the current J's solution and the returned ratio
  /// measures how far they got (BlockNewton's next-update test).
  double solve(std::vector<double>& d, double nb, double tolerance);

 private:
  /// r = f - J d (block-tridiagonal product; each row's entries in column order, nodes k-1,
  /// k, k+1, as a CRS product sums them).
  void residual_of(const std::vector<double>& d, std::vector<double>& r) const;
  int n_ = 0, b_ = 0;
  std::vector<double> blocks_, f_, r_, dx_;
  std::unique_ptr<BlockTridiagonalFactors> lu_;
};

/// max |v_i|, or NaN when some entry is not finite.
double max_abs(const std::vector<double>& v);

}  // namespace traverse::solver

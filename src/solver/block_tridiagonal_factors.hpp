#pragma once
// The factorisation and solve of the block-tridiagonal LU (the algorithm is described in
// block_tridiagonal_preconditioner.hpp), on raw blocks: Eigen only, no Trilinos (the Tpetra
// operator BlockTridiagonalPreconditioner works through it).
//
// Layout: per node k of this rank, `blocks` holds three b x b column-major blocks: L_k
// (coupling to node k-1), D_k, U_k (node k+1); entry (r, c) of the slot-th block of node k is
// blocks[3 b^2 k + slot b^2 + c b + r]. Vectors hold b entries per node.
#include <functional>
#include <memory>
#include <vector>

namespace traverse::solver {

/// Called once per factorisation (and once per solve) on several ranks with this rank's packed
/// contribution; must return every rank's, in rank order (an all-gather). Not called on 1 rank.
using BlockExchange = std::function<std::vector<double>(const std::vector<double>&)>;

/// Rank p's nodes are split into its interior (all but its last node when a rank follows, all
/// otherwise) and, when a rank follows, its separator (its last node).
class BlockTridiagonalFactors {
 public:
  virtual ~BlockTridiagonalFactors() = default;
  /// Factorises this rank's part (n nodes, block size b); on several ranks `exchange` is called
  /// once with this rank's contribution to the separator system. `half`: every L_k is zero
  /// outside its first b/2 rows and every U_k outside its last b/2 (half_coupled(); the rod's
  /// rows are a cell's, and a cell's rows fall to its left node's last half and its right
  /// node's first), which the factorisation and the solve then use: about half the arithmetic
  /// of dense couplings (fixed block sizes; the dynamic size ignores it).
  virtual void factor(const double* blocks, int n, int b, int rank, int ranks, const BlockExchange& exchange,
                      bool half) = 0;
  /// y = A^{-1} x (this rank's entries); `blocks` are the factorised ones.
  virtual void solve(const double* x, double* y, const double* blocks, const BlockExchange& exchange) const = 0;
  /// Smallest reciprocal condition estimate of the factorised diagonal blocks (this rank).
  virtual double min_rcond() const = 0;
};

/// Whether the L and U blocks of n nodes are zero where `half` in factor() says (b even).
bool half_coupled(const double* blocks, int n, int b);

/// Factors for block size b (fixed-size Eigen blocks for 6, 12 and 24, dynamic otherwise).
std::unique_ptr<BlockTridiagonalFactors> make_block_tridiagonal_factors(int b);

}  // namespace traverse::solver

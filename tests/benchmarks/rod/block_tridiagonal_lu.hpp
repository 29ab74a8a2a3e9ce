#pragma once
// The "floor" of the rod benchmarks: one block-tridiagonal LU factorisation and solve with
// dense B x B Eigen blocks (no pivoting across blocks, partial pivoting inside each diagonal
// block), i.e. the least work any direct solver of the rod's Jacobian (block-tridiagonal by
// node, B = 12 unknowns per node on the 3D path, 6 on the planar path) has to do. Written for
// the benchmarks; not used by the solver.
#include <Eigen/Dense>
#include <chrono>
#include <random>
#include <vector>

namespace traverse::bench {

template <int B>
struct BlockTridiagonal {
  using Block = Eigen::Matrix<double, B, B>;
  using BVec = Eigen::Matrix<double, B, 1>;
  std::vector<Block> lower, diag, upper;  ///< lower[0], upper[n-1] unused
  std::vector<BVec> rhs;

  explicit BlockTridiagonal(int n, unsigned seed = 1)
      : lower(static_cast<size_t>(n)), diag(static_cast<size_t>(n)), upper(static_cast<size_t>(n)),
        rhs(static_cast<size_t>(n)) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    auto fill = [&](Block& b) {
      for (int i = 0; i < B; ++i)
        for (int j = 0; j < B; ++j) b(i, j) = U(gen);
    };
    for (int k = 0; k < n; ++k) {
      fill(lower[k]);
      fill(upper[k]);
      fill(diag[k]);
      diag[k].diagonal().array() += 30.0;  // block diagonally dominant: no inter-block pivoting needed
      for (int i = 0; i < B; ++i) rhs[k](i) = U(gen);
    }
  }
  int size() const { return static_cast<int>(diag.size()); }
};

/// Storage of the factors (allocated once, reused: the floor times the arithmetic, not the
/// page faults of fresh allocations).
template <int B>
struct BlockLuWorkspace {
  using Block = Eigen::Matrix<double, B, B>;
  using BVec = Eigen::Matrix<double, B, 1>;
  std::vector<Eigen::PartialPivLU<Block>> lu;
  std::vector<Block> C;  ///< D_k^{-1} U_k
  std::vector<BVec> y;
  explicit BlockLuWorkspace(int n)
      : lu(static_cast<size_t>(n), Eigen::PartialPivLU<Block>(Block::Identity())),
        C(static_cast<size_t>(n), Block::Zero()), y(static_cast<size_t>(n), BVec::Zero()) {}
};

/// Factorise and solve (Thomas algorithm by blocks); the solution is left in ws.y.
template <int B>
void block_tridiagonal_solve(const BlockTridiagonal<B>& A, BlockLuWorkspace<B>& ws) {
  using Block = Eigen::Matrix<double, B, B>;
  using BVec = Eigen::Matrix<double, B, 1>;
  const int n = A.size();
  auto& lu = ws.lu;
  auto& C = ws.C;
  auto& y = ws.y;
  Block D = A.diag[0];
  BVec b = A.rhs[0];
  for (int k = 0; k < n; ++k) {
    if (k > 0) {
      D.noalias() = A.diag[k] - A.lower[k] * C[k - 1];
      b.noalias() = A.rhs[k] - A.lower[k] * y[k - 1];
    } else {
      D = A.diag[0];
      b = A.rhs[0];
    }
    lu[k].compute(D);
    y[k] = lu[k].solve(b);
    if (k + 1 < n) C[k] = lu[k].solve(A.upper[k]);
  }
  for (int k = n - 2; k >= 0; --k) y[k] -= C[k] * y[k + 1];
}

/// Seconds per factorise+solve of an n-block system of B x B blocks (repeated until
/// min_seconds elapsed).
template <int B = 12>
double time_block_tridiagonal(int n, double min_seconds = 0.2, double* residual = nullptr) {
  using BVec = Eigen::Matrix<double, B, 1>;
  const BlockTridiagonal<B> A(n);
  BlockLuWorkspace<B> ws(n);
  block_tridiagonal_solve(A, ws);  // warm-up: touches all the storage once
  int reps = 0;
  double el = 0.0, sink = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  do {
    block_tridiagonal_solve(A, ws);
    sink += ws.y[0](0);
    ++reps;
    el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } while (el < min_seconds);
  const std::vector<BVec>& x = ws.y;
  if (residual) {  // max |A x - b|, to show the floor solves the system
    double r = 0.0;
    for (int k = 0; k < n; ++k) {
      BVec e = A.diag[k] * x[k] - A.rhs[k];
      if (k > 0) e += A.lower[k] * x[k - 1];
      if (k + 1 < n) e += A.upper[k] * x[k + 1];
      r = std::max(r, e.cwiseAbs().maxCoeff());
    }
    *residual = r + 0.0 * sink;
  }
  return el / reps;
}

}  // namespace traverse::bench

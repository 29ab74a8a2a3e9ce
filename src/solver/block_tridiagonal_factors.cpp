#include "block_tridiagonal_factors.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace traverse::solver {

namespace {

/// X = A^{-1} R for a fixed-size LU and a matrix right-hand side, by row operations on X (the
/// permutation, the unit lower and the upper triangle): Eigen's solve in another order of the
/// same operations, without its general triangular-matrix kernel, which is slower for blocks
/// as small as the planar path's 6 x 6.
template <int B>
void lu_solve_rows(const Eigen::PartialPivLU<Eigen::Matrix<double, B, B>>& lu,
                   const Eigen::Map<const Eigen::Matrix<double, B, B>>& R, Eigen::Matrix<double, B, B>& X) {
  if constexpr (B == Eigen::Dynamic) {
    X = lu.solve(R);
  } else {
    using RowT = Eigen::Matrix<double, 1, B>;
    X = lu.permutationP() * R;
    const auto& A = lu.matrixLU();
    for (int i = 1; i < B; ++i) {
      RowT r = X.row(i);
      for (int j = 0; j < i; ++j) r -= A(i, j) * X.row(j);
      X.row(i) = r;
    }
    for (int i = B - 1; i >= 0; --i) {
      RowT r = X.row(i);
      for (int j = i + 1; j < B; ++j) r -= A(i, j) * X.row(j);
      X.row(i) = r / A(i, i);
    }
  }
}

/// dst -= l r for blocks of fixed size B: coefficient-based (unrolled at compile time) instead
/// of Eigen's general product kernels, whose packing costs more than the arithmetic of a 6 x 6
/// or 12 x 12 block.
template <int B, class Dst, class Lhs, class Rhs>
void subtract_product(Dst&& dst, const Lhs& l, const Rhs& r) {
  if constexpr (B == Eigen::Dynamic) dst.noalias() -= l * r;
  else dst.noalias() -= l.lazyProduct(r);
}

/// out = A^{-1} z (Eigen's solve: for one vector and fixed sizes faster than substitutions
/// written out here).
template <class LU, class Vec>
void lu_solve_vector(const LU& lu, const Vec& z, double* out) {
  Eigen::Map<Vec>(out, z.size()) = lu.solve(z);
}

/// X = R S^{-1} for a fixed-size LU of S (P S = L U) and R with H rows, by column operations
/// (the columns of the H x B result are contiguous): X P^T L U = R is solved as T U = R,
/// V L = T, X = V P. H x B instead of B x B: the rows of a coupling block that are not zero.
template <int B, int H, class Rhs>
void lu_solve_right(const Eigen::PartialPivLU<Eigen::Matrix<double, B, B>>& lu, const Rhs& R,
                    Eigen::Matrix<double, H, B>& X) {
  using Col = Eigen::Matrix<double, H, 1>;
  const auto& A = lu.matrixLU();
  Eigen::Matrix<double, H, B> V;
  for (int i = 0; i < B; ++i) {  // T U = R (upper triangle, columns in increasing order)
    Col t = R.col(i);
    for (int j = 0; j < i; ++j) t -= A(j, i) * V.col(j);
    V.col(i) = t / A(i, i);
  }
  for (int i = B - 2; i >= 0; --i) {  // V L = T (unit lower triangle, decreasing order)
    Col v = V.col(i);
    for (int j = i + 1; j < B; ++j) v -= A(j, i) * V.col(j);
    V.col(i) = v;
  }
  X.noalias() = V * lu.permutationP();
}

/// The block Thomas algorithm on a chain of m blocks, visited in a given order (natural or
/// reversed): position i has the coupling Lp[i] to position i-1, Dp[i], the coupling Up[i]
/// to position i+1, and its vector block at offset off[i] (in blocks). The first q positions
/// are eliminated together (one LU of q b x q b): q = 1 unless the first diagonal block is
/// singular on its own, which happens at a rod end eliminated first in the reversed order
/// (the right end's rows there are its end conditions and the kinematic rows of the last
/// cell, which leave the force unknowns out), then q grows until the start block is regular.
///
/// Dense couplings: the Schur complements S_i = D_i - Lp_i C_{i-1} with C_i = S_i^{-1} Up_i;
/// the forward sweep stores S_i^{-1} (x_i - Lp_i y_{i-1}), the backward one subtracts C_i y_{i+1}.
/// Half couplings (see BlockTridiagonalFactors::factor; natural order: Lp's non-zero rows are
/// the first H = B/2, Up's the last H; reversed the other way round): with X_i = Lp_{i+1}' S_i^{-1}
/// (H x B, Lp' the non-zero rows), S_{i+1} = D_{i+1} - X_i' Up_i' only on Lp's rows (X' the
/// columns of Up's rows): an H x H by H x B product where the dense form has B x B by B x B,
/// and X_i costs H right-hand sides where C_i costs B. The forward sweep stores
/// w_i = x_i - Lp_i S_{i-1}^{-1} w_{i-1} (X_{i-1} w_{i-1} on Lp's rows), the last position
/// solved; the backward one solves y_i = S_i^{-1} (w_i - Up_i y_{i+1}). The start block
/// (positions 0..q-1) and the first position after it are the same in both forms.
template <int B>
struct Chain {
  using Mat = Eigen::Matrix<double, B, B>;
  using Vec = Eigen::Matrix<double, B, 1>;
  using CMap = Eigen::Map<const Mat>;
  using Dyn = Eigen::MatrixXd;
  static constexpr bool kCanHalve = B != Eigen::Dynamic && B % 2 == 0;
  static constexpr int H = kCanHalve ? B / 2 : 1;
  using HalfRows = Eigen::Matrix<double, H, B>;
  static constexpr int kMaxMerge = 4;
  static constexpr double kStartPivot = 1e-13;
  int b = 0, m = 0, q = 1;
  bool half = false;
  int lo = 0, uo = 0;  ///< first non-zero row of Lp and of Up (half couplings)
  std::vector<const double*> Lp, Dp, Up;
  std::vector<long> off;
  Eigen::PartialPivLU<Dyn> lu0;              ///< LU of the start block (positions 0..q-1)
  Dyn E0;                                    ///< start block^-1 [0; ..; 0; U_{q-1}]
  std::vector<Eigen::PartialPivLU<Mat>> lu;  ///< LU of the Schur complements S_i, i >= q
  std::vector<Mat> C;                        ///< S_i^{-1} U_i (i = q-1: E0's last block)
  std::vector<HalfRows> X;                   ///< half couplings: Lp_{i+1}' S_i^{-1}, i >= q
  mutable Eigen::VectorXd zq;

  /// Positions 0..m_-1 over the blocks first..first+m_-1 of a [L, D, U] array, natural
  /// order or reversed (then "previous" is the next node: L and U swap roles).
  void bind(const double* blocks, int bsz, int first, int m_, bool reversed, bool half_couplings) {
    b = bsz;
    m = m_;
    half = half_couplings && kCanHalve;
    lo = reversed ? H : 0;
    uo = reversed ? 0 : H;
    const long bb = static_cast<long>(b) * b;
    Lp.assign(static_cast<size_t>(m), nullptr);
    Dp = Up = Lp;
    off.assign(static_cast<size_t>(m), 0);
    for (int i = 0; i < m; ++i) {
      const long j = first + (reversed ? m - 1 - i : i);
      const double* base = blocks + 3 * bb * j;
      Lp[static_cast<size_t>(i)] = reversed ? base + 2 * bb : base;
      Dp[static_cast<size_t>(i)] = base + bb;
      Up[static_cast<size_t>(i)] = reversed ? base : base + 2 * bb;
      off[static_cast<size_t>(i)] = j;
    }
  }

  /// The start block's LU has no pivot below kStartPivot times its largest (Eigen's rcond()
  /// estimate is no test: it returns 1 for an exactly singular matrix).
  bool regular_start() const {
    const Eigen::VectorXd d = lu0.matrixLU().diagonal().cwiseAbs();
    const double lo = d.minCoeff(), hi = d.maxCoeff();
    return std::isfinite(lo) && std::isfinite(hi) && hi > 0.0 && lo > kStartPivot * hi;
  }

  void factor() {
    lu.resize(static_cast<size_t>(m));
    if (m == 0) return;
    for (int want = 1;; ++want) {
      q = std::min(want, m);
      Dyn M = Dyn::Zero(q * b, q * b);
      for (int i = 0; i < q; ++i) {
        const auto I = static_cast<size_t>(i);
        M.block(i * b, i * b, b, b) = CMap(Dp[I], b, b);
        if (i > 0) M.block(i * b, (i - 1) * b, b, b) = CMap(Lp[I], b, b);
        if (i + 1 < q) M.block(i * b, (i + 1) * b, b, b) = CMap(Up[I], b, b);
      }
      lu0.compute(M);
      if (q == m || want == kMaxMerge || regular_start()) break;
    }
    C.resize(static_cast<size_t>(half ? q : m));  // half couplings: only C_{q-1}
    if (half) X.resize(static_cast<size_t>(m));
    if (q < m) {
      Dyn R = Dyn::Zero(q * b, b);
      R.bottomRows(b) = CMap(Up[static_cast<size_t>(q - 1)], b, b);
      E0 = lu0.solve(R);
      C[static_cast<size_t>(q - 1)] = E0.bottomRows(b);
    }
    Mat S(b, b);
    for (int k = q; k < m; ++k) {
      const auto K = static_cast<size_t>(k);
      S = CMap(Dp[K], b, b);
      if (half && k > q) {
        if constexpr (kCanHalve)
          subtract_product<B>(S.template middleRows<H>(lo), X[K - 1].template middleCols<H>(uo),
                              CMap(Up[K - 1]).template middleRows<H>(uo));
      } else {
        subtract_product<B>(S, CMap(Lp[K], b, b), C[K - 1]);
      }
      lu[K].compute(S);
      if (k + 1 == m) continue;
      if (!half) lu_solve_rows<B>(lu[K], CMap(Up[K], b, b), C[K]);
      else if constexpr (kCanHalve) lu_solve_right<B, H>(lu[K], CMap(Lp[K + 1]).template middleRows<H>(lo), X[K]);
    }
  }

  /// y = A^{-1} x on this chain's blocks (x and y in natural layout; other blocks untouched).
  void solve(const double* x, double* y) const {
    forward(x, y);
    backward(y);
  }

  /// The forward elimination of x into y (natural layout). Afterwards the block at the
  /// chain's last position is final: it is that block of A^{-1} x.
  void forward(const double* x, double* y) const {
    if (m == 0) return;
    zq.resize(static_cast<Eigen::Index>(q) * b);
    for (int i = 0; i < q; ++i) zq.segment(i * b, b) = Eigen::Map<const Vec>(x + off[static_cast<size_t>(i)] * b, b);
    zq = lu0.solve(zq);
    for (int i = 0; i < q; ++i) Eigen::Map<Vec>(y + off[static_cast<size_t>(i)] * b, b) = zq.segment(i * b, b);
    Vec z(b);
    for (int k = q; k < m; ++k) {
      const auto K = static_cast<size_t>(k);
      z = Eigen::Map<const Vec>(x + off[K] * b, b);
      eliminate_previous(k, z, y);
      if (half && k + 1 < m) Eigen::Map<Vec>(y + off[K] * b, b) = z;
      else lu_solve_vector(lu[K], z, y + off[K] * b);
    }
  }

  /// z -= (the previous position's contribution) for position k >= q of the forward sweep,
  /// y holding the sweep's values of the positions before k.
  void eliminate_previous(int k, Vec& z, const double* y) const {
    const auto K = static_cast<size_t>(k);
    const Eigen::Map<const Vec> prev(y + off[K - 1] * b, b);
    if (half && k > q) {
      if constexpr (kCanHalve) z.template segment<H>(lo).noalias() -= X[K - 1].lazyProduct(prev);
    } else {
      subtract_product<B>(z, CMap(Lp[K], b, b), prev);
    }
  }

  /// Redoes the last position of forward(x, y) with its right-hand side block replaced by
  /// x_last (the other positions are unchanged: the last is eliminated last). Same
  /// operations as forward() on the modified right-hand side, so the same bits.
  void forward_last(const double* x, const Vec& x_last, double* y) const {
    if (m == 0) return;
    const auto K = static_cast<size_t>(m - 1);
    if (m > q) {
      Vec z = x_last;
      eliminate_previous(m - 1, z, y);
      lu_solve_vector(lu[K], z, y + off[K] * b);
      return;
    }
    for (int i = 0; i + 1 < q; ++i)
      zq.segment(i * b, b) = Eigen::Map<const Vec>(x + off[static_cast<size_t>(i)] * b, b);
    zq.segment((q - 1) * b, b) = x_last;
    zq = lu0.solve(zq);
    for (int i = 0; i < q; ++i) Eigen::Map<Vec>(y + off[static_cast<size_t>(i)] * b, b) = zq.segment(i * b, b);
  }

  /// The back substitution that completes forward(): y becomes A^{-1} x.
  void backward(double* y) const {
    if (m == 0) return;
    for (int k = m - 2; k >= q; --k) {
      const auto K = static_cast<size_t>(k);
      const Eigen::Map<const Vec> next(y + off[K + 1] * b, b);
      if (!half) {
        subtract_product<B>(Eigen::Map<Vec>(y + off[K] * b, b), C[K], next);
      } else if constexpr (kCanHalve) {
        Vec z = Eigen::Map<const Vec>(y + off[K] * b, b);
        z.template segment<H>(uo).noalias() -= CMap(Up[K]).template middleRows<H>(uo).lazyProduct(next);
        lu_solve_vector(lu[K], z, y + off[K] * b);
      }
    }
    if (q < m) {
      const Vec yq = Eigen::Map<const Vec>(y + off[static_cast<size_t>(q)] * b, b);
      for (int i = 0; i < q; ++i)
        Eigen::Map<Vec>(y + off[static_cast<size_t>(i)] * b, b).noalias() -= E0.middleRows(i * b, b) * yq;
    }
  }

  /// (A^{-1})_{last,last} R.
  Mat last_last(const Mat& R) const {
    if (m > q) return lu.back().solve(R);
    Dyn Z = Dyn::Zero(q * b, b);
    Z.bottomRows(b) = R;
    return lu0.solve(Z).bottomRows(b);
  }
  /// (A^{-1})_{last,first} R: forward elimination of the right-hand side e_first R (the
  /// last block of the solution is the last block after the forward sweep).
  Mat last_first(const Mat& R) const {
    Dyn Z = Dyn::Zero(q * b, b);
    Z.topRows(b) = R;
    Mat W = lu0.solve(Z).bottomRows(b);
    for (int k = q; k < m; ++k) {
      const auto K = static_cast<size_t>(k);
      W = lu[K].solve(-(CMap(Lp[K], b, b) * W));
    }
    return W;
  }

  double min_rcond() const {
    double r = m > 0 ? lu0.rcond() : 1.0;
    for (int k = q; k < m; ++k) r = std::min(r, lu[static_cast<size_t>(k)].rcond());
    return r;
  }
};

template <int B>
struct Factors final : BlockTridiagonalFactors {
  using Mat = Eigen::Matrix<double, B, B>;
  using Vec = Eigen::Matrix<double, B, 1>;
  using CMap = Eigen::Map<const Mat>;
  using VMap = Eigen::Map<const Vec>;

  int b = 0, n = 0, m = 0, rank = 0, ranks = 1;
  bool has_left = false, has_sep = false;
  Chain<B> fwd, rev;        ///< interior in natural order (when a separator follows) / reversed
  const Chain<B>* solver = nullptr;
  std::vector<double> red;  ///< separator system, [L, D, U] per separator
  std::vector<double> usep; ///< every rank's U of its separator (coupling to the next rank)
  Chain<B> red_chain;
  mutable std::vector<double> z, w, xs, rhs;

  const double* L(const double* blocks, long j) const { return blocks + 3L * b * b * j; }
  const double* D(const double* blocks, long j) const { return blocks + 3L * b * b * j + static_cast<long>(b) * b; }
  const double* U(const double* blocks, long j) const { return blocks + 3L * b * b * j + 2L * b * b; }

  void factor(const double* blocks, int n_, int b_, int rank_, int ranks_, const BlockExchange& exchange,
              bool half) override {
    b = b_;
    n = n_;
    rank = rank_;
    ranks = ranks_;
    has_left = rank > 0;
    has_sep = rank + 1 < ranks;
    m = has_sep ? n - 1 : n;
    const bool need_fwd = has_sep || !has_left;
    if (need_fwd) {
      fwd.bind(blocks, b, 0, m, false, half);
      fwd.factor();
    }
    if (has_left) {
      rev.bind(blocks, b, 0, m, true, half);
      rev.factor();
    }
    solver = need_fwd ? &fwd : &rev;
    if (ranks == 1) return;

    // This rank's contribution to the separator system (5 b x b blocks):
    //   [0] D_s - L_s (A^-1)_{last,last} U_{m-1}   (own separator s; from the interior)
    //   [1] -L_s (A^-1)_{last,first} L_0          (s's coupling to the previous separator)
    //   [2] U_s                                    (s's coupling to the next rank's first node)
    //   [3] (A^-1)_{first,first} L_0               (for the previous separator's row)
    //   [4] (A^-1)_{first,last} U_{m-1}            (ditto, coupling to this rank's separator)
    const long bb = static_cast<long>(b) * b;
    std::vector<double> mine(static_cast<size_t>(5 * bb), 0.0);
    auto put = [&](int slot, const Mat& M) { Eigen::Map<Mat>(mine.data() + slot * bb, b, b) = M; };
    // A rank holding only its separator (m = 0) has no interior: its separator couples
    // directly to the previous one ([1] = L_s, [4] = -I so that the previous row gets +U).
    const long s = n - 1;
    if (has_sep) {
      const Mat Ls = CMap(L(blocks, s), b, b);
      if (m > 0) {
        put(0, CMap(D(blocks, s), b, b) - Ls * fwd.last_last(CMap(U(blocks, m - 1), b, b)));
        if (has_left) put(1, -(Ls * fwd.last_first(CMap(L(blocks, 0), b, b))));
      } else {
        put(0, CMap(D(blocks, s), b, b));
        if (has_left) put(1, Ls);
      }
      put(2, CMap(U(blocks, s), b, b));
    }
    if (has_left) {
      if (m > 0) {
        put(3, rev.last_last(CMap(L(blocks, 0), b, b)));
        if (has_sep) put(4, rev.last_first(CMap(U(blocks, m - 1), b, b)));
      } else {
        put(4, -Mat::Identity(b, b));
      }
    }
    const std::vector<double> all = exchange(mine);
    auto got = [&](int r, int slot) { return CMap(all.data() + (5L * r + slot) * bb, b, b); };
    const int ns = ranks - 1;  // separators: the last node of ranks 0 .. ranks-2
    red.assign(static_cast<size_t>(3 * bb * ns), 0.0);
    usep.assign(static_cast<size_t>(bb * ns), 0.0);
    for (int k = 0; k < ns; ++k) {
      double* base = red.data() + 3 * bb * k;
      const Mat Us = got(k, 2);
      Eigen::Map<Mat>(usep.data() + bb * k, b, b) = Us;
      if (k > 0) Eigen::Map<Mat>(base, b, b) = got(k, 1);
      Eigen::Map<Mat>(base + bb, b, b) = got(k, 0) - Us * got(k + 1, 3);
      if (k + 1 < ns) Eigen::Map<Mat>(base + 2 * bb, b, b) = -(Us * got(k + 1, 4));
    }
    red_chain.bind(red.data(), b, 0, ns, false, false);
    red_chain.factor();
    z.assign(static_cast<size_t>(n) * b, 0.0);
    w.assign(static_cast<size_t>(n) * b, 0.0);
    xs.assign(static_cast<size_t>(ns) * b, 0.0);
    rhs.assign(static_cast<size_t>(ns) * b, 0.0);
  }

  void solve(const double* x, double* y, const double* blocks,
             const BlockExchange& exchange) const override {
    if (ranks == 1) {
      solver->solve(x, y);
      return;
    }
    // 1. Interior solve with the separators at zero; 2. the separators' right-hand sides
    // (every rank's) and the separator system, solved on every rank; 3. the interior again
    // with the separators' values moved to the right-hand side.
    // A rank at either end of the rod has one separator, coupled to its chain's last
    // position (rank 0: the forward chain ends at its separator; the last rank: the reversed
    // chain ends next to the previous rank's separator). There step 1 is only the forward
    // elimination (the last position, which is all step 2 needs, is final after it) and step
    // 3 redoes that last position with the separator's term on its right-hand side and
    // back-substitutes: one sweep over the interior instead of two solves, same results.
    const bool one_sweep = has_left != has_sep && m > 0;
    if (one_sweep)
      solver->forward(x, z.data());
    else
      solver->solve(x, z.data());
    std::vector<double> mine(static_cast<size_t>(2 * b), 0.0);
    const long s = n - 1;
    if (has_sep) {
      Eigen::Map<Vec>(mine.data(), b) = VMap(x + s * b, b);
      if (m > 0)
        Eigen::Map<Vec>(mine.data(), b).noalias() -= CMap(L(blocks, s), b, b) * VMap(z.data() + (m - 1L) * b, b);
    }
    if (has_left && m > 0) Eigen::Map<Vec>(mine.data() + b, b) = VMap(z.data(), b);
    const std::vector<double> all = exchange(mine);
    const int ns = ranks - 1;
    for (int k = 0; k < ns; ++k)
      Eigen::Map<Vec>(rhs.data() + static_cast<long>(k) * b, b) =
          VMap(all.data() + 2L * b * k, b) -
          CMap(usep.data() + static_cast<long>(b) * b * k, b, b) * VMap(all.data() + 2L * b * (k + 1) + b, b);
    red_chain.solve(rhs.data(), xs.data());
    if (has_sep) Eigen::Map<Vec>(y + s * b, b) = VMap(xs.data() + static_cast<long>(rank) * b, b);
    if (m == 0) return;
    if (one_sweep) {
      // The interior occupies blocks 0 .. m-1 on both end ranks (rank 0: nodes 0 .. n-2; the
      // last rank: its nodes 0 .. m-1 with the separator to the left of node 0).
      std::copy(z.begin(), z.begin() + static_cast<long>(m) * b, y);
      const long j = has_sep ? m - 1L : 0L;  // the interior node next to the separator
      Vec xl = VMap(x + j * b, b);
      if (has_sep)
        xl.noalias() -= CMap(U(blocks, j), b, b) * VMap(xs.data() + static_cast<long>(rank) * b, b);
      else
        xl.noalias() -= CMap(L(blocks, j), b, b) * VMap(xs.data() + (rank - 1L) * b, b);
      solver->forward_last(x, xl, y);
      solver->backward(y);
      return;
    }
    std::copy(x, x + static_cast<long>(m) * b, w.begin());
    if (has_left)
      Eigen::Map<Vec>(w.data(), b).noalias() -=
          CMap(L(blocks, 0), b, b) * VMap(xs.data() + (rank - 1L) * b, b);
    if (has_sep)
      Eigen::Map<Vec>(w.data() + (m - 1L) * b, b).noalias() -=
          CMap(U(blocks, m - 1), b, b) * VMap(xs.data() + static_cast<long>(rank) * b, b);
    solver->solve(w.data(), y);
  }

  double min_rcond() const override {
    double r = 1.0;
    if (!fwd.lu.empty()) r = std::min(r, fwd.min_rcond());
    if (!rev.lu.empty()) r = std::min(r, rev.min_rcond());
    if (!red_chain.lu.empty()) r = std::min(r, red_chain.min_rcond());
    return r;
  }
};

}  // namespace

bool half_coupled(const double* blocks, int n, int b) {
  if (b % 2 != 0) return false;
  const long bb = static_cast<long>(b) * b, h = b / 2;
  for (long k = 0; k < n; ++k) {
    const double* L = blocks + 3 * bb * k;
    const double* U = L + 2 * bb;
    for (long c = 0; c < b; ++c)
      for (long r = 0; r < h; ++r)
        if (L[c * b + h + r] != 0.0 || U[c * b + r] != 0.0) return false;
  }
  return true;
}

std::unique_ptr<BlockTridiagonalFactors> make_block_tridiagonal_factors(int b) {
  switch (b) {
    case 6: return std::make_unique<Factors<6>>();
    case 12: return std::make_unique<Factors<12>>();
    case 24: return std::make_unique<Factors<24>>();
    default: return std::make_unique<Factors<Eigen::Dynamic>>();
  }
}

}  // namespace traverse::solver

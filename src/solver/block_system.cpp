#include "block_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace traverse::solver {

double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double a : v) {
    if (!std::isfinite(a)) return std::numeric_limits<double>::quiet_NaN();
    m = std::max(m, std::abs(a));
  }
  return m;
}

BlockSystem::BlockSystem(int nodes, int b) : n_(nodes), b_(b) {
  const size_t bb = static_cast<size_t>(b_) * static_cast<size_t>(b_);
  blocks_.assign(3 * bb * static_cast<size_t>(n_), 0.0);
  f_.assign(static_cast<size_t>(n_) * b_, 0.0);
  r_ = dx_ = f_;
  lu_ = make_block_tridiagonal_factors(b_);
}

void BlockSystem::clear() {
  std::fill(blocks_.begin(), blocks_.end(), 0.0);
  std::fill(f_.begin(), f_.end(), 0.0);
}

namespace {

// The bodies of BlockSystem::add and residual_of for a block size B known at compile time (the
// 6 x 6 and 12 x 12 paths: the compiler unrolls the short loops) or B = 0 (b at run time).
template <long B>
void add_block(std::vector<double>& blocks, std::vector<double>& f, long b_run, const rod::LocalBlock& blk) {
  const long b = B > 0 ? B : b_run, bb = b * b;
  const long rows = static_cast<long>(blk.residual.size());
  for (long i = 0; i < rows; ++i) f[static_cast<size_t>(blk.row + i)] += blk.residual(i);
  // Column by column (the blocks and the kernel's Jacobians are both column-major), over the
  // runs of rows that fall in one node.
  for (size_t c = 0; c < blk.cols.size(); ++c) {
    const MatX& J = blk.jac[c];
    if (blk.cols[c] % b != 0 || J.cols() != b || J.rows() != rows)
      throw std::logic_error("block system: a kernel block lies outside the block tridiagonal");
    const long col_node = static_cast<long>(blk.cols[c]) / b;
    for (long i0 = 0; i0 < rows;) {
      const long g = static_cast<long>(blk.row + i0), k = g / b, rr = g % b;
      const long run = std::min(rows - i0, b - rr);
      const long slot = col_node - k + 1;
      if (slot < 0 || slot > 2)
        throw std::logic_error("block system: a kernel block lies outside the block tridiagonal");
      double* dst = blocks.data() + 3 * bb * k + slot * bb + rr;
      for (long cc = 0; cc < b; ++cc) {
        const double* src = J.data() + cc * rows + i0;
        double* d = dst + cc * b;
        for (long i = 0; i < run; ++i) d[i] += src[i];
      }
      i0 += run;
    }
  }
}

template <long B>
void block_residual(const std::vector<double>& blocks, const std::vector<double>& f, long n, long b_run,
                    const std::vector<double>& d, std::vector<double>& r) {
  const long b = B > 0 ? B : b_run, bb = b * b;
  for (long k = 0; k < n; ++k) {
    double* rk = r.data() + k * b;
    const double* fk = f.data() + k * b;
    for (long rr = 0; rr < b; ++rr) rk[rr] = 0.0;
    const double* row_blocks = blocks.data() + 3 * bb * k;
    for (long slot = 0; slot < 3; ++slot) {  // column-major blocks: columns times entries
      const long node = k - 1 + slot;
      if (node < 0 || node >= n) continue;
      const double* blk = row_blocks + slot * bb;
      const double* v = d.data() + node * b;
      for (long cc = 0; cc < b; ++cc) {
        const double vc = v[cc];
        const double* col = blk + cc * b;
        for (long rr = 0; rr < b; ++rr) rk[rr] += col[rr] * vc;
      }
    }
    for (long rr = 0; rr < b; ++rr) rk[rr] = fk[rr] - rk[rr];
  }
}

}  // namespace

void BlockSystem::add(const rod::LocalBlock& blk) {
  if (b_ == 6) return add_block<6>(blocks_, f_, b_, blk);
  if (b_ == 12) return add_block<12>(blocks_, f_, b_, blk);
  add_block<0>(blocks_, f_, b_, blk);
}

void BlockSystem::factor() {
  const BlockExchange none;  // one process: never called
  lu_->factor(blocks_.data(), n_, b_, 0, 1, none);
}

void BlockSystem::residual_of(const std::vector<double>& d, std::vector<double>& r) const {
  if (b_ == 6) return block_residual<6>(blocks_, f_, n_, b_, d, r);
  if (b_ == 12) return block_residual<12>(blocks_, f_, n_, b_, d, r);
  block_residual<0>(blocks_, f_, n_, b_, d, r);
}

double BlockSystem::solve(std::vector<double>& d, double nb, double tolerance) {
  const BlockExchange none;
  d.resize(f_.size());
  lu_->solve(f_.data(), d.data(), blocks_.data(), none);
  double worst = 0.0;
  for (int pass = 0; pass <= 2; ++pass) {
    residual_of(d, r_);
    const double nr = max_abs(r_);
    const double q = nb > 0.0 ? nr / nb : nr;
    worst = std::isfinite(q) ? q : std::numeric_limits<double>::infinity();
    if (worst <= tolerance || pass == 2 || std::isinf(worst)) break;
    lu_->solve(r_.data(), dx_.data(), blocks_.data(), none);
    for (size_t i = 0; i < d.size(); ++i) d[i] = d[i] + dx_[i];
  }
  return worst;
}

}  // namespace traverse::solver

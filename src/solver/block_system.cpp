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

void BlockSystem::add(const rod::LocalBlock& blk) {
  const long b = b_, bb = b * b;
  for (Eigen::Index i = 0; i < blk.residual.size(); ++i) {
    const long g = static_cast<long>(blk.row + i), k = g / b, rr = g % b;
    f_[static_cast<size_t>(g)] += blk.residual(i);
    double* row_blocks = blocks_.data() + 3 * bb * k;
    for (size_t c = 0; c < blk.cols.size(); ++c) {
      const long slot = static_cast<long>(blk.cols[c]) / b - k + 1;
      if (slot < 0 || slot > 2 || blk.cols[c] % b != 0 || blk.jac[c].cols() != b)
        throw std::logic_error("block system: a kernel block lies outside the block tridiagonal");
      double* dst = row_blocks + slot * bb + rr;
      const MatX& J = blk.jac[c];
      for (long cc = 0; cc < b; ++cc) dst[cc * b] += J(i, cc);
    }
  }
}

void BlockSystem::factor() {
  const BlockExchange none;  // one process: never called
  lu_->factor(blocks_.data(), n_, b_, 0, 1, none);
}

void BlockSystem::residual_of(const std::vector<double>& d, std::vector<double>& r) const {
  const long b = b_, bb = b * b;
  for (long k = 0; k < n_; ++k) {
    const double* row_blocks = blocks_.data() + 3 * bb * k;
    for (long rr = 0; rr < b; ++rr) {
      double s = 0.0;
      for (long slot = 0; slot < 3; ++slot) {
        const long node = k - 1 + slot;
        if (node < 0 || node >= n_) continue;
        const double* blk = row_blocks + slot * bb + rr;
        const double* v = d.data() + node * b;
        for (long cc = 0; cc < b; ++cc) s += blk[cc * b] * v[cc];
      }
      r[static_cast<size_t>(k * b + rr)] = f_[static_cast<size_t>(k * b + rr)] - s;
    }
  }
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

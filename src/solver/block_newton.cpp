#include "block_newton.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace traverse::solver {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// max |v_i|, or NaN when some entry is not finite.
double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double a : v) {
    if (!std::isfinite(a)) return std::numeric_limits<double>::quiet_NaN();
    m = std::max(m, std::abs(a));
  }
  return m;
}
}  // namespace

BlockNewton::BlockNewton(const rod::StepAssembly& assembly, BlockNewtonOptions options)
    : asm_(assembly), opt_(options) {
  const int nodes = asm_.model().num_cells + 1;
  if (asm_.first_owned_node() != 0 || asm_.num_owned_nodes() != nodes || asm_.num_ghosted_nodes() != nodes)
    throw std::invalid_argument("BlockNewton: the assembly must own every node of the rod (one rank)");
  n_ = nodes;
  b_ = asm_.unknowns_per_node();
  const size_t bb = static_cast<size_t>(b_) * static_cast<size_t>(b_);
  blocks_.assign(3 * bb * static_cast<size_t>(n_), 0.0);
  f_.assign(static_cast<size_t>(n_) * b_, 0.0);
  d_ = r_ = dx_ = x_old_ = f_;
  lu_ = make_block_tridiagonal_factors(b_);
}

double BlockNewton::evaluate(const std::vector<double>& x) {
  const auto t0 = std::chrono::steady_clock::now();
  std::fill(blocks_.begin(), blocks_.end(), 0.0);
  std::fill(f_.begin(), f_.end(), 0.0);
  const long b = b_, bb = b * b;
  dropped_ = asm_.for_each_block(x.data(), [&](const rod::LocalBlock& blk) {
    for (Eigen::Index i = 0; i < blk.residual.size(); ++i) {
      const long g = static_cast<long>(blk.row + i), k = g / b, rr = g % b;
      f_[static_cast<size_t>(g)] += blk.residual(i);
      double* row_blocks = blocks_.data() + 3 * bb * k;
      for (size_t c = 0; c < blk.cols.size(); ++c) {
        const long slot = static_cast<long>(blk.cols[c]) / b - k + 1;
        if (slot < 0 || slot > 2 || blk.cols[c] % b != 0 || blk.jac[c].cols() != b)
          throw std::logic_error("BlockNewton: a kernel block lies outside the block tridiagonal");
        double* dst = row_blocks + slot * bb + rr;
        const MatX& J = blk.jac[c];
        for (long cc = 0; cc < b; ++cc) dst[cc * b] += J(i, cc);
      }
    }
  });
  ++n_f_;
  t_asm_ += seconds_since(t0);
  return max_abs(f_);
}

void BlockNewton::residual_of(const std::vector<double>& d, std::vector<double>& r) const {
  // The rows' entries in column order (nodes k-1, k, k+1), as a CRS product sums them.
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

double BlockNewton::solve_linear(double nb) {
  const BlockExchange none;  // one rank: never called
  lu_->solve(f_.data(), d_.data(), blocks_.data(), none);
  double worst = 0.0;
  for (int pass = 0; pass <= 2; ++pass) {
    residual_of(d_, r_);
    const double nr = max_abs(r_);
    const double q = nb > 0.0 ? nr / nb : nr;
    worst = std::isfinite(q) ? q : std::numeric_limits<double>::infinity();
    if (worst <= opt_.linear_tolerance || pass == 2 || std::isinf(worst)) break;
    lu_->solve(r_.data(), dx_.data(), blocks_.data(), none);
    for (size_t i = 0; i < d_.size(); ++i) d_[i] = d_[i] + dx_[i];
  }
  return worst;
}

NewtonReport BlockNewton::solve(std::vector<double>& x) {
  if (x.size() != f_.size()) throw std::invalid_argument("BlockNewton::solve: x has the wrong size");
  // As NewtonSolver (NOX): an exception inside the kernels or the LU is a failed solve.
  try {
    return iterate(x);
  } catch (const std::exception& e) {
    NewtonReport rep;
    rep.status = std::string("failed: exception: ") + e.what();
    rep.residual_norm = std::numeric_limits<double>::quiet_NaN();
    return rep;
  }
}

NewtonReport BlockNewton::iterate(std::vector<double>& x) {
  NewtonReport rep;
  double nf = evaluate(x);
  rep.residual_history.push_back(nf);
  rep.update_wrms = 1e12;  // NOX's value before the first update
  const double N = static_cast<double>(x.size());
  int it = 0;
  bool linear_ok = true;  // NOX's NormWRMS also asks the linear solve's achieved tolerance <= 0.5
  for (;;) {
    if (!std::isfinite(nf)) {
      rep.status = "failed: non-finite residual";
      break;
    }
    if (it > 0 && nf < opt_.residual_tolerance && rep.update_wrms < 1.0 && linear_ok) {
      rep.converged = true;
      rep.status = "converged";
      break;
    }
    if (it >= opt_.max_iterations) {
      rep.status = "failed: no convergence in " + std::to_string(opt_.max_iterations) + " Newton iterations";
      break;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const BlockExchange none;
    lu_->factor(blocks_.data(), n_, b_, 0, 1, none);
    ++n_lu_;
    t_lu_ += seconds_since(t0);
    const double achieved = solve_linear(nf);
    x_old_ = x;
    for (size_t i = 0; i < x.size(); ++i) x[i] = x_old_[i] + (-d_[i]);
    ++it;
    nf = evaluate(x);
    rep.residual_history.push_back(nf);
    // NOX's NormWRMS: sqrt(sum ((x - x_old) / (rtol |x_old| + atol))^2 / N).
    double ss = 0.0;
    for (size_t i = 0; i < x.size(); ++i) {
      const double w = 1.0 / (opt_.update_relative_tolerance * std::abs(x_old_[i]) + opt_.update_absolute_tolerance);
      const double u = (x[i] - x_old_[i]) * w;
      ss += u * u;
    }
    rep.update_wrms = std::sqrt(ss) / std::sqrt(N);
    linear_ok = achieved <= 0.5;
  }
  rep.iterations = it;
  rep.residual_norm = nf;
  return rep;
}

}  // namespace traverse::solver

#include "traverse/rod/rod_loads.hpp"

#include <algorithm>
#include <cmath>

namespace traverse::rod {

PointLoadWeights point_load_weights(double sigma, int num_cells, double ds) {
  PointLoadWeights w;
  const int N = num_cells;
  w.last = N;
  const double L = N * ds;
  const double tol = 1e-12 * L;
  if (!(sigma >= -tol && sigma <= L + tol)) return w;  // off the rod (or NaN)
  w.on_rod = true;
  const double x = std::clamp(sigma / ds, 0.0, static_cast<double>(N));
  const int k = std::clamp(static_cast<int>(std::floor(x)) + 1, 1, N);
  const double xi = std::clamp(x - (k - 1), 0.0, 1.0);
  auto share = [&](int node, double v) {
    if (v == 0.0) return;
    if (node == 0) w.left += v;
    else if (node == N) w.right += v;
    else {
      w.node[static_cast<size_t>(w.count)] = node;
      w.weight[static_cast<size_t>(w.count)] = v;
      ++w.count;
    }
  };
  share(k - 1, 1.0 - xi);
  share(k, xi);
  return w;
}

double point_load_slope(double sigma, int node, int num_cells, double ds) {
  const int N = num_cells;
  const double L = N * ds;
  if (!(sigma >= -1e-12 * L && sigma <= L * (1.0 + 1e-12))) return 0.0;
  auto cell_slope = [&](int k) {
    if (node == k - 1) return -1.0 / ds;
    if (node == k) return 1.0 / ds;
    return 0.0;
  };
  const double x = std::clamp(sigma / ds, 0.0, static_cast<double>(N));
  const double on = std::round(x);
  if (std::abs(x - on) <= 1e-9 * std::max(1.0, x) && on > 0.0 && on < N) {
    const int k = static_cast<int>(on);
    return 0.5 * (cell_slope(k) + cell_slope(k + 1));
  }
  return cell_slope(std::clamp(static_cast<int>(std::floor(x)) + 1, 1, N));
}

MassPathSegment mass_path_in_cell(double sigma_old, double sigma_new, int cell, int num_cells, double ds) {
  MassPathSegment seg;
  const int N = num_cells;
  const double L = N * ds;
  if (cell < 1 || cell > N || !std::isfinite(sigma_old) || !std::isfinite(sigma_new)) return seg;
  const double lo = (cell - 1) * ds, hi = cell == N ? L : cell * ds;
  if (sigma_old == sigma_new) {  // at rest during the step
    const double s = sigma_old;
    if (!(s >= 0.0 && s <= L)) return seg;
    const int k = std::clamp(static_cast<int>(std::floor(s / ds)) + 1, 1, N);
    if (k != cell) return seg;
    seg.valid = true;
    seg.tau_a = 0.0;
    seg.tau_b = 1.0;
    seg.s_a = seg.s_b = s;
    return seg;
  }
  // tau at which the path passes the cell's ends (each node's crossing computed by the same
  // expression for both of its cells, so neighbouring segments share their end point).
  const double d = sigma_new - sigma_old;
  const double s_lo = std::max(lo, 0.0), s_hi = std::min(hi, L);
  const double t_lo = (s_lo - sigma_old) / d, t_hi = (s_hi - sigma_old) / d;
  const bool forward = d > 0.0;  // then t_lo < t_hi
  const double t_in = forward ? t_lo : t_hi, t_out = forward ? t_hi : t_lo;
  seg.tau_a = std::max(0.0, t_in);
  seg.tau_b = std::min(1.0, t_out);
  if (!(seg.tau_b > seg.tau_a)) return seg;
  seg.valid = true;
  seg.s_a = seg.tau_a == t_in ? (forward ? s_lo : s_hi) : sigma_old;
  seg.s_b = seg.tau_b == t_out ? (forward ? s_hi : s_lo) : sigma_new;
  return seg;
}

bool line_mass_part(double sigma, int cell, int num_cells, double ds, double& l, double& r) {
  const double L = num_cells * ds, tol = 1e-12 * L;
  if (cell < 1 || cell > num_cells || !(sigma >= -tol && sigma <= L + tol)) return false;
  l = std::max(sigma - ds, (cell - 1) * ds);
  r = std::min(sigma + ds, cell * ds);
  return r > l;
}

}  // namespace traverse::rod

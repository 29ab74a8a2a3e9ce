#include "traverse/rod/time_error.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

namespace traverse::rod {

namespace {
/// The step's amplification matrix on y' = lambda y, z = lambda dt, for (y, w = dt yt):
///   (1 - at) w1 + at w0 = z ((1 - bt) y1 + bt y0),  y1 = y0 + (1 - gt) w0 + gt w1;
/// its eigenvalue nearest e^z (the principal root).
double principal_root(const AlphaParameters& a, double z) {
  // y1 [(1 - at)/gt - z (1 - bt)] = y0 [(1 - at)/gt + z bt] + w0 [(1 - at)(1 - gt)/gt - at]
  const double d = (1.0 - a.at) / a.gt - z * (1.0 - a.bt);
  const double a11 = ((1.0 - a.at) / a.gt + z * a.bt) / d;
  const double a12 = ((1.0 - a.at) * (1.0 - a.gt) / a.gt - a.at) / d;
  // w1 = (y1 - y0 - (1 - gt) w0) / gt
  const double a21 = (a11 - 1.0) / a.gt;
  const double a22 = (a12 - (1.0 - a.gt)) / a.gt;
  const double tr = a11 + a22, det = a11 * a22 - a12 * a21;
  const std::complex<double> disc = std::sqrt(std::complex<double>(tr * tr / 4.0 - det));
  const std::complex<double> r1 = tr / 2.0 + disc, r2 = tr / 2.0 - disc;
  const double ez = std::exp(z);
  return std::abs(r1 - ez) < std::abs(r2 - ez) ? r1.real() : r2.real();
}

constexpr int kPosition = static_cast<int>(ErrorGroup::position);
constexpr int kOrientation = static_cast<int>(ErrorGroup::orientation);

Vec3 group(const NodeLevel& y, int g) { return y.segment<3>(3 * g); }

/// The displacement-type groups' increments over a step of h by the trapezoidal rule.
Vec3 trapezoid(const NodeLevel& a, const NodeLevel& b, int g, double h) { return 0.5 * h * (group(a, g) + group(b, g)); }
}  // namespace

NodeLevel node_level(const RodNode& n) {
  NodeLevel y;
  y.segment<3>(0) = n.R.transpose() * n.y.segment<3>(var::u);
  y.segment<3>(3) = n.R.transpose() * n.y.segment<3>(var::omega);
  y.segment<9>(6) = n.y.head<9>();
  return y;
}

double local_error_constant(const AlphaParameters& alpha) {
  // (R(z) - e^z) / z^3 = c + d z + e z^2 + O(z^3): three small z remove d and e.
  auto coefficient = [&](double z) { return (principal_root(alpha, z) - std::exp(z)) / (z * z * z); };
  const double z = 5e-3;
  return 8.0 / 3.0 * coefficient(z) - 2.0 * coefficient(2.0 * z) + coefficient(4.0 * z) / 3.0;
}

void TimeErrorParts::include(int g, const Vec3& estimate, const Vec3& value) {
  const double e = estimate.norm();
  error[g] = std::isnan(e) ? HUGE_VAL : std::max(error[g], e);  // a NaN estimate is no estimate
  size[g] = std::max(size[g], value.norm());
}

void LevelHistory::start(std::vector<NodeLevel> y) {
  *this = LevelHistory();
  displacement.assign(y.size(), Vec3::Zero());
  rotation.assign(y.size(), Vec3::Zero());
  y0 = std::move(y);
  levels = 1;
}

void LevelHistory::push(std::vector<NodeLevel> y_new, double h) {
  for (size_t j = 0; j < y_new.size(); ++j) {
    displacement[j] += trapezoid(y0[j], y_new[j], kPosition, h);
    rotation[j] += trapezoid(y0[j], y_new[j], kOrientation, h);
  }
  y2 = std::move(y1);
  y1 = std::move(y0);
  y0 = std::move(y_new);
  h2 = h1;
  h1 = h;
  levels = std::min(levels + 1, 3);
}

ExtrapolationWeights extrapolation_weights(double h, double h1, double h2, double c) {
  ExtrapolationWeights w;
  // Lagrange weights of t_n, t_{n-1} = t_n - h1, t_{n-2} = t_n - h1 - h2 at t_n + h.
  w.w0 = (h + h1) * (h + h1 + h2) / (h1 * (h1 + h2));
  w.w1 = -h * (h + h1 + h2) / (h1 * h2);
  w.w2 = h * (h + h1) / (h2 * (h1 + h2));
  const double K = h * (h + h1) * (h + h1 + h2) / 6.0, C = c * h * h * h;
  w.factor = C / K;
  return w;
}

TimeErrorParts extrapolation_error(const std::vector<NodeLevel>& y_new, const LevelHistory& history, double h,
                                   double c) {
  const ExtrapolationWeights w = extrapolation_weights(h, history.h1, history.h2, c);
  const double h1 = history.h1;
  TimeErrorParts parts;
  for (size_t j = 0; j < y_new.size(); ++j) {
    const NodeLevel &y = y_new[j], &a = history.y0[j], &b = history.y1[j];
    // Displacements: h^3 / 12 times the second divided difference of their rates.
    const NodeLevel second = 2.0 / (h + h1) * ((y - a) / h - (a - b) / h1);
    const NodeLevel e_disp = h * h * h / 12.0 * second;
    parts.include(kPosition, group(e_disp, kPosition),
                  history.displacement[j] + trapezoid(a, y, kPosition, h));
    parts.include(kOrientation, group(e_disp, kOrientation),
                  history.rotation[j] + trapezoid(a, y, kOrientation, h));
    const NodeLevel pred = w.w0 * a + w.w1 * b + w.w2 * history.y2[j];
    const NodeLevel e_state = w.factor * (y - pred);
    for (int g = 2; g < kErrorGroups; ++g) parts.include(g, group(e_state, g), group(y, g));
  }
  return parts;
}

TimeErrorParts doubling_error(const std::vector<NodeLevel>& full, const std::vector<NodeLevel>& mid,
                              const std::vector<NodeLevel>& half, const LevelHistory& history, double h) {
  TimeErrorParts parts;
  for (size_t j = 0; j < half.size(); ++j) {
    const NodeLevel& a = history.y0[j];
    for (const int g : {kPosition, kOrientation}) {
      const Vec3 d_full = trapezoid(a, full[j], g, h);
      const Vec3 d_half = trapezoid(a, mid[j], g, 0.5 * h) + trapezoid(mid[j], half[j], g, 0.5 * h);
      const Vec3& since_start = g == kPosition ? history.displacement[j] : history.rotation[j];
      parts.include(g, (d_half - d_full) / 3.0, since_start + d_half);
    }
    for (int g = 2; g < kErrorGroups; ++g) parts.include(g, (group(half[j], g) - group(full[j], g)) / 3.0, group(half[j], g));
  }
  return parts;
}

double weighted_error(const TimeErrorParts& parts, const GroupValues& peak, const ErrorWeights& w) {
  double e = 0.0;
  for (int g = 0; g < kErrorGroups; ++g) {
    if (!w.controlled[g] || parts.error[g] == 0.0) continue;
    if (!std::isfinite(parts.error[g])) return HUGE_VAL;
    const double scale = w.absolute[g] + w.relative * std::max({parts.size[g], peak[g], w.floor[g]});
    e = std::max(e, scale > 0.0 ? parts.error[g] / scale : HUGE_VAL);
  }
  return e;
}

GroupValues scale_floors(double length) { return {1e-3 * length, 1e-3, 0.0, 0.0, 0.0}; }

}  // namespace traverse::rod

#include "traverse/beam/uniform_modes.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/SVD>

namespace traverse::beam {

namespace {

using Mat4 = Eigen::Matrix4d;
using Vec4 = Eigen::Vector4d;
constexpr double kPi = constants::pi;

/// 1 / cosh(l) without overflow.
double sech(double l) {
  const double e = std::exp(-std::abs(l));
  return 2.0 * e / (1.0 + e * e);
}

double characteristic_derivative(Support s, double l) {
  switch (s) {
    case Support::SimplySupported:
      return std::cos(l);
    case Support::ClampedFree:
      return -std::sin(l) - sech(l) * std::tanh(l);
    case Support::ClampedClamped:
      return -std::sin(l) + sech(l) * std::tanh(l);
    case Support::ClampedPinned: {
      const double sh = sech(l);
      return std::cos(l) + std::sin(l) * std::tanh(l) - std::cos(l) * sh * sh;
    }
    default:
      throw std::invalid_argument("UniformModes: unknown support");
  }
}

/// Basis values (cos, sin, e^{-l xi}, e^{-l (1-xi)}) and their k-th xi-derivatives divided
/// by l^k, k = 0..3, at xi in {0, 1}.
Eigen::Matrix<double, 4, 4> basis_rows(double l, double xi) {
  const double c = std::cos(l * xi), s = std::sin(l * xi);
  const double e1 = std::exp(-l * xi), e2 = std::exp(-l * (1.0 - xi));
  Eigen::Matrix<double, 4, 4> r;
  r << c, s, e1, e2,      // value
      -s, c, -e1, e2,     // first derivative / l
      -c, -s, e1, e2,     // second derivative / l^2
      s, -c, -e1, e2;     // third derivative / l^3
  return r;
}

enum class EndKind { Clamped, Pinned, Free };

void end_rows(EndKind k, const Eigen::Matrix<double, 4, 4>& b, Mat4& m, int row) {
  int r0 = 0, r1 = 0;
  switch (k) {
    case EndKind::Clamped: r0 = 0; r1 = 1; break;
    case EndKind::Pinned: r0 = 0; r1 = 2; break;
    case EndKind::Free: r0 = 2; r1 = 3; break;
    default: throw std::invalid_argument("UniformModes: unknown end kind");
  }
  m.row(row) = b.row(r0);
  m.row(row + 1) = b.row(r1);
}

std::pair<EndKind, EndKind> ends_of(Support s) {
  switch (s) {
    case Support::SimplySupported: return {EndKind::Pinned, EndKind::Pinned};
    case Support::ClampedFree: return {EndKind::Clamped, EndKind::Free};
    case Support::ClampedClamped: return {EndKind::Clamped, EndKind::Clamped};
    case Support::ClampedPinned: return {EndKind::Clamped, EndKind::Pinned};
    default: throw std::invalid_argument("UniformModes: unknown support");
  }
}

/// Value and xi-derivatives (not scaled by 1/L) of the unnormalised mode in stable form.
struct ModeEval {
  double f, d1, d2;
};
ModeEval eval_mode(const std::array<double, 4>& k, double l, double xi) {
  const double c = std::cos(l * xi), s = std::sin(l * xi);
  const double e1 = std::exp(-l * xi), e2 = std::exp(-l * (1.0 - xi));
  return {k[0] * c + k[1] * s + k[2] * e1 + k[3] * e2,
          l * (-k[0] * s + k[1] * c - k[2] * e1 + k[3] * e2),
          l * l * (-k[0] * c - k[1] * s + k[2] * e1 + k[3] * e2)};
}

/// max over xi in [0, 1] of |Phi(xi)|: dense sampling, then safeguarded Newton on Phi' = 0
/// inside the two sample intervals around the largest sample.
double max_abs(const std::array<double, 4>& k, double l) {
  const int m = 64 * (static_cast<int>(l / kPi) + 2);
  int best = 0;
  double best_val = -1.0;
  for (int j = 0; j <= m; ++j) {
    const double v = std::abs(eval_mode(k, l, static_cast<double>(j) / m).f);
    if (v > best_val) {
      best_val = v;
      best = j;
    }
  }
  double a = static_cast<double>(std::max(best - 1, 0)) / m;
  double b = static_cast<double>(std::min(best + 1, m)) / m;
  double fa = eval_mode(k, l, a).d1, fb = eval_mode(k, l, b).d1;
  if (fa == 0.0) return std::max(best_val, std::abs(eval_mode(k, l, a).f));
  if (fb == 0.0) return std::max(best_val, std::abs(eval_mode(k, l, b).f));
  if ((fa > 0) == (fb > 0)) return best_val;  // maximum at an end point
  double x = 0.5 * (a + b);
  for (int it = 0; it < 100; ++it) {
    const ModeEval e = eval_mode(k, l, x);
    if (e.d1 == 0.0) break;
    if ((e.d1 > 0) == (fa > 0)) {
      a = x;
      fa = e.d1;
    } else {
      b = x;
    }
    double xn = (e.d2 != 0.0) ? x - e.d1 / e.d2 : 0.5 * (a + b);
    if (!(xn > a && xn < b)) xn = 0.5 * (a + b);
    const bool done = std::abs(xn - x) <= 4.0 * std::numeric_limits<double>::epsilon();
    x = xn;
    if (done) break;
  }
  return std::max(best_val, std::abs(eval_mode(k, l, x).f));
}

}  // namespace

const char* to_string(Support s) {
  switch (s) {
    case Support::SimplySupported: return "simply-supported";
    case Support::ClampedFree: return "clamped-free";
    case Support::ClampedClamped: return "clamped-clamped";
    case Support::ClampedPinned: return "clamped-pinned";
    default: throw std::invalid_argument("to_string: unknown support");
  }
}

double UniformModes::characteristic(Support s, double l) {
  switch (s) {
    case Support::SimplySupported: return std::sin(l);
    case Support::ClampedFree: return std::cos(l) + sech(l);
    case Support::ClampedClamped: return std::cos(l) - sech(l);
    case Support::ClampedPinned: return std::sin(l) - std::cos(l) * std::tanh(l);
    default: throw std::invalid_argument("UniformModes: unknown support");
  }
}

double UniformModes::root(Support s, int i) {
  if (i < 1) throw std::invalid_argument("UniformModes::root: mode index starts at 1");
  const double di = static_cast<double>(i);
  // Brackets holding exactly one root (sign of the scaled function at the ends is known):
  //   ClampedFree: ((i-1) pi, i pi); ClampedClamped: (i pi, (i+1) pi);
  //   ClampedPinned: (i pi, i pi + pi/2). Initial guesses are the asymptotic roots.
  double a = 0, b = 0, x = 0;
  switch (s) {
    case Support::SimplySupported: return di * kPi;
    case Support::ClampedFree: a = (di - 1) * kPi; b = di * kPi; x = (di - 0.5) * kPi; break;
    case Support::ClampedClamped: a = di * kPi; b = (di + 1) * kPi; x = (di + 0.5) * kPi; break;
    case Support::ClampedPinned: a = di * kPi; b = (di + 0.5) * kPi; x = (di + 0.25) * kPi; break;
    default: throw std::invalid_argument("UniformModes: unknown support");
  }
  double fa = characteristic(s, a);
  for (int it = 0; it < 200; ++it) {
    const double f = characteristic(s, x);
    if (f == 0.0) return x;
    if ((f > 0) == (fa > 0)) {
      a = x;
      fa = f;
    } else {
      b = x;
    }
    const double d = characteristic_derivative(s, x);
    double xn = (d != 0.0) ? x - f / d : 0.5 * (a + b);
    if (!(xn > a && xn < b)) xn = 0.5 * (a + b);
    const bool done = std::abs(xn - x) <= 2.0 * std::numeric_limits<double>::epsilon() * x ||
                      (b - a) <= 4.0 * std::numeric_limits<double>::epsilon() * x;
    x = xn;
    if (done) break;
  }
  return x;
}

UniformModes::UniformModes(Support support, int n, double length, double EI, double rhoA)
    : support_(support), length_(length), EI_(EI), rhoA_(rhoA) {
  if (n < 1) throw std::invalid_argument("UniformModes: need at least one mode");
  if (!(length > 0) || !(EI > 0) || !(rhoA > 0))
    throw std::invalid_argument("UniformModes: L, EI and rhoA must be positive");
  const auto [left, right] = ends_of(support);
  lambda_.resize(static_cast<std::size_t>(n));
  coef_.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double l = root(support, i + 1);
    lambda_[static_cast<std::size_t>(i)] = l;
    std::array<double, 4> k{};
    if (support == Support::SimplySupported) {
      k = {0.0, 1.0, 0.0, 0.0};
    } else {
      Mat4 m;
      end_rows(left, basis_rows(l, 0.0), m, 0);
      end_rows(right, basis_rows(l, 1.0), m, 2);
      Eigen::JacobiSVD<Mat4> svd(m, Eigen::ComputeFullV);
      const Vec4 v = svd.matrixV().col(3);
      k = {v(0), v(1), v(2), v(3)};
    }
    // Sign and scale.
    double scale = 0.0;
    if (support == Support::ClampedFree) {
      scale = eval_mode(k, l, 1.0).f;  // tip value -> +1
    } else {
      const ModeEval e0 = eval_mode(k, l, 0.0);
      const double sign = (left == EndKind::Clamped) ? (e0.d2 > 0 ? 1.0 : -1.0)
                                                     : (e0.d1 > 0 ? 1.0 : -1.0);
      scale = sign * max_abs(k, l);
    }
    for (double& c : k) c /= scale;
    coef_[static_cast<std::size_t>(i)] = k;
  }
}

VecX UniformModes::betas() const {
  VecX b(size());
  for (Eigen::Index i = 0; i < size(); ++i) b(i) = lambda_[static_cast<std::size_t>(i)] / length_;
  return b;
}

VecX UniformModes::circular_frequencies() const {
  const VecX b = betas();
  return b.array().square() * std::sqrt(EI_ / rhoA_);
}

void UniformModes::evaluate(double x, Eigen::Ref<VecX> phi, Eigen::Ref<VecX> dphi,
                            Eigen::Ref<VecX> ddphi) const {
  const double xi = x / length_;
  const bool exps = support_ != Support::SimplySupported;
  for (std::size_t i = 0; i < lambda_.size(); ++i) {
    const double l = lambda_[i], b = l / length_;
    const std::array<double, 4>& k = coef_[i];
    const double c = std::cos(l * xi), s = std::sin(l * xi);
    double ep = 0.0, em = 0.0;  // C e^{-l xi} + D e^{-l(1-xi)}, C e^{-l xi} - D e^{-l(1-xi)}
    if (exps) {
      const double e1 = k[2] * std::exp(-l * xi), e2 = k[3] * std::exp(-l * (1.0 - xi));
      ep = e1 + e2;
      em = e1 - e2;
    }
    const Eigen::Index j = static_cast<Eigen::Index>(i);
    phi(j) = k[0] * c + k[1] * s + ep;
    dphi(j) = b * (-k[0] * s + k[1] * c - em);
    ddphi(j) = b * b * (-k[0] * c - k[1] * s + ep);
  }
}

void UniformModes::third_derivative(double x, Eigen::Ref<VecX> dddphi) const {
  const double xi = x / length_;
  for (std::size_t i = 0; i < lambda_.size(); ++i) {
    const double l = lambda_[i], b = l / length_;
    const std::array<double, 4>& k = coef_[i];
    const double c = std::cos(l * xi), s = std::sin(l * xi);
    const double e1 = k[2] * std::exp(-l * xi), e2 = k[3] * std::exp(-l * (1.0 - xi));
    dddphi(static_cast<Eigen::Index>(i)) = b * b * b * (k[0] * s - k[1] * c - e1 + e2);
  }
}

}  // namespace traverse::beam

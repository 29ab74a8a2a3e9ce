// The local error estimate of the rod's time step (rod/time_error.hpp, docs/adaptive.md) on a
// problem with a known solution: the harmonic oscillator x' = v, v' = -w^2 x integrated by the
// trapezoidal rule (the box scheme in time). The state (x, v) sits in the u group, the rate v
// in the position group (whose displacement over a step is then x(t + h) - x(t) exactly). The
// estimate must follow the true local error (the step from the numerical level against the
// exact solution from that level) in order (3) and constant (ratio -> 1), for uniform and
// non-uniform step histories, and by step doubling at the start. Also: the error constant of
// the generalised-alpha scheme against the growth factor measured by running its recursion.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "traverse/rod/time_error.hpp"

namespace traverse::rod {
namespace {

constexpr double kW = 2.0 * M_PI;  // angular frequency [rad/s]

struct Osc {
  double x, v;
};
Osc trapezoid_step(const Osc& s, double h) {  // exact solve of the linear TR step
  const double a = 0.5 * h, d = 1.0 + a * a * kW * kW;
  const double x = (s.x * (1.0 - a * a * kW * kW) + 2.0 * a * s.v) / d;
  return {x, s.v - a * kW * kW * (s.x + x)};
}
Osc exact_step(const Osc& s, double h) {
  const double c = std::cos(kW * h), sn = std::sin(kW * h);
  return {s.x * c + s.v / kW * sn, -s.x * kW * sn + s.v * c};
}
NodeLevel level(const Osc& s) {
  NodeLevel y = NodeLevel::Zero();
  y(0) = s.v;       // position group: its rate
  y(6) = s.x;       // u group: the state
  y(7) = s.v;
  return y;
}

struct Measured {
  double est_disp, true_disp, est_state, true_state;
};

/// Steps from x = 1, v = 0.3 to about t = 0.37 with step lengths h g(t), then one step of
/// h g(t): estimate and true local error.
template <class G>
Measured measure(double h, G g) {
  Osc s{1.0, 0.3};
  LevelHistory hist;
  hist.start({level(s)});
  double t = 0.0;
  while (t < 0.37) {
    const double hi = h * g(t);
    s = trapezoid_step(s, hi);
    hist.push({level(s)}, hi);
    t += hi;
  }
  const double hn = h * g(t);
  const Osc num = trapezoid_step(s, hn), ex = exact_step(s, hn);
  const TimeErrorParts p = extrapolation_error({level(num)}, hist, hn, 1.0 / 12.0);
  Measured m;
  m.est_disp = p.error[0];
  m.true_disp = std::abs(0.5 * hn * (s.v + num.v) - (ex.x - s.x));
  m.est_state = p.error[2];
  m.true_state = std::hypot(num.x - ex.x, num.v - ex.v);
  return m;
}

template <class G>
void check_follows(G g, double tol_ratio) {
  std::vector<Measured> ms;
  for (const double h : {0.01, 0.005, 0.0025, 0.00125}) {
    ms.push_back(measure(h, g));
    const Measured& m = ms.back();
    std::printf("  h = %.5f: displacement est %.4e true %.4e (ratio %.4f); state est %.4e true %.4e (ratio %.4f)\n", h,
                m.est_disp, m.true_disp, m.est_disp / m.true_disp, m.est_state, m.true_state, m.est_state / m.true_state);
  }
  for (size_t i = 1; i < ms.size(); ++i) {
    const double od = std::log2(ms[i - 1].true_disp / ms[i].true_disp), oe = std::log2(ms[i - 1].est_disp / ms[i].est_disp);
    const double os = std::log2(ms[i - 1].true_state / ms[i].true_state), oes = std::log2(ms[i - 1].est_state / ms[i].est_state);
    std::printf("  orders: displacement true %.3f est %.3f; state true %.3f est %.3f\n", od, oe, os, oes);
    EXPECT_NEAR(oe, 3.0, 0.25);
    EXPECT_NEAR(oes, 3.0, 0.25);
  }
  EXPECT_NEAR(ms.back().est_disp / ms.back().true_disp, 1.0, tol_ratio);
  EXPECT_NEAR(ms.back().est_state / ms.back().true_state, 1.0, tol_ratio);
}

TEST(TimeError, FollowsTheTrueLocalErrorOnUniformSteps) {
  check_follows([](double) { return 1.0; }, 0.03);
}

// Step lengths varying smoothly by +-30 % (as a controller varies them).
TEST(TimeError, FollowsTheTrueLocalErrorOnNonUniformSteps) {
  check_follows([](double t) { return 1.0 + 0.3 * std::sin(17.0 * t); }, 0.05);
}

TEST(TimeError, StepDoublingEstimatesTheErrorOfTheTwoHalfSteps) {
  for (const double h : {0.02, 0.01, 0.005}) {
    const Osc s{1.0, 0.3};
    LevelHistory hist;
    hist.start({level(s)});
    const Osc full = trapezoid_step(s, h), mid = trapezoid_step(s, 0.5 * h), half = trapezoid_step(mid, 0.5 * h);
    const Osc ex = exact_step(s, h);
    const TimeErrorParts p = doubling_error({level(full)}, {level(mid)}, {level(half)}, hist, h);
    const double true_state = std::hypot(half.x - ex.x, half.v - ex.v);
    const double d_half = 0.25 * h * (s.v + 2.0 * mid.v + half.v);
    const double true_disp = std::abs(d_half - (ex.x - s.x));
    std::printf("  h = %.3f: state est/true %.4f, displacement est/true %.4f\n", h, p.error[2] / true_state,
                p.error[0] / true_disp);
    EXPECT_NEAR(p.error[2] / true_state, 1.0, 0.05);
    EXPECT_NEAR(p.error[0] / true_disp, 1.0, 0.05);
  }
}

TEST(TimeError, ExtrapolationIsExactForQuadratics) {
  const double h = 0.3, h1 = 0.5, h2 = 0.2, tn = 1.0;
  auto q = [](double t) { return 2.0 - 3.0 * t + 0.7 * t * t; };
  const ExtrapolationWeights w = extrapolation_weights(h, h1, h2, 1.0 / 12.0);
  EXPECT_NEAR(w.w0 * q(tn) + w.w1 * q(tn - h1) + w.w2 * q(tn - h1 - h2), q(tn + h), 1e-13);
  const ExtrapolationWeights u = extrapolation_weights(1.0, 1.0, 1.0, 1.0 / 12.0);
  EXPECT_NEAR(u.w0, 3.0, 1e-14);
  EXPECT_NEAR(u.w1, -3.0, 1e-14);
  EXPECT_NEAR(u.w2, 1.0, 1e-14);
  EXPECT_NEAR(u.factor, 1.0 / 12.0, 1e-14);  // (1/12) / K, K = 1
}

// The constant from the amplification matrix against the per-step growth measured by running
// the scheme's recursion on y' = lambda y until its spurious root has decayed.
TEST(TimeError, ErrorConstantMatchesTheSchemesRecursion) {
  EXPECT_NEAR(local_error_constant(AlphaParameters()), 1.0 / 12.0, 1e-7);
  for (const double rho : {0.9, 0.5, 0.0}) {
    const AlphaParameters a = AlphaParameters::from_rho_inf(rho);
    const double z = 0.01;
    double y = 1.0, w = z;  // w = dt yt
    double ratio = 0.0;
    for (int i = 0; i < 400; ++i) {
      // (1 - at) w1 + at w0 = z ((1 - bt) y1 + bt y0), y1 = y0 + (1 - gt) w0 + gt w1
      const double y1 = (y * ((1.0 - a.at) / a.gt + z * a.bt) + w * ((1.0 - a.at) * (1.0 - a.gt) / a.gt - a.at)) /
                        ((1.0 - a.at) / a.gt - z * (1.0 - a.bt));
      const double w1 = (y1 - y - (1.0 - a.gt) * w) / a.gt;
      ratio = y1 / y;
      y = y1;
      w = w1;
    }
    const double measured = (ratio - std::exp(z)) / (z * z * z);
    const double c = local_error_constant(a);
    std::printf("  rho_inf = %.1f: c = %.6f, from the recursion at z = 0.01: %.6f\n", rho, c, measured);
    EXPECT_NEAR(measured, c, 0.02 * std::abs(c) + 1e-3);
  }
}

TEST(TimeError, WeightedErrorUsesTheControlledGroupsAndTheirScales) {
  TimeErrorParts p;
  p.error = {1e-6, 2e-3, 5.0, 0.0, 0.0};
  p.size = {1e-2, 0.5, 1.0, 0.0, 0.0};
  ErrorWeights w;
  w.relative = 1e-3;
  w.floor = scale_floors(1.0);
  w.controlled = {true, true, false, false, false};
  const GroupValues peak{0.1, 0.0, 0.0, 0.0, 0.0};
  // position: 1e-6 / (1e-3 * 0.1) = 0.01; orientation: 2e-3 / (1e-3 * 0.5) = 4
  EXPECT_NEAR(weighted_error(p, peak, w), 4.0, 1e-12);
  w.controlled = {true, false, false, false, false};
  EXPECT_NEAR(weighted_error(p, peak, w), 0.01, 1e-12);
  w.absolute[0] = 1e-4;
  EXPECT_NEAR(weighted_error(p, peak, w), 1e-6 / (1e-4 + 1e-4), 1e-12);
  p.error[0] = NAN;
  EXPECT_TRUE(std::isinf(weighted_error(p, peak, w)));
  // A start from rest: zero size and peak, the floor (1e-3 L) sets the scale.
  TimeErrorParts z;
  z.error[0] = 1e-9;
  w.absolute[0] = 0.0;
  w.controlled = {true, false, false, false, false};
  EXPECT_NEAR(weighted_error(z, GroupValues{}, w), 1e-9 / (1e-3 * 1e-3), 1e-12);
}

}  // namespace
}  // namespace traverse::rod

// Trains of moving forces on a simply supported beam: the response is the superposition of the
// single axle's (linearity), the first mode resonates at v = f1 d / i for loads d apart, and a
// load leaves no first-mode vibration behind at the cancellation speeds v = 2 f1 L / (2 i + 1).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "traverse/beam/beam_simulation.hpp"

using namespace traverse;
using namespace traverse::beam;

namespace {
constexpr double kPi = constants::pi;
constexpr double kL = 25.0, kEI = 3.5e10 * 1.3901, kRhoA = 18358.0;

double f1() { return kPi / (2.0 * kL * kL) * std::sqrt(kEI / kRhoA); }  // first frequency [Hz]

BeamProblem bridge(int n, double dt, double t_end, double zeta) {
  BeamProblem p;
  p.length = kL;
  p.EI = kEI;
  p.rhoA = kRhoA;
  p.n_modes = n;
  p.self_weight = false;
  p.initial_state = InitialState::Rest;
  p.dt = dt;
  p.t_end = t_end;
  if (zeta > 0) {
    p.damping.kind = ModalDamping::Kind::Ratios;
    p.damping.ratios = {zeta};
  }
  return p;
}

void add_force(BeamProblem& p, double P, double v, double delay) {
  MovingLoad f;
  f.kind = LoadKind::Force;
  f.force = -P;
  f.speed = v;
  f.entry_time = delay;
  p.loads.push_back(f);
}

std::vector<double> midspan(BeamProblem p) {
  BeamSimulation sim(std::move(p));
  std::vector<double> w;
  sim.run([&](const BeamSnapshot& s) { w.push_back(s.deflection(0.5 * kL)); });
  return w;
}

double absmax(const std::vector<double>& v) {
  double m = 0;
  for (const double x : v) m = std::max(m, std::abs(x));
  return m;
}

// Peak |w(L/2)| of n equal loads d apart at speed v, until the last has left.
double train_peak(int n, double d, double v, double zeta) {
  BeamProblem p = bridge(4, 2e-3, (kL + (n - 1) * d) / v, zeta);
  for (int a = 0; a < n; ++a) add_force(p, 1e5, v, a * d / v);
  return absmax(midspan(p));
}
}  // namespace

TEST(AxleTrain, ResponseIsTheSuperpositionOfTheSingleAxle) {
  // Three unequal axles at offsets that are whole numbers of steps: the train's w(L/2, t) equals
  // sum_a P_a / P w_single(t - e_a / v) at every step (and so does its peak).
  const double v = 50.0, dt = 1e-3, T = 2.0;
  const std::vector<double> offsets{0.0, 2.5, 17.5}, loads{1.2e5, 1.0e5, 0.7e5};
  BeamProblem train = bridge(6, dt, T, 0.02), single = bridge(6, dt, T, 0.02);
  for (std::size_t a = 0; a < offsets.size(); ++a) add_force(train, loads[a], v, offsets[a] / v);
  add_force(single, 1.0, v, 0.0);
  const std::vector<double> wt = midspan(train), ws = midspan(single);
  std::vector<double> sum(ws.size(), 0.0);
  for (std::size_t a = 0; a < offsets.size(); ++a) {
    const auto shift = static_cast<std::size_t>(std::lround(offsets[a] / v / dt));
    for (std::size_t k = shift; k < ws.size(); ++k) sum[k] += loads[a] * ws[k - shift];
  }
  double worst = 0;
  for (std::size_t k = 0; k < ws.size(); ++k) worst = std::max(worst, std::abs(wt[k] - sum[k]));
  std::cout << "train - superposition: largest difference " << worst / absmax(wt) << " of the peak; peaks "
            << absmax(wt) << " and " << absmax(sum) << " m\n";
  EXPECT_LT(worst, 1e-9 * absmax(wt));
  EXPECT_NEAR(absmax(sum) / absmax(wt), 1.0, 1e-9);
}

TEST(AxleTrain, FirstModeResonatesAtF1DOverI) {
  // 15 loads d = 12 m apart, 1 % damping: the peak over speeds near v_i = f1 d / i lies within
  // 3 % of it, and it stands 50 % above the response halfway between two resonances.
  const int n = 15;
  const double d = 12.0;
  for (const int i : {1, 2}) {
    const double vr = f1() * d / i;
    double best_v = 0, best = 0;
    for (double v = 0.85 * vr; v <= 1.15 * vr; v += 0.005 * vr) {
      const double w = train_peak(n, d, v, 0.01);
      if (w > best) {
        best = w;
        best_v = v;
      }
    }
    const double between = train_peak(n, d, f1() * d / (i + 0.5), 0.01);
    std::cout << "i = " << i << ": v_i = f1 d / i = " << vr << " m/s, peak at " << best_v << " m/s (" << best
              << " m); between resonances " << between << " m\n";
    EXPECT_NEAR(best_v / vr, 1.0, 0.03);
    EXPECT_GT(best, 1.5 * between);
  }
}

TEST(AxleTrain, NoResidualFirstModeAtCancellationSpeeds) {
  // Undamped: after a load has crossed, mode 1 vibrates with an amplitude proportional to
  // S |cos(omega_1 L / (2 v))| / |1 - S^2|, S = pi v / (omega_1 L): zero at v = 2 f1 L / (2 i + 1).
  const double omega1 = 2.0 * kPi * f1();
  auto residual = [&](double v) {
    BeamProblem p = bridge(4, 1e-4, kL / v + 1.0, 0.0);
    add_force(p, 1e5, v, 0.0);
    BeamSimulation sim(p);
    double amp = 0;
    sim.run([&](const BeamSnapshot& s) {
      if (s.t > kL / v) amp = std::max(amp, std::hypot(s.Y(0), s.Ydot(0) / omega1));
    });
    return amp;
  };
  for (const int i : {1, 2}) {
    const double vc = 2.0 * f1() * kL / (2 * i + 1);
    const double at = residual(vc), off = residual(1.1 * vc);
    const double S = kPi * 1.1 * vc / (omega1 * kL);
    const double expected_off = S * std::abs(std::cos(omega1 * kL / (2.0 * 1.1 * vc))) / std::abs(1.0 - S * S);
    const double S0 = kPi * 0.5 * vc / (omega1 * kL);
    const double ref = residual(0.5 * vc), expected_ref = S0 * std::abs(std::cos(omega1 * kL / vc)) / std::abs(1.0 - S0 * S0);
    std::cout << "i = " << i << ": cancellation speed " << vc << " m/s: residual " << at << " m; at 1.1 v: " << off
              << " m\n";
    EXPECT_LT(at, 1e-6 * off);
    // The amplitude law itself: the ratio of two speeds' residuals.
    EXPECT_NEAR((off / ref) / (expected_off / expected_ref), 1.0, 1e-6);
  }
}

TEST(AxleTrain, AccelerationProbeMatchesClosedForm) {
  // Undamped, one force P at speed v from rest: Y_i = -P / (m (w^2 - W^2)) (sin W t - W / w sin w t),
  // m = rhoA L / 2, w = omega_i, W = i pi v / L, so Y_i'' = -P / (m (w^2 - W^2)) (W w sin w t - W^2 sin W t).
  const double P = 1e5, v = 40.0, m = kRhoA * kL / 2.0;
  const int n = 6;
  BeamProblem p = bridge(n, 2.5e-5, kL / v, 0.0);
  p.accelerations = true;
  add_force(p, P, v, 0.0);
  BeamSimulation sim(p);
  double worst = 0, peak = 0;
  sim.run([&](const BeamSnapshot& s) {
    double a = 0;
    for (int i = 1; i <= n; ++i) {
      const double w = std::pow(i * kPi / kL, 2) * std::sqrt(kEI / kRhoA), W = i * kPi * v / kL;
      a += std::sin(i * kPi / 2.0) * -P / (m * (w * w - W * W)) * (W * w * std::sin(w * s.t) - W * W * std::sin(W * s.t));
    }
    worst = std::max(worst, std::abs(s.acceleration(0.5 * kL) - a));
    peak = std::max(peak, std::abs(a));
  });
  std::cout << "w_tt(L/2): largest error " << worst / peak << " of the peak " << peak << " m/s^2\n";
  EXPECT_LT(worst, 1e-7 * peak);
}

TEST(AxleTrain, ResonanceCancelledWhenItsSpeedIsACancellationSpeed) {
  // With d = 2 L / 3 the first resonance v = f1 d is also the cancellation speed 2 f1 L / 3: each
  // load leaves no first-mode vibration behind, so nothing builds up. Measured by the free
  // vibration of mode 1 after the last load has left (its amplitude sqrt(Y^2 + (Y'/omega)^2)),
  // undamped: against the same train at 0.9 and 1.1 times that speed.
  const int n = 15;
  const double d = 2.0 * kL / 3.0, vr = f1() * d, omega1 = 2.0 * kPi * f1();
  auto residual = [&](double v) {
    const double t_off = (kL + (n - 1) * d) / v;
    BeamProblem p = bridge(4, 1e-4, t_off + 0.5, 0.0);
    for (int a = 0; a < n; ++a) add_force(p, 1e5, v, a * d / v);
    BeamSimulation sim(p);
    double amp = 0;
    sim.run([&](const BeamSnapshot& s) {
      if (s.t > t_off) amp = std::max(amp, std::hypot(s.Y(0), s.Ydot(0) / omega1));
    });
    return amp;
  };
  const double at = residual(vr), below = residual(0.9 * vr), above = residual(1.1 * vr);
  std::cout << "d = 2 L / 3: residual mode-1 amplitude at v = f1 d = " << vr << " m/s: " << at << " m; at 0.9 v: "
            << below << " m, at 1.1 v: " << above << " m\n";
  EXPECT_LT(at, 1e-6 * std::min(below, above));
}

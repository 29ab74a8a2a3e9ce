// Static limits: initial equilibrium, self weight, quasi-static series convergence in n.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <vector>

#include "traverse/beam/beam_simulation.hpp"

using namespace traverse;
using namespace traverse::beam;

namespace {
double fit_slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// Static Galerkin deflection at xe for a point force P (downwards) at a: Kb Y = -P Phi(a).
double static_w(const BeamSimulation& sim, double a, double xe, double P) {
  const Eigen::Index n = sim.modes().size();
  VecX p(n), d1(n), d2(n), q(n);
  sim.modes().evaluate(a, p, d1, d2);
  const VecX Y = sim.matrices().Kb.ldlt().solve(-P * p);
  sim.modes().evaluate(xe, q, d1, d2);
  return q.dot(Y);
}

BeamProblem unit_problem(Support s, int n) {
  BeamProblem p;
  p.support = s;
  p.n_modes = n;
  p.length = 1.0;
  p.EI = 1.0;
  p.rhoA = 1.0;
  p.self_weight = false;
  p.t_end = 1e-3;
  p.dt = 1e-3;
  return p;
}
}  // namespace

TEST(BeamStatic, InitialStateIsStaticGalerkinSolution) {
  // Cantilever scene section, self weight on, a mass already at 0.7 L (entered earlier) and a
  // moving force at 0.3 L: Y(t0) must solve Kb Y = -Pb + sum F_k Phi(x_k), Y'(t0) = 0.
  const Section sec = circular_tube(2.0e11, 7850, 0.1, 0.05);
  BeamProblem p;
  p.support = Support::ClampedFree;
  p.length = 2.0;
  p.EI = sec.EI;
  p.rhoA = sec.rhoA;
  p.n_modes = 8;
  MovingLoad m;
  m.mass = 90.0;
  m.speed = 10.0;
  m.entry_time = -0.7 * 2.0 / 10.0;
  MovingLoad f;
  f.kind = LoadKind::Force;
  f.force = -500.0;
  f.speed = 10.0;
  f.entry_time = -0.3 * 2.0 / 10.0;
  p.loads = {m, f};
  p.t_end = 1e-3;
  p.dt = 1e-4;
  BeamSimulation sim(p);
  VecX Y0, V0;
  double x0 = 0, x1 = 0;
  sim.run([&](const BeamSnapshot& s) {
    if (Y0.size() == 0) {
      Y0 = s.Y;
      V0 = s.Ydot;
      x0 = s.load_position(0);
      x1 = s.load_position(1);
    }
  });
  const Eigen::Index n = 8;
  VecX p0(n), p1(n), d1(n), d2(n);
  sim.modes().evaluate(0.7 * 2.0, p0, d1, d2);
  sim.modes().evaluate(0.3 * 2.0, p1, d1, d2);
  const VecX rhs = -sim.matrices().Pb - 90.0 * 9.8 * p0 - 500.0 * p1;
  const VecX Ys = sim.matrices().Kb.ldlt().solve(rhs);
  const double err = (Y0 - Ys).norm() / Ys.norm();
  std::cout << "load positions at t0: " << x0 << ", " << x1 << " m; |Y0 - Kb^-1 rhs|/|.| = " << err
            << ", |Y'0| = " << V0.norm() << "\n";
  EXPECT_NEAR(x0, 1.4, 1e-12);
  EXPECT_NEAR(x1, 0.6, 1e-12);
  EXPECT_LT(err, 1e-12);
  EXPECT_EQ(V0.norm(), 0.0);
}

TEST(BeamStatic, CantileverSelfWeightTipConverges) {
  // Exact: w(L) = -rhoA g L^4 / (8 EI). Mode i contributes Phi_i(L) Pb_i / Kb_ii with
  // Pb_i = g rhoA int Phi_i = -g rhoA Phi_i'''(0) / beta_i^4 ~ beta_i^-1 (alternating sign
  // for tip-normalised modes) and Kb_ii ~ beta_i^4: terms ~ (-1)^i i^-5, so the alternating
  // tail falls like n^-5 (a same-sign tail would give n^-4).
  const Section sec = circular_tube(2.0e11, 7850, 0.1, 0.05);
  const double L = 2.0, g = 9.8, exact = -sec.rhoA * g * std::pow(L, 4) / (8 * sec.EI);
  std::vector<double> lx, ly;
  double prev = 1e9, e30 = 0;
  for (int n : {1, 2, 3, 5, 8, 12, 16, 20, 25, 30}) {
    BeamProblem p;
    p.support = Support::ClampedFree;
    p.length = L;
    p.EI = sec.EI;
    p.rhoA = sec.rhoA;
    p.n_modes = n;
    p.t_end = 1e-4;
    p.dt = 1e-4;
    BeamSimulation sim(p);
    const double e = std::abs(sim.deflection(L) / exact - 1);
    std::cout << "n = " << std::setw(2) << n << ": tip = " << std::setprecision(12) << sim.deflection(L)
              << " m, exact " << exact << ", rel error " << std::setprecision(4) << e << "\n";
    EXPECT_LT(e, prev);
    prev = e;
    if (n >= 5) {
      lx.push_back(std::log(n));
      ly.push_back(std::log(e));
    }
    e30 = e;
  }
  const double rate = -fit_slope(lx, ly);
  std::cout << "fitted convergence rate (n >= 5): n^-" << rate << "\n";
  EXPECT_LT(e30, 1e-5);
  EXPECT_NEAR(rate, 5.0, 0.3);
}

TEST(BeamStatic, QuasiStaticSeriesConvergenceRates) {
  // Static Galerkin deflection for a point force P = 1 against the beam formulas, n = 1..60.
  // Under the load the modal tail is sum_{i>n} Phi_i(a)^2 / Kb_ii ~ sum i^-4 ~ n^-3 (all
  // terms positive); away from the load (SS: midspan, load at 0.3 L) the coefficients
  // sin(0.3 i pi) sin(0.5 i pi) are periodic with zero mean, so the tail falls like n^-4 but
  // oscillates (it nearly vanishes for some n): the rate is fitted to the envelope
  // E(n) = max_{m >= n} e(m) over n = 12..50; the oscillating case is still
  // pre-asymptotic there (measured 3.77), hence its wider tolerance 0.4. (The brief expected n^-4 under the load; the
  // theoretical and measured rate there is 3.)
  struct Case {
    const char* name;
    Support s;
    double a, xe, exact, rate, tol;
  };
  const double a = 0.3, b = 0.7;
  const Case cases[] = {
      {"SS under the load a = 0.3L", Support::SimplySupported, a, a, a * a * b * b / 3.0, 3.0, 0.3},
      {"SS midspan, load at 0.3L", Support::SimplySupported, a, 0.5, a * 0.5 * (1 - a * a - 0.25) / 6.0, 4.0, 0.4},
      {"cantilever under the load a = 0.6L", Support::ClampedFree, 0.6, 0.6, std::pow(0.6, 3) / 3.0, 3.0, 0.3},
      {"cantilever tip load", Support::ClampedFree, 1.0, 1.0, 1.0 / 3.0, 3.0, 0.3}};
  for (const Case& c : cases) {
    std::vector<double> lx, ly;
    std::cout << c.name << ": exact " << c.exact << "\n";
    const int nmax = 60;
    std::vector<double> e(nmax + 1, 0.0);
    for (int n = 1; n <= nmax; ++n) {
      BeamSimulation sim(unit_problem(c.s, n));
      const double w = -static_w(sim, c.a, c.xe, 1.0);
      e[n] = std::abs(w / c.exact - 1);
      if (n % 10 == 0 || n <= 3) std::cout << "  n = " << n << ": rel error " << e[n] << "\n";
    }
    for (int n = nmax - 1; n >= 1; --n) e[n] = std::max(e[n], e[n + 1]);  // envelope
    for (int n = 12; n <= 50; ++n) {
      lx.push_back(std::log(n));
      ly.push_back(std::log(e[n]));
    }
    const double rate = -fit_slope(lx, ly);
    std::cout << "  fitted rate of the error envelope (n = 12..50): n^-" << rate << "\n";
    EXPECT_NEAR(rate, c.rate, c.tol) << c.name;
  }
}

TEST(BeamStatic, SlowMovingForceFollowsStaticSolution) {
  // Simply supported, 5 modes, alpha = v/(2 f1 L) = 0.002: the deflection under the load
  // follows the static 5-mode Galerkin value within O(alpha) (the free vibration started at
  // entry has relative amplitude ~ alpha).
  const int n = 5;
  const double alpha = 0.002, v = alpha * constants::pi;
  BeamProblem p = unit_problem(Support::SimplySupported, n);
  p.initial_state = InitialState::Rest;
  p.t_end = 1.0 / v;
  p.dt = 2e-3;
  p.output_every = 50;
  MovingLoad f;
  f.kind = LoadKind::Force;
  f.force = -1.0;
  f.speed = v;
  p.loads.push_back(f);
  BeamSimulation sim(p);
  double worst = 0;
  sim.run([&](const BeamSnapshot& s) {
    const double x = s.load_position(0);
    if (x < 0.1 || x > 0.9) return;
    const double ws = static_w(sim, x, x, 1.0);
    worst = std::max(worst, std::abs(s.load_deflection(0) / ws - 1));
  });
  std::cout << "alpha = 0.002: max relative deviation from the static deflection under the load "
               "(0.1 L .. 0.9 L) = "
            << worst << "\n";
  EXPECT_LT(worst, 5 * alpha);
}

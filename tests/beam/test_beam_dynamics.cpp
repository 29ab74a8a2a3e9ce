// Moving force against closed forms, dynamic amplification, time-step orders, moving mass
// versus moving force.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <vector>

#include "traverse/beam/beam_simulation.hpp"

using namespace traverse;
using namespace traverse::beam;

namespace {
constexpr double kPi = constants::pi;

// Simply supported beam L = EI = rhoA = 1: omega_i = (i pi)^2, f1 = pi/2 Hz, beam mass 1 kg.
BeamProblem ss_problem(int n, double v, double t_end, double dt) {
  BeamProblem p;
  p.length = 1.0;
  p.EI = 1.0;
  p.rhoA = 1.0;
  p.support = Support::SimplySupported;
  p.n_modes = n;
  p.self_weight = false;
  p.initial_state = InitialState::Rest;
  p.t_end = t_end;
  p.dt = dt;
  MovingLoad f;
  f.kind = LoadKind::Force;
  f.force = -1.0;  // P = 1 N downwards
  f.speed = v;
  p.loads.push_back(f);
  return p;
}

// Closed-form (Fryba) undamped modal response of the SS beam (L = EI = rhoA = 1) to a force
// P = 1 moving at speed v from rest: Y_i = -P/(m (w^2 - W^2)) (sin W t - W/w sin w t),
// m = rhoA L / 2, w = (i pi)^2, W = i pi v. Valid while the force is on the beam.
// alpha = v / (2 f1 L) = W_1 / w_1, so alpha = 1 is resonance of mode 1.
double fryba_mode(int i, double v, double t) {
  const double w = std::pow(i * kPi, 2), W = i * kPi * v, m = 0.5;
  if (std::abs(w - W) < 1e-7 * w)  // resonance (alpha = 1 for mode 1): limit W -> w
    return -1.0 / (2 * m * w * w) * (std::sin(w * t) - w * t * std::cos(w * t));
  return -1.0 / (m * (w * w - W * W)) * (std::sin(W * t) - W / w * std::sin(w * t));
}
double fryba_w(int nmodes, double v, double t, double x) {
  double s = 0;
  for (int i = 1; i <= nmodes; ++i) s += std::sin(i * kPi * x) * fryba_mode(i, v, t);
  return s;
}

double speed_for_alpha(double alpha) { return alpha * 2.0 * (kPi / 2.0) * 1.0; }  // v = 2 f1 L alpha

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
}  // namespace

TEST(BeamDynamics, MovingForceMatchesFrybaClosedForm) {
  const int n = 5;
  const double v = speed_for_alpha(0.25), T = 1.0 / v;
  BeamSimulation sim(ss_problem(n, v, T, 1e-4));
  double err_mid = 0, max_mid = 0, err_Y = 0, max_Y = 0, err_load = 0;
  sim.run([&](const BeamSnapshot& s) {
    const double mid = fryba_w(n, v, s.t, 0.5);
    err_mid = std::max(err_mid, std::abs(s.deflection(0.5) - mid));
    max_mid = std::max(max_mid, std::abs(mid));
    for (int i = 1; i <= n; ++i) {
      err_Y = std::max(err_Y, std::abs(s.Y(i - 1) - fryba_mode(i, v, s.t)));
      max_Y = std::max(max_Y, std::abs(fryba_mode(i, v, s.t)));
    }
    const double x = s.load_position(0);
    err_load = std::max(err_load, std::abs(s.load_deflection(0) - fryba_w(n, v, s.t, x)));
  });
  std::cout << "SS moving force, n = 5, alpha = 0.25, RK4 dt = 1e-4: max rel error midspan = "
            << err_mid / max_mid << ", modal coords = " << err_Y / max_Y
            << ", under the load = " << err_load / max_mid << "\n";
  EXPECT_LT(err_mid / max_mid, 1e-8);
  EXPECT_LT(err_Y / max_Y, 1e-8);
  EXPECT_LT(err_load / max_mid, 1e-8);
}

TEST(BeamDynamics, DynamicAmplificationFactorAgainstModalSeries) {
  // DAF = max_t(-w(L/2, t)) / (P L^3 / 48 EI) while the force is on the beam.
  // Reference: closed-form series with 399 modes maximised on a 40001-point time grid, then
  // refined by golden section. Simulation: 20 modes, RK4, dt = 1e-4 (truncation of the
  // midspan series beyond mode 20 is ~2e-5 relative, so the tolerance is 2e-4).
  const double wst = 1.0 / 48.0;
  for (double alpha : {0.1, 0.25, 0.5, 1.0}) {
    const double v = speed_for_alpha(alpha), T = 1.0 / v;
    auto ref = [&](double t) { return -fryba_w(399, v, t, 0.5); };
    const int G = 40000;
    int best = 0;
    double bv = -1;
    for (int j = 0; j <= G; ++j) {
      const double f = ref(T * j / G);
      if (f > bv) {
        bv = f;
        best = j;
      }
    }
    double a = T * std::max(best - 1, 0) / G, b = T * std::min(best + 1, G) / G;
    for (int it = 0; it < 60; ++it) {
      const double m1 = a + 0.382 * (b - a), m2 = a + 0.618 * (b - a);
      if (ref(m1) > ref(m2)) b = m2; else a = m1;
    }
    const double daf_ref = std::max(bv, ref(0.5 * (a + b))) / wst;
    BeamSimulation sim(ss_problem(20, v, T, 1e-4));
    double wmax = 0;
    sim.run([&](const BeamSnapshot& s) { wmax = std::max(wmax, -s.deflection(0.5)); });
    const double daf = wmax / wst;
    std::cout << std::setprecision(8) << "alpha = " << alpha << ": DAF series = " << daf_ref
              << ", simulation (20 modes) = " << daf << ", rel diff = "
              << std::abs(daf / daf_ref - 1) << "\n";
    EXPECT_NEAR(daf / daf_ref, 1.0, 2e-4);
  }
}

namespace {
// Cantilever launch barrel (spec), p = 20 %, v = 100 m/s, n = 3, to 1.25 L/v (the mass
// leaves the free end at L/v: the step is split there).
BeamProblem barrel(Integrator integ, double dt, int n = 3) {
  const Section s = circular_tube(2.0e11, 7850, 0.1, 0.05);
  BeamProblem p;
  p.length = 2.0;
  p.EI = s.EI;
  p.rhoA = s.rhoA;
  p.support = Support::ClampedFree;
  p.n_modes = n;
  p.gravity = 9.8;
  const double mb = s.rhoA * p.length, pm = 0.2;
  MovingLoad m;
  m.kind = LoadKind::Mass;
  m.mass = pm / (1 - pm) * mb;
  m.speed = 100.0;
  p.loads.push_back(m);
  p.t_end = 1.25 * p.length / m.speed;
  p.dt = dt;
  p.integrator = integ;
  return p;
}

// Tip deflection at multiples of `every_t`.
std::vector<double> tip_history(const BeamProblem& p, double every_t) {
  BeamProblem q = p;
  q.output_every = static_cast<int>(std::lround(every_t / p.dt));
  std::vector<double> out;
  BeamSimulation sim(q);
  sim.run([&](const BeamSnapshot& s) { out.push_back(s.deflection(q.length)); });
  return out;
}

double max_diff(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double e = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) e = std::max(e, std::abs(a[i] - b[i]));
  return e;
}
}  // namespace

TEST(BeamDynamics, TimeStepOrdersOnMovingMass) {
  const double every = 1e-4;
  const auto ref = tip_history(barrel(Integrator::RK4, 1e-4 / 512), every);
  double scale = 0;
  for (double w : ref) scale = std::max(scale, std::abs(w));
  struct Case {
    Integrator integ;
    const char* name;
    std::vector<double> dts;
    double order;
  };
  const Case cases[] = {{Integrator::RK4, "RK4", {1e-4 / 4, 1e-4 / 8, 1e-4 / 16, 1e-4 / 32}, 4.0},
                        {Integrator::Newmark, "Newmark", {1e-4 / 4, 1e-4 / 8, 1e-4 / 16, 1e-4 / 32}, 2.0}};
  for (const Case& c : cases) {
    std::vector<double> lx, ly;
    for (double dt : c.dts) {
      const double e = max_diff(tip_history(barrel(c.integ, dt), every), ref);
      std::cout << c.name << " dt = " << dt << ": max tip error = " << e << " m (rel " << e / scale << ")\n";
      lx.push_back(std::log(dt));
      ly.push_back(std::log(e));
    }
    for (std::size_t i = 1; i < lx.size(); ++i)
      std::cout << "  pairwise order " << (ly[i - 1] - ly[i]) / (lx[i - 1] - lx[i]) << "\n";
    const double order = fit_slope(lx, ly);
    std::cout << c.name << " fitted order = " << order << "\n";
    EXPECT_NEAR(order, c.order, 0.1) << c.name;
  }
}

namespace {
// Max |deflection under the load| over the traversal for a mass or a force on the SS beam.
double max_under_load(int n, double alpha, double M, LoadKind kind, std::vector<double>* hist = nullptr) {
  const double v = speed_for_alpha(alpha), T = 1.0 / v;
  BeamProblem p = ss_problem(n, v, T, 1e-4);
  p.loads[0].kind = kind;
  p.loads[0].mass = M;
  p.loads[0].force.reset();  // weight -M g
  double m = 0;
  BeamSimulation sim(p);
  sim.run([&](const BeamSnapshot& s) {
    const double w = s.load_deflection(0);
    m = std::max(m, -w);
    if (hist) hist->push_back(w / (M * 9.8));
  });
  return m;
}
}  // namespace

TEST(BeamDynamics, MovingMassTendsToMovingForce) {
  // Deflection under the load divided by M g: the mass-minus-force difference is of first
  // order in the mass ratio mu = M / (rhoA L), so it must fall ~10x per decade of mu.
  std::vector<double> f;
  max_under_load(8, 0.25, 1.0, LoadKind::Force, &f);
  double fscale = 0;
  for (double x : f) fscale = std::max(fscale, std::abs(x));
  std::vector<double> lx, ly;
  for (double mu : {1e-1, 1e-2, 1e-3, 1e-4}) {
    std::vector<double> h;
    max_under_load(8, 0.25, mu, LoadKind::Mass, &h);
    double d = 0;
    for (std::size_t i = 0; i < h.size(); ++i) d = std::max(d, std::abs(h[i] - f[i]));
    std::cout << "mu = " << mu << ": max |w/(Mg) mass - force| / max|w/(Mg) force| = " << d / fscale << "\n";
    lx.push_back(std::log(mu));
    ly.push_back(std::log(d / fscale));
  }
  const double slope = fit_slope(lx, ly);
  std::cout << "fitted exponent in mu = " << slope << "\n";
  EXPECT_NEAR(slope, 1.0, 0.05);
  EXPECT_LT(std::exp(ly.back()), 1e-3);
}

TEST(BeamDynamics, MassInertiaIncreasesDeflection) {
  // Simply supported, 8 modes, mu = M / (rhoA L). d = max(-w) with the mass / max(-w) with
  // the force of the same weight - 1.
  //
  // (a) Under the load at alpha = 0.25. Two effects raise the deflection: the rider's mass
  // lowers the loaded beam's frequency (one mode, mass at midspan: omega^2 -> omega^2/(1+2mu),
  // i.e. alpha_eff = alpha sqrt(1+2mu), and the force DAF rises with alpha here), and the
  // centrifugal term: following the sagging beam (w_xx > 0) the mass presses with
  // M (g + v^2 w_xx); with the static w_xx = M g L / (4 EI) at midspan this adds
  // mu v^2 L^3 rhoA/(4 EI) at most. Upper estimate U = DAF_F(alpha_eff)/DAF_F(alpha) - 1 +
  // mu v^2 / 4 (the mass is not at midspan all the time, so d < U); lower: d > 0.
  // d must grow with mu (it is O(mu), see MovingMassTendsToMovingForce).
  const double alpha = 0.25, v = speed_for_alpha(alpha);
  const double daf_f = max_under_load(8, alpha, 1.0, LoadKind::Force);
  double prev = 0;
  for (double mu : {0.05, 0.1, 0.2, 0.4}) {
    const double d = max_under_load(8, alpha, mu, LoadKind::Mass) / (mu * daf_f) - 1;
    const double U = max_under_load(8, alpha * std::sqrt(1 + 2 * mu), 1.0, LoadKind::Force) / daf_f - 1 +
                     mu * v * v / 4;
    std::cout << "under the load, alpha = 0.25, mu = " << mu << ": d = " << d << " (d/mu = " << d / mu
              << "), upper estimate U = " << U << "\n";
    EXPECT_GT(d, prev);
    EXPECT_LT(d, U);
    prev = d;
  }
  // Under the load, as a function of speed (mu = 0.2): measured positive but DECREASING over
  // alpha in [0.2, 0.44] (the maximum under the load moves towards the exit, where the mass's
  // lag matters less), and sign-changing below alpha ~ 0.2 (phase of the free vibration).
  prev = 1e9;
  for (double a : {0.2, 0.25, 0.3, 0.35, 0.4}) {
    const double mu = 0.2;
    const double d = max_under_load(8, a, mu, LoadKind::Mass) / max_under_load(8, a, mu, LoadKind::Force) - 1;
    std::cout << "under the load, mu = 0.2, alpha = " << a << ": d = " << d << "\n";
    EXPECT_GT(d, 0.0);
    EXPECT_LT(d, prev);
    prev = d;
  }
  // (b) Maximum midspan deflection (the classical DAF with a moving mass): the mass's inertia
  // increases it, more with larger mu and, for mu = 0.2, more with higher speed over
  // alpha in [0.4, 0.8] (the mass lowers the loaded frequency, so the effective speed
  // parameter, and with it the free-vibration amplitude left behind, grows). Band: O(mu)
  // effect, 0 < d < mu (measured 0.2 mu .. 0.75 mu).
  auto mid = [](double a, double mu, LoadKind kind) {
    const double v2 = speed_for_alpha(a);
    BeamProblem p = ss_problem(8, v2, 1.0 / v2, 1e-4);
    p.loads[0].kind = kind;
    p.loads[0].mass = mu;
    p.loads[0].force.reset();
    double m = 0;
    BeamSimulation sim(p);
    sim.run([&](const BeamSnapshot& s) { m = std::max(m, -s.deflection(0.5)); });
    return m;
  };
  prev = 0;
  for (double mu : {0.05, 0.1, 0.2, 0.4}) {
    const double d = mid(0.6, mu, LoadKind::Mass) / mid(0.6, mu, LoadKind::Force) - 1;
    std::cout << "midspan max, alpha = 0.6, mu = " << mu << ": d = " << d << "\n";
    EXPECT_GT(d, prev);
    EXPECT_LT(d, mu);
    prev = d;
  }
  prev = 0;
  for (double a : {0.4, 0.5, 0.6, 0.7, 0.8}) {
    const double mu = 0.2;
    const double d = mid(a, mu, LoadKind::Mass) / mid(a, mu, LoadKind::Force) - 1;
    std::cout << "midspan max, mu = 0.2, alpha = " << a << ": d = " << d << "\n";
    EXPECT_GT(d, prev);
    EXPECT_LT(d, mu);
    prev = d;
  }
}

TEST(BeamDynamics, DirectionsAccelerationAndSeveralLoads) {
  // (1) Mirror symmetry: an accelerating mass entering the SS beam at x = L moving in -x must
  // give the mirror image of the same mass entering at x = 0 (modes sin(i pi x/L) are even/odd
  // about midspan), exactly up to round-off.
  auto one = [](BeamEnd end) {
    BeamProblem p = ss_problem(6, 0.5, 1.2, 1e-4);
    p.loads[0].kind = LoadKind::Mass;
    p.loads[0].mass = 0.3;
    p.loads[0].force.reset();
    p.loads[0].entry = end;
    p.loads[0].direction = end == BeamEnd::Left ? 1 : -1;
    p.loads[0].acceleration = 0.8;
    p.loads[0].entry_time = 0.1;
    std::vector<double> h;
    BeamSimulation sim(p);
    sim.run([&](const BeamSnapshot& s) {
      h.push_back(s.load_on_beam(0) ? s.load_deflection(0) : 0.0);
      h.push_back(s.deflection(0.3));
      h.push_back(s.deflection(0.7));
    });
    return h;
  };
  const std::vector<double> a = one(BeamEnd::Left), b = one(BeamEnd::Right);
  double d = 0, sc = 0;
  for (std::size_t i = 0; i + 2 < a.size(); i += 3) {
    d = std::max({d, std::abs(a[i] - b[i]), std::abs(a[i + 1] - b[i + 2]), std::abs(a[i + 2] - b[i + 1])});
    sc = std::max(sc, std::abs(a[i]));
  }
  std::cout << "mirror (entry x=0 vs x=L, a = 0.8 m/s^2): max rel difference = " << d / sc << "\n";
  EXPECT_LT(d / sc, 1e-12);

  // (2) Two masses (one from each end, staggered, one decelerating) and a force, entering and
  // leaving mid-step: Newmark at dt, dt/2, dt/4 against RK4 (dt = 2.5e-5); the pairwise order
  // must be 2 +- 0.1 (second order survives the load switching and the two-mass Woodbury update).
  auto multi = [](Integrator integ, double dt) {
    BeamProblem p = ss_problem(6, 0.7, 2.5, dt);
    p.self_weight = true;
    p.gravity = 9.8;
    p.initial_state = InitialState::Static;
    p.integrator = integ;
    MovingLoad m1;
    m1.mass = 0.25;
    m1.speed = 0.7;
    m1.entry_time = 0.0123;
    MovingLoad m2;
    m2.mass = 0.4;
    m2.entry = BeamEnd::Right;
    m2.direction = -1;
    m2.speed = 1.1;
    m2.acceleration = -0.3;
    m2.entry_time = 0.3377;
    p.loads[0].force = -2.0;
    p.loads[0].entry_time = 0.5555;
    p.loads.push_back(m1);
    p.loads.push_back(m2);
    p.output_every = static_cast<int>(std::lround(1e-2 / dt));
    std::vector<double> h;
    BeamSimulation sim(p);
    sim.run([&](const BeamSnapshot& s) { h.push_back(s.deflection(0.41)); });
    return h;
  };
  const auto ref = multi(Integrator::RK4, 2.5e-5);
  double sc2 = 0;
  for (double x : ref) sc2 = std::max(sc2, std::abs(x));
  std::vector<double> errs;
  for (double dt : {2.5e-4, 1.25e-4, 6.25e-5}) {
    errs.push_back(max_diff(multi(Integrator::Newmark, dt), ref));
    std::cout << "3 loads, Newmark dt = " << dt << ": rel error " << errs.back() / sc2 << "\n";
  }
  for (std::size_t i = 1; i < errs.size(); ++i) {
    const double order = std::log2(errs[i - 1] / errs[i]);
    std::cout << "  pairwise order " << order << "\n";
    EXPECT_NEAR(order, 2.0, 0.1);
  }
  EXPECT_LT(errs.back() / sc2, 1e-5);
}

// The moving-mass equations term by term: one mode of the simply supported beam (L = EI =
// rhoA = 1, phi = sin(pi x), m = 1/2, k = pi^4 / 2), a mass M = 0.5 at v = 2 (past the
// critical speed pi / 2 ... the inertia terms are large) and a = 3, from rest, without
// gravity on the beam. Written out here from the physics,
//   (m + M phi^2) Y'' + 2 M v phi phi' Y' + (k + M v^2 phi phi'' + M a phi phi') Y = -M g phi,
// and integrated with this test's own RK4 at dt = 1e-5: the simulation's midspan deflection
// (RK4 at 1e-4) agrees at the common times to the methods' error (< 1e-9 of its largest value). A wrong sign or a
// dropped Coriolis (2 M v phi phi' Y'), centrifugal (M v^2 phi phi'') or acceleration term
// changes it at the percent level.
TEST(BeamDynamics, MovingMassOneModeMatchesTheEquationWrittenOut) {
  const double M = 0.5, v0 = 2.0, a = 3.0, g = 9.8;
  const double T = (std::sqrt(v0 * v0 + 2.0 * a) - v0) / a;  // when the mass reaches x = 1
  BeamProblem p = ss_problem(1, v0, T, 1e-4);
  p.loads[0].kind = LoadKind::Mass;
  p.loads[0].mass = M;
  p.loads[0].force.reset();
  p.loads[0].acceleration = a;
  p.gravity = g;
  std::vector<double> t_sim, w_sim;
  BeamSimulation sim(p);
  sim.run([&](const BeamSnapshot& s) {
    t_sim.push_back(s.t);
    w_sim.push_back(s.deflection(0.5));
  });
  // The same with this test's ODE: state (Y, Y'), the mass at x = v0 t + a t^2 / 2.
  auto rhs = [&](double t, double Y, double V, double& dY, double& dV) {
    const double x = v0 * t + 0.5 * a * t * t, v = v0 + a * t;
    const double ph = std::sin(kPi * x), d1 = kPi * std::cos(kPi * x), d2 = -kPi * kPi * ph;
    const double m = 0.5 + M * ph * ph, c = 2.0 * M * v * ph * d1;
    const double k = std::pow(kPi, 4) / 2.0 + M * v * v * ph * d2 + M * a * ph * d1;
    dY = V;
    dV = (-M * g * ph - c * V - k * Y) / m;
  };
  const double h = 1e-5;  // a tenth of the simulation's step: the outputs fall on this grid
  const int n = static_cast<int>(T / h);
  double Y = 0.0, V = 0.0, worst = 0.0, largest = 0.0;
  std::size_t next = 1;
  for (int i = 0; i < n; ++i) {
    const double t = i * h;
    double k1y, k1v, k2y, k2v, k3y, k3v, k4y, k4v;
    rhs(t, Y, V, k1y, k1v);
    rhs(t + h / 2, Y + h / 2 * k1y, V + h / 2 * k1v, k2y, k2v);
    rhs(t + h / 2, Y + h / 2 * k2y, V + h / 2 * k2v, k3y, k3v);
    rhs(t + h, Y + h * k3y, V + h * k3v, k4y, k4v);
    Y += h / 6 * (k1y + 2 * k2y + 2 * k3y + k4y);
    V += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    while (next < t_sim.size() && t_sim[next] < (i + 1.5) * h) {
      if (std::abs(t_sim[next] - (i + 1) * h) > 1e-3 * h) {  // the shortened last step
        ++next;
        continue;
      }
      worst = std::max(worst, std::abs(w_sim[next] - Y));  // phi(1/2) = 1
      largest = std::max(largest, std::abs(Y));
      ++next;
    }
  }
  std::cout << "one mode, moving mass: max |w_sim - w_ode| at midspan = " << worst << " m of max |w| = " << largest
            << " m (" << next << " of " << t_sim.size() << " outputs compared)\n";
  EXPECT_GE(next, t_sim.size() - 1);
  EXPECT_LT(worst, 1e-9 * largest);
}

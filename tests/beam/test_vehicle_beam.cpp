// Structural damping (free decay against the damping ratio), the sprung mass and the two-axle
// vehicle (against an independent modal integration written here, the limits of a stiff and a
// soft suspension, the energy balance), the orders of both integrators with the new terms.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <vector>

#include "traverse/beam/beam_simulation.hpp"
#include "traverse/beam/vehicle_beam.hpp"

using namespace traverse;
using namespace traverse::beam;

namespace {
constexpr double kPi = constants::pi;

// Cantilever L = EI = rhoA = 1 released from rest under its own weight: every mode vibrates
// about its static value.
BeamProblem decay_problem(int n, const ModalDamping& d, Integrator integ, double t_end, double dt) {
  BeamProblem p;
  p.support = Support::ClampedFree;
  p.n_modes = n;
  p.self_weight = true;
  p.initial_state = InitialState::Rest;
  p.damping = d;
  p.integrator = integ;
  p.t_end = t_end;
  p.dt = dt;
  return p;
}

// Damping ratio from the logarithmic decrement of the peaks of x(t) (samples at spacing dt,
// each peak refined by a parabola through its three samples) over the first `cycles` cycles.
double ratio_from_decrement(const std::vector<double>& x, int cycles) {
  std::vector<double> peaks;
  for (std::size_t k = 1; k + 1 < x.size() && static_cast<int>(peaks.size()) <= cycles; ++k)
    if (x[k] > x[k - 1] && x[k] >= x[k + 1] && x[k] > 0) {
      const double a = 0.5 * (x[k - 1] + x[k + 1]) - x[k], b = 0.5 * (x[k + 1] - x[k - 1]);
      peaks.push_back(x[k] - b * b / (4.0 * a));
    }
  if (static_cast<int>(peaks.size()) <= cycles) return NAN;
  const double delta = std::log(peaks[0] / peaks[static_cast<std::size_t>(cycles)]) / cycles;
  return delta / std::sqrt(4.0 * kPi * kPi + delta * delta);
}

// Free decay of every mode: the measured ratio against the one the damping gives the mode.
void check_decay(const ModalDamping& d, Integrator integ, const std::vector<double>& zeta) {
  const int n = static_cast<int>(zeta.size());
  // The shortest period sets dt; the longest, with the slowest decay, the duration.
  BeamSimulation probe(decay_problem(n, d, integ, 1.0, 1.0));
  const VecX omega = probe.modes().circular_frequencies();
  const double dt = 2.0 * kPi / omega(n - 1) / 400.0, T = 8.0 * 2.0 * kPi / omega(0);
  const int cycles = 5;
  BeamSimulation sim(decay_problem(n, d, integ, T, dt));
  const VecX Ys = sim.matrices().Kb.ldlt().solve(-sim.matrices().Pb);
  std::vector<std::vector<double>> x(static_cast<std::size_t>(n));
  sim.run([&](const BeamSnapshot& s) {
    for (int i = 0; i < n; ++i) x[static_cast<std::size_t>(i)].push_back(s.Y(i) - Ys(i));
  });
  for (int i = 0; i < n; ++i) {
    const double z = ratio_from_decrement(x[static_cast<std::size_t>(i)], cycles);
    std::cout << "  mode " << i + 1 << ": zeta " << zeta[static_cast<std::size_t>(i)] << ", from the decrement " << z
              << " (rel. error " << z / zeta[static_cast<std::size_t>(i)] - 1.0 << ")\n";
    EXPECT_NEAR(z / zeta[static_cast<std::size_t>(i)], 1.0, 1e-3) << "mode " << i + 1;
  }
}

// The published moving-oscillator case: 25 m simply supported span, E = 3.5e10 Pa, I = 1.3901 m^4,
// 18358 kg/m, a 5750 kg body on 1595 kN/m at 25 m/s.
constexpr double kL = 25.0, kEI = 3.5e10 * 1.3901, kRhoA = 18358.0, kMv = 5750.0, kKv = 1595e3, kV = 25.0, kG = 9.81;

BeamProblem bridge(int n, double dt, double t_end, Integrator integ = Integrator::RK4) {
  BeamProblem p;
  p.length = kL;
  p.EI = kEI;
  p.rhoA = kRhoA;
  p.support = Support::SimplySupported;
  p.n_modes = n;
  p.gravity = kG;
  p.self_weight = false;
  p.initial_state = InitialState::Static;
  p.integrator = integ;
  p.dt = dt;
  p.t_end = t_end;
  return p;
}

Vehicle sprung(double k, double c, double mw = 0.0, double mass = kMv) {
  Vehicle v;
  v.name = "car";
  v.mass = mass;
  v.axles.push_back({0.0, k, c, mw});
  v.motion.speed = kV;
  return v;
}

// Independent integration: sine modes Phi_i = sin(i pi x / L), modal mass rhoA L / 2,
// omega_i = (i pi / L)^2 sqrt(EI / rhoA), modal damping zeta; the body on k, c; RK4 at fixed
// steps on (q, q', z, z'). The oscillator enters at x = 0 at t = 0 with the beam at rest,
// the body at z = -M g / k. Returns the series of w(L/2) and of the body's acceleration.
struct Series {
  std::vector<double> mid, body_acc;
};
Series independent(int n, double k, double c, double zeta, double dt, double t_end, int every) {
  const double m = kRhoA * kL / 2.0;
  std::vector<double> om(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) om[static_cast<std::size_t>(i)] = std::pow((i + 1) * kPi / kL, 2) * std::sqrt(kEI / kRhoA);
  const std::size_t N = static_cast<std::size_t>(2 * n + 2);
  // y = (q_1..q_n, p_1..p_n, z, z')
  auto rhs = [&](double t, const std::vector<double>& y, std::vector<double>& d, double& zdd) {
    const double x = kV * t;
    const bool on = x >= 0.0 && x <= kL;
    double w = 0, wt = 0, wx = 0;
    for (int i = 0; i < n; ++i) {
      const double a = (i + 1) * kPi / kL;
      if (on) {
        w += std::sin(a * x) * y[static_cast<std::size_t>(i)];
        wt += std::sin(a * x) * y[static_cast<std::size_t>(n + i)];
        wx += a * std::cos(a * x) * y[static_cast<std::size_t>(i)];
      }
    }
    const double z = y[N - 2], zd = y[N - 1];
    const double F = k * (z - w) + c * (zd - wt - kV * wx);  // the suspension's force on the beam, up
    zdd = (-F - kMv * kG) / kMv;
    for (int i = 0; i < n; ++i) {
      const std::size_t iu = static_cast<std::size_t>(i);
      const double a = (i + 1) * kPi / kL, q = y[iu], p = y[iu + static_cast<std::size_t>(n)];
      d[iu] = p;
      d[iu + static_cast<std::size_t>(n)] =
          (on ? std::sin(a * x) * F / m : 0.0) - 2.0 * zeta * om[iu] * p - om[iu] * om[iu] * q;
    }
    d[N - 2] = zd;
    d[N - 1] = zdd;
  };
  std::vector<double> y(N, 0.0), k1(N), k2(N), k3(N), k4(N), ys(N);
  y[N - 2] = -kMv * kG / k;
  Series out;
  auto record = [&](double t) {
    std::vector<double> d(N);
    double zdd;
    rhs(t, y, d, zdd);
    double w = 0;
    for (int i = 0; i < n; ++i) w += std::sin((i + 1) * kPi / 2.0) * y[static_cast<std::size_t>(i)];
    out.mid.push_back(w);
    out.body_acc.push_back(zdd);
  };
  record(0.0);
  const long steps = std::lround(t_end / dt);
  double dz;
  for (long s = 0; s < steps; ++s) {
    const double t = s * dt;
    rhs(t, y, k1, dz);
    for (std::size_t j = 0; j < N; ++j) ys[j] = y[j] + 0.5 * dt * k1[j];
    rhs(t + 0.5 * dt, ys, k2, dz);
    for (std::size_t j = 0; j < N; ++j) ys[j] = y[j] + 0.5 * dt * k2[j];
    rhs(t + 0.5 * dt, ys, k3, dz);
    for (std::size_t j = 0; j < N; ++j) ys[j] = y[j] + dt * k3[j];
    rhs(t + dt, ys, k4, dz);
    for (std::size_t j = 0; j < N; ++j) y[j] += dt / 6.0 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    if ((s + 1) % every == 0) record((s + 1) * dt);
  }
  return out;
}

double absmax(const std::vector<double>& v) {
  double m = 0;
  for (const double x : v) m = std::max(m, std::abs(x));
  return m;
}

Series production(const BeamProblem& p, const std::vector<Vehicle>& v) {
  VehicleBeam sim(p, v);
  Series s;
  sim.run([&](const VehicleBeam& b) {
    s.mid.push_back(b.deflection(0.5 * kL));
    s.body_acc.push_back(b.body_acceleration(0));
  });
  return s;
}
}  // namespace

TEST(BeamDamping, FreeDecayMatchesModalRatiosRK4) {
  ModalDamping d;
  d.kind = ModalDamping::Kind::Ratios;
  d.ratios = {0.01, 0.02, 0.05};
  check_decay(d, Integrator::RK4, d.ratios);
}

TEST(BeamDamping, FreeDecayMatchesOneRatioNewmark) {
  ModalDamping d;
  d.kind = ModalDamping::Kind::Ratios;
  d.ratios = {0.03};
  check_decay(d, Integrator::Newmark, {0.03, 0.03, 0.03});
}

TEST(BeamDamping, FreeDecayMatchesRayleighRatios) {
  // zeta_i = a / (2 omega_i) + b omega_i / 2 with omega_i of the cantilever (L = EI = rhoA = 1).
  ModalDamping d;
  d.kind = ModalDamping::Kind::Rayleigh;
  d.mass = 0.2;
  d.stiffness = 2e-4;
  std::vector<double> zeta;
  for (const double l : {1.87510407, 4.69409113, 7.85475744}) {
    const double w = l * l;
    zeta.push_back(d.mass / (2.0 * w) + d.stiffness * w / 2.0);
  }
  check_decay(d, Integrator::RK4, zeta);
}

TEST(BeamDamping, BadRatioListIsRefused) {
  ModalDamping d;
  d.kind = ModalDamping::Kind::Ratios;
  d.ratios = {0.01, 0.02};
  EXPECT_THROW(BeamSimulation(decay_problem(3, d, Integrator::RK4, 1.0, 0.01)), std::invalid_argument);
}

TEST(SprungMass, MatchesIndependentModalIntegrationYangYau) {
  // Undamped (the published case) and with a suspension damper and 2 % modal damping.
  const int n = 10;
  const double T = kL / kV, dt = 1e-4;
  for (const auto& [c, zeta] : {std::pair<double, double>{0.0, 0.0}, {2.0e4, 0.02}}) {
    BeamProblem p = bridge(n, dt, T);
    if (zeta > 0) {
      p.damping.kind = ModalDamping::Kind::Ratios;
      p.damping.ratios = {zeta};
    }
    const Series a = production(p, {sprung(kKv, c)});
    const Series b = independent(n, kKv, c, zeta, dt / 4, T, 4);
    ASSERT_EQ(a.mid.size(), b.mid.size());
    const double wa = absmax(a.mid), wb = absmax(b.mid), aa = absmax(a.body_acc), ab = absmax(b.body_acc);
    std::cout << "c = " << c << ", zeta = " << zeta << ": peak midspan deflection " << wa << " m (independent " << wb
              << ", rel. diff " << wa / wb - 1 << "); peak body acceleration " << aa << " m/s^2 (independent " << ab
              << ", rel. diff " << aa / ab - 1 << ")\n";
    EXPECT_NEAR(wa / wb, 1.0, 1e-6);
    EXPECT_NEAR(aa / ab, 1.0, 1e-6);
    // The body's acceleration differs from zero by the bridge only: its scale is the bridge's.
    EXPECT_GT(aa, 1e-3);
  }
}

TEST(SprungMass, StiffSuspensionGivesTheMovingMass) {
  const int n = 8;
  const double T = kL / kV, dt = 2e-5;
  for (const double mw : {0.0, 1000.0}) {
    const Series a = production(bridge(n, dt, T), {sprung(1e10, 0.0, mw)});
    BeamProblem p = bridge(n, dt, T);
    MovingLoad m;
    m.kind = LoadKind::Mass;
    m.mass = kMv + mw;
    m.speed = kV;
    p.loads.push_back(m);
    BeamSimulation sim(p);
    std::vector<double> mid;
    sim.run([&](const BeamSnapshot& s) { mid.push_back(s.deflection(0.5 * kL)); });
    const double wa = absmax(a.mid), wb = absmax(mid);
    std::cout << "k = 1e10 N/m, wheel mass " << mw << " kg: peak midspan " << wa << " m, moving mass " << wb
              << " m (rel. diff " << wa / wb - 1 << ")\n";
    EXPECT_NEAR(wa / wb, 1.0, 2e-4);
  }
}

TEST(SprungMass, SoftSuspensionGivesTheMovingForce) {
  const int n = 8;
  const double T = kL / kV, dt = 1e-4;
  const Series a = production(bridge(n, dt, T), {sprung(kKv * 1e-6, 0.0)});
  BeamProblem p = bridge(n, dt, T);
  MovingLoad f;
  f.kind = LoadKind::Force;
  f.force = -kMv * kG;
  f.speed = kV;
  p.loads.push_back(f);
  BeamSimulation sim(p);
  std::vector<double> mid;
  sim.run([&](const BeamSnapshot& s) { mid.push_back(s.deflection(0.5 * kL)); });
  const double wa = absmax(a.mid), wb = absmax(mid);
  std::cout << "k = 1.595 N/m: peak midspan " << wa << " m, moving force " << wb << " m (rel. diff " << wa / wb - 1
            << ")\n";
  EXPECT_NEAR(wa / wb, 1.0, 1e-3);
}

TEST(SprungMass, EnergyBalanceWithDamperDissipation) {
  // E(t) + int (dissipation - drive power) dt = E(0), the integral by the trapezoidal rule on
  // every step; its error O(dt^2) halves the residual four times per halving of dt.
  const double T = kL / kV;
  std::vector<double> residual;
  for (const double dt : {4e-4, 2e-4}) {
    BeamProblem p = bridge(6, dt, T);
    p.damping.kind = ModalDamping::Kind::Ratios;
    p.damping.ratios = {0.02};
    VehicleBeam sim(p, {sprung(kKv, 3e4)});
    double E0 = NAN, integral = 0, last_p = 0, last_t = 0, worst = 0, lost = 0;
    sim.run([&](const VehicleBeam& b) {
      const double P = b.dissipation_power() - b.drive_power();
      if (std::isnan(E0)) {
        E0 = b.mechanical_energy();
      } else {
        integral += 0.5 * (P + last_p) * (b.time() - last_t);
        lost += 0.5 * (b.dissipation_power()) * (b.time() - last_t);
      }
      last_p = P;
      last_t = b.time();
      worst = std::max(worst, std::abs(b.mechanical_energy() + integral - E0));
    });
    std::cout << "dt = " << dt << ": dissipated " << lost << " J, worst |E + int (D - P) - E0| " << worst << " J\n";
    EXPECT_GT(lost, 0.1);  // about 0.15 J: the damper works
    EXPECT_LT(worst, 1e-3 * lost);
    residual.push_back(worst);
  }
  EXPECT_NEAR(residual[0] / residual[1], 4.0, 0.5);
}

namespace {
// A 2-axle car: 4 m wheelbase, centre 1.5 m behind the front axle (axle loads 62.5 / 37.5 %).
Vehicle two_axle(double k, double c, double mw) {
  Vehicle v;
  v.name = "car";
  v.mass = kMv;
  v.pitch_inertia = kMv * 2.0 * 2.0;
  v.axles.push_back({1.5, k, c, mw});
  v.axles.push_back({-2.5, k * 1.5 / 2.5, c, mw});
  v.motion.speed = kV;
  return v;
}
}  // namespace

TEST(Vehicle, SoftTwoAxleCarGivesItsStaticAxleLoads) {
  // A soft suspension carries the static axle loads M g e_r / (e_f + e_r), M g e_f / (e_f + e_r)
  // as two moving forces 4 m apart, the rear one entering 4 m / v later.
  const int n = 8;
  const double T = (kL + 4.0) / kV, dt = 1e-4;
  const Series a = production(bridge(n, dt, T), {two_axle(kKv * 1e-6, 0.0, 0.0)});
  BeamProblem p = bridge(n, dt, T);
  for (const auto& [share, delay] : {std::pair<double, double>{2.5 / 4.0, 0.0}, {1.5 / 4.0, 4.0 / kV}}) {
    MovingLoad f;
    f.kind = LoadKind::Force;
    f.force = -kMv * kG * share;
    f.speed = kV;
    f.entry_time = delay;
    p.loads.push_back(f);
  }
  BeamSimulation sim(p);
  std::vector<double> mid;
  sim.run([&](const BeamSnapshot& s) { mid.push_back(s.deflection(0.5 * kL)); });
  ASSERT_EQ(a.mid.size(), mid.size());
  double worst = 0;
  for (std::size_t k = 0; k < mid.size(); ++k) worst = std::max(worst, std::abs(a.mid[k] - mid[k]));
  std::cout << "soft 2-axle car: largest difference of w(L/2) from the two moving forces " << worst / absmax(mid)
            << " of the peak\n";
  EXPECT_LT(worst, 1e-3 * absmax(mid));
}

TEST(Vehicle, StaticStartIsEquilibrium) {
  // A car standing on the beam (front axle at 15 m) with the beam's self weight: at t = 0 the
  // body's and the beam's accelerations are zero and the contact forces are the static axle loads.
  BeamProblem p = bridge(6, 1e-3, 0.01);
  p.self_weight = true;
  Vehicle v = two_axle(kKv, 1e4, 300.0);
  v.motion.speed = 0.0;
  v.motion.start = 15.0;
  VehicleBeam sim(p, {v});
  const double W = (kMv + 600.0) * kG;
  EXPECT_NEAR(sim.body_acceleration(0), 0.0, 1e-9 * kG);
  EXPECT_NEAR(sim.contact_force(0, 0) + sim.contact_force(0, 1), W, 1e-9 * W);
  EXPECT_NEAR(sim.contact_force(0, 0), kMv * kG * 2.5 / 4.0 + 300.0 * kG, 1e-9 * W);
  EXPECT_NEAR(sim.acceleration(10.0), 0.0, 1e-9 * kG);
  EXPECT_NEAR(sim.body_velocity(0), 0.0, 1e-12);
}

namespace {
// Error at t_end of (w(L/2), z, theta) against a fine RK4 reference, for a damped beam with a
// 2-axle car on damped suspensions and wheel masses (every term of the coupled system).
double vehicle_error(Integrator integ, double dt, const std::vector<double>& ref) {
  BeamProblem p = bridge(4, dt, 0.9);
  p.integrator = integ;
  p.damping.kind = ModalDamping::Kind::Ratios;
  p.damping.ratios = {0.02};
  VehicleBeam sim(p, {two_axle(kKv, 2e4, 800.0)});
  sim.run();
  const std::vector<double> s{sim.deflection(0.5 * kL) / 1e-4, sim.body_displacement(0) / 1e-3,
                              sim.body_pitch(0) / 1e-4};
  if (ref.empty()) return NAN;
  double e = 0;
  for (std::size_t k = 0; k < s.size(); ++k) e = std::max(e, std::abs(s[k] - ref[k]));
  return e;
}
std::vector<double> vehicle_reference() {
  BeamProblem p = bridge(4, 1e-5, 0.9);
  p.damping.kind = ModalDamping::Kind::Ratios;
  p.damping.ratios = {0.02};
  VehicleBeam sim(p, {two_axle(kKv, 2e4, 800.0)});
  sim.run();
  return {sim.deflection(0.5 * kL) / 1e-4, sim.body_displacement(0) / 1e-3, sim.body_pitch(0) / 1e-4};
}
double order(double e1, double e2) { return std::log(e1 / e2) / std::log(2.0); }
}  // namespace

TEST(Vehicle, OrdersOfRK4AndNewmark) {
  const std::vector<double> ref = vehicle_reference();
  const double e1 = vehicle_error(Integrator::RK4, 1e-3, ref), e2 = vehicle_error(Integrator::RK4, 5e-4, ref);
  const double n1 = vehicle_error(Integrator::Newmark, 4e-4, ref), n2 = vehicle_error(Integrator::Newmark, 2e-4, ref);
  std::cout << "RK4 errors " << e1 << ", " << e2 << ": order " << order(e1, e2) << "; Newmark errors " << n1 << ", "
            << n2 << ": order " << order(n1, n2) << "\n";
  EXPECT_NEAR(order(e1, e2), 4.0, 0.2);
  EXPECT_NEAR(order(n1, n2), 2.0, 0.1);
}

TEST(BeamDamping, OrdersWithMovingMassAndDamping) {
  auto run = [](Integrator integ, double dt) {
    BeamProblem p = bridge(4, dt, 0.9, integ);
    p.damping.kind = ModalDamping::Kind::Rayleigh;
    p.damping.mass = 0.5;
    p.damping.stiffness = 1e-4;
    MovingLoad m;
    m.kind = LoadKind::Mass;
    m.mass = 2e4;
    m.speed = kV;
    m.acceleration = 2.0;
    p.loads.push_back(m);
    BeamSimulation sim(p);
    sim.run();
    return sim.deflection(0.5 * kL);
  };
  const double ref = run(Integrator::RK4, 1e-5);
  const double e1 = std::abs(run(Integrator::RK4, 1e-3) - ref), e2 = std::abs(run(Integrator::RK4, 5e-4) - ref);
  const double n1 = std::abs(run(Integrator::Newmark, 4e-4) - ref), n2 = std::abs(run(Integrator::Newmark, 2e-4) - ref);
  std::cout << "damped moving mass: RK4 order " << order(e1, e2) << ", Newmark order " << order(n1, n2) << "\n";
  EXPECT_NEAR(order(e1, e2), 4.0, 0.2);
  EXPECT_NEAR(order(n1, n2), 2.0, 0.1);
}

TEST(SprungMass, UnilateralContactEndsAtLiftOff) {
  // A stiff suspension (417 rad/s) coming from level ground (it reaches x = 0 at 0.01 s) onto the
  // bridge sagged under its own weight: at entry the wheel follows the slope w_x(0) < 0 down at v |w_x(0)| = 0.06 m/s, more than the body on its
  // spring can follow (v |w_x| omega_v > g), so the contact force falls to zero within a quarter
  // period of the suspension. The run ends there (|F| ~ 0); the bilateral run, stopped at the
  // same instant, has the same (zero) force: the event is located on the trajectory.
  const double k = 1e9, omega_v = std::sqrt(k / kMv);
  BeamProblem p = bridge(8, 1e-5, kL / kV);
  p.self_weight = true;
  Vehicle v = sprung(k, 0.0);
  v.motion.entry_time = 0.01;
  Vehicle bilateral = v;
  v.unilateral = true;
  VehicleBeam sim(p, {v});
  sim.run();
  ASSERT_EQ(sim.end_reason(), VehicleEnd::LiftOff);
  const double t_off = sim.time(), F = sim.contact_force(0, 0);
  std::cout << "lift-off at t = " << t_off << " s (a quarter period: " << 0.5 * kPi / omega_v << " s), contact force "
            << F << " N\n";
  EXPECT_GT(t_off, 0.01);
  EXPECT_LT(t_off, 0.01 + 0.5 * kPi / omega_v);
  EXPECT_LT(std::abs(F), 1e-8 * kMv * kG);
  BeamProblem q = p;
  q.t_end = t_off;
  VehicleBeam both(q, {bilateral});
  both.run();
  EXPECT_EQ(both.end_reason(), VehicleEnd::EndTime);
  EXPECT_LT(std::abs(both.contact_force(0, 0)), 1e-6 * kMv * kG);
}

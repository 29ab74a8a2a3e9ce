// The sprung mass on the rod (rod::CoupledRodStepper with a suspension and a prescribed path,
// docs/rod.md "Sprung mass") on the serial reference stepper, on the hanging cable of the
// reference scenes: its stiff limit against the rod's own moving mass M_v + m_w, the energy
// balance with the damper's dissipation, and the body's damped oscillation on a rigid track.
#include <gtest/gtest.h>

#include "reference_stepper.hpp"

#include "hanging_cable.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "traverse/rod/coupled_mass_rod.hpp"

using namespace traverse;

namespace {

constexpr double kG = 9.8, kL = 1.0, kS0 = 0.1, kV = 2.0;

rod::CoupledRodMass sprung(double body, double wheel, double k, double c, double v = kV) {
  rod::CoupledRodMass m;
  m.mass = wheel;
  m.path_sigma = [v](double t) { return kS0 + v * t; };
  m.path_speed = [v](double) { return v; };
  m.suspended = true;
  m.suspension = {body, k, c, Vec3::UnitY()};
  return m;
}

rod::RodState start(int cells, double weight, const rod::RodProperties& props) {
  bool converged = false;
  const rod::RodState s =
      traverse::testing::static_start(traverse::testing::hanging_cable_statics(props, cells, kL, kG, weight, kS0), converged);
  EXPECT_TRUE(converged);
  return s;
}

struct History {
  std::vector<double> mid;      ///< midspan deflection (j) at every step
  std::vector<double> balance;  ///< energy balance (sprung runs)
  double damper_work = 0.0;
};

/// The sprung mass from s0 at its path's speed to t_end, steps of ds / (2 kV), from the static
/// state under its weight (or under gravity alone: `loaded` false).
History run_sprung(int cells, const rod::CoupledRodMass& mass, double t_end, const rod::RodProperties& props,
                   int refine = 1, bool loaded = true) {
  const rod::RodModel model = traverse::testing::hanging_cable_model(props, cells, kL, kG);
  rod::RodState state = start(cells, loaded ? (mass.mass + mass.suspension.body_mass) * kG : 0.0, props);
  rod::CoupledRodStepper stepper(model, mass, rod::reference_rod_solve);
  rod::CoupledMassState m{kS0, mass.path_speed(0.0)};
  rod::start_suspension(mass, model, state, m);
  std::vector<Vec3> r = rod::centreline_in_space(state);
  History h;
  auto record = [&] {
    h.mid.push_back(r[static_cast<size_t>(cells / 2)].y());
    h.balance.push_back(rod::coupled_energies(stepper.model(), state, r, m, mass).balance());
  };
  record();
  const double dt = model.ds() / (2.0 * kV * refine);
  const long steps = std::lround(t_end / dt);
  for (long k = 1; k <= steps; ++k) {
    const rod::RodState old = state;
    const rod::CoupledStepReport rep = stepper.step(state, m, dt);
    EXPECT_TRUE(rep.converged) << "step " << k;
    if (!rep.converged) break;
    r = rod::advance_centreline_in_time(r, old, state);
    if (k % refine == 0) record();
  }
  h.damper_work = m.damper_work;
  return h;
}

/// The same path (at speed v) with the rod's own moving load (reference stepper, no coupling).
History run_moving(int cells, double mass, bool inertia, double t_end, const rod::RodProperties& props,
                   double v = kV, bool loaded = true) {
  rod::RodModel model = traverse::testing::hanging_cable_model(props, cells, kL, kG);
  rod::MovingMass mm = traverse::testing::uniform_mass(mass, v, inertia);
  mm.sigma = [v](double t) { return kS0 + v * t; };
  model.loads.masses.push_back(mm);
  rod::RodState state = start(cells, loaded ? mass * kG : 0.0, props);
  const rod::ReferenceStepper stepper(model);
  std::vector<Vec3> r = rod::centreline_in_space(state);
  History h;
  h.mid.push_back(r[static_cast<size_t>(cells / 2)].y());
  const double dt = model.ds() / (2.0 * kV);
  for (long k = 1; k <= std::lround(t_end / dt); ++k) {
    const rod::RodState old = state;
    EXPECT_TRUE(stepper.step(state, dt).converged) << "step " << k;
    r = rod::advance_centreline_in_time(r, old, state);
    h.mid.push_back(r[static_cast<size_t>(cells / 2)].y());
  }
  return h;
}

/// max |a - b| / max |b - b_0| over the common steps.
double relative_difference(const History& a, const History& b) {
  double d = 0.0, scale = 0.0;
  for (size_t i = 0; i < std::min(a.mid.size(), b.mid.size()); ++i) {
    d = std::max(d, std::abs(a.mid[i] - b.mid[i]));
    scale = std::max(scale, std::abs(b.mid[i] - b.mid[0]));
  }
  return d / scale;
}

constexpr double kBody = 0.02, kWheel = 0.005, kT = 0.3;

}  // namespace

// A stiff suspension moves the body with the wheel: the rod carries the moving mass M_v + m_w.
// As k grows the sprung mass converges to its own stiff limit (the body lags the wheel by its
// quasi-static stretch M_v w'' / k: differences as 1 / k), and that limit is the rod's own moving
// mass (reference stepper, no coupling) up to how the body's inertia along j reaches the rod:
// through the spring at the wheel's point against the moving mass's short line mass, the same
// load to second order in (ds, dt).
TEST(SprungMassRod, StiffSuspensionGivesTheMovingMass) {
  const rod::RodProperties props = rod::RodProperties::scene_rod();
  const double stiff = 1e8;
  std::vector<double> to_moving;
  for (int cells : {20, 40, 80}) {
    to_moving.push_back(relative_difference(run_sprung(cells, sprung(kBody, kWheel, stiff, 0.0), kT, props),
                                            run_moving(cells, kBody + kWheel, true, kT, props)));
    std::printf("%d cells, k = %.0e N/m: midspan against the moving mass %.3e (relative)\n", cells, stiff,
                to_moving.back());
  }
  EXPECT_NEAR(std::log2(to_moving[0] / to_moving[1]), 2.0, 0.3);
  EXPECT_NEAR(std::log2(to_moving[1] / to_moving[2]), 2.0, 0.3);
  const History limit = run_sprung(80, sprung(kBody, kWheel, stiff, 0.0), kT, props);
  std::vector<double> to_limit;
  for (double k : {1e3, 1e4, 1e5}) {
    to_limit.push_back(relative_difference(run_sprung(80, sprung(kBody, kWheel, k, 0.0), kT, props), limit));
    std::printf("80 cells, k = %.0e N/m: midspan against k = %.0e N/m %.3e (relative)\n", k, stiff, to_limit.back());
  }
  EXPECT_NEAR(std::log10(to_limit[0] / to_limit[1]), 1.0, 0.15);
  EXPECT_NEAR(std::log10(to_limit[1] / to_limit[2]), 1.0, 0.15);
}

// Rod + wheel + body + damper work is constant up to the discretisation: the drift of the
// balance falls at second order in (ds, dt) together (the moving load's work, as for the coupled
// mass), while the damper dissipates much more.
TEST(SprungMassRod, EnergyBalanceWithDamperDissipation) {
  const rod::RodProperties props = rod::RodProperties::scene_rod();
  std::vector<double> drift;
  double dissipated = 0.0;
  for (int cells : {20, 40, 80}) {
    const History h = run_sprung(cells, sprung(kBody, kWheel, 2.0, 0.2), kT, props);
    double d = 0.0;
    for (double b : h.balance) d = std::max(d, std::abs(b - h.balance[0]));
    drift.push_back(d);
    dissipated = h.damper_work;
    std::printf("%d cells: balance drift %.3e J, damper work %.4e J\n", cells, d, h.damper_work);
  }
  EXPECT_GT(dissipated, 100.0 * drift.back());
  EXPECT_NEAR(std::log2(drift[0] / drift[1]), 2.0, 0.3);
  EXPECT_NEAR(std::log2(drift[1] / drift[2]), 2.0, 0.3);
}

// On a track that hardly deflects (the cable's stiffness times 1e4; the wheel parked), a body
// started with a velocity u0 relative to its rest oscillates as the damped oscillator: z - z0 =
// (u0 / omega_d) exp(-zeta omega t) sin(omega_d t). The midpoint rule's phase error is second
// order in dt.
TEST(SprungMassRod, BodyOscillatesAsTheDampedOscillatorOnARigidTrack) {
  rod::RodProperties props = rod::RodProperties::scene_rod();
  props.K *= 1e4;
  const double k = 2.0, c = 0.02, u0 = 0.01, T = 0.6;
  const double w = std::sqrt(k / kBody), zeta = c / (2.0 * std::sqrt(k * kBody)), wd = w * std::sqrt(1.0 - zeta * zeta);
  const rod::CoupledRodMass mass = sprung(kBody, kWheel, k, c, 0.0);
  std::vector<double> err;
  for (int refine : {1, 2, 4}) {
    const int cells = 40;
    const rod::RodModel model = traverse::testing::hanging_cable_model(props, cells, kL, kG);
    rod::RodState state = start(cells, (kBody + kWheel) * kG, props);
    rod::CoupledRodStepper stepper(model, mass, rod::reference_rod_solve);
    rod::CoupledMassState m{kS0, 0.0};
    rod::start_suspension(mass, model, state, m);
    const double z0 = m.body;
    m.body_speed += u0;
    const double dt = 0.1 / (w * refine);
    double e = 0.0;
    for (long n = 1; n <= std::lround(T / dt); ++n) {
      ASSERT_TRUE(stepper.step(state, m, dt).converged);
      const double t = n * dt, exact = u0 / wd * std::exp(-zeta * w * t) * std::sin(wd * t);
      e = std::max(e, std::abs(m.body - z0 - exact));
    }
    err.push_back(e / (u0 / w));
    std::printf("dt = %.4g s: body against the damped oscillator %.3e (relative to u0 / omega)\n", dt, err.back());
  }
  EXPECT_LT(err[0], 1e-2);
  EXPECT_NEAR(std::log2(err[0] / err[1]), 2.0, 0.2);
  EXPECT_NEAR(std::log2(err[1] / err[2]), 2.0, 0.2);
}


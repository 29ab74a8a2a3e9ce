// The coupled mass's rod step on the distributed stepper (solver::DistributedCoupledRodSolve) on
// 1 and 2 ranks, planar and 3D path, against the serial reference solve (docs/rod.md "Coupled
// mass"): a bead with drive and resistance on the hanging cable, crossing midspan (the rank
// boundary on 2 ranks).
#include <gtest/gtest.h>

#include "reference_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "hanging_cable.hpp"
#include "rod_mpi_test_util.hpp"
#include "traverse/rod/planar.hpp"
#include "traverse/solver/coupled_rod_solve.hpp"

namespace traverse::solver {
namespace {

using test::say;

struct Compared {
  double worst_state = 0.0, worst_mass = 0.0, sigma = 0.0;
  int coupling_reference = 0, coupling = 0;
};

/// `steps` steps of dt of the coupled stepper on the reference solve and on the distributed
/// one, from the same state: the largest differences.
Compared compare(const rod::RodModel& model, const rod::RodState& initial, const rod::CoupledRodMass& mass,
                 const rod::CoupledMassState& m0, double dt, int steps, bool planar) {
  rod::CoupledRodStepper reference(model, mass, rod::reference_rod_solve);
  DistributedCoupledRodSolve* made = nullptr;
  rod::CoupledRodStepper distributed(model, mass, [&](rod::RodModel with_mass) {
    auto st = std::make_unique<DistributedStepper>(std::move(with_mass), test::comm(), test::solver_params("auto"));
    auto solve = std::make_unique<DistributedCoupledRodSolve>(std::move(st), MPI_COMM_WORLD);
    made = solve.get();
    return solve;
  });
  Compared c;
  EXPECT_NE(made, nullptr);
  if (!made) return c;
  made->stepper().set_state(initial);
  if (planar) {
    const rod::PlanarCheck pc = rod::check_planar(model, initial, {});
    EXPECT_TRUE(pc.planar) << pc.reason;
    made->stepper().set_planar(&pc.symmetry);
  }
  rod::RodState a = initial, b = initial;
  rod::CoupledMassState ma = m0, mb = m0;
  for (int i = 0; i < steps; ++i) {
    const auto ra = reference.step(a, ma, dt), rb = distributed.step(b, mb, dt);
    EXPECT_TRUE(ra.converged && rb.converged) << "step " << i;
    if (!ra.converged || !rb.converged) break;
    c.coupling_reference += ra.coupling_iterations;
    c.coupling += rb.coupling_iterations;
    c.worst_state = std::max(c.worst_state, test::max_difference(a, b));
    c.worst_mass = std::max({c.worst_mass, std::abs(ma.sigma - mb.sigma), std::abs(ma.speed - mb.speed) * dt,
                             std::abs(ma.drive_work - mb.drive_work), std::abs(ma.dissipated - mb.dissipated),
                             std::abs(ma.body - mb.body), std::abs(ma.body_speed - mb.body_speed) * dt,
                             std::abs(ma.damper_work - mb.damper_work)});
  }
  c.sigma = mb.sigma;
  return c;
}

TEST(CoupledRodSolve, DistributedTakesTheReferencesSteps) {
  // The hanging cable (scene rod, 40 cells) in static equilibrium under the mass's weight at sigma0.
  const double M = 0.05, sigma0 = 0.4, g = 9.8;
  const rod::RodModel model = testing::hanging_cable_model(rod::RodProperties::scene_rod(), 40, 1.0, g);
  bool converged = false;
  const rod::RodState initial = testing::static_start(
      testing::hanging_cable_statics(model.props, 40, 1.0, g, M * g, sigma0), converged);
  ASSERT_TRUE(converged);
  const rod::CoupledRodMass mass{M, 0.2, 0.05, 0.0};  // drive 0.2 N, resistance 0.05 N s/m
  const double dt = 0.5 * model.ds() / 2.0;
  for (const bool planar : {false, true}) {
    // 24 steps at about 2 m/s: from 0.4 m past 0.6 m
    const Compared c = compare(model, initial, mass, {sigma0, 2.0}, dt, 24, planar);
    say("  %s path, %d rank(s): sigma %.6f -> %.6f m; max |state difference| %.2e, max |mass difference| %.2e; "
        "coupling iterations %d (reference) / %d\n",
        planar ? "planar" : "3D", test::ranks(), sigma0, c.sigma, c.worst_state, c.worst_mass, c.coupling_reference,
        c.coupling);
    EXPECT_GT(c.sigma, 0.6);  // crossed midspan, where 2 ranks split the rod
    EXPECT_LE(c.worst_state, 1e-11);  // measured 2e-14 .. 3e-14
    EXPECT_LE(c.worst_mass, 1e-13);
    EXPECT_LE(std::abs(c.coupling_reference - c.coupling), c.coupling_reference / 10);  // measured: equal
  }
}

// The sprung mass (a body on a damped spring over a wheel at a prescribed speed) across the rank
// boundary: the same steps as the reference solve.
TEST(CoupledRodSolve, SprungMassTakesTheReferencesSteps) {
  const double body = 0.02, wheel = 0.005, sigma0 = 0.4, v = 2.0, g = 9.8;
  const rod::RodModel model = testing::hanging_cable_model(rod::RodProperties::scene_rod(), 40, 1.0, g);
  bool converged = false;
  const rod::RodState initial = testing::static_start(
      testing::hanging_cable_statics(model.props, 40, 1.0, g, (body + wheel) * g, sigma0), converged);
  ASSERT_TRUE(converged);
  rod::CoupledRodMass mass;
  mass.mass = wheel;
  mass.path_sigma = [=](double t) { return sigma0 + v * t; };
  mass.path_speed = [=](double) { return v; };
  mass.suspended = true;
  mass.suspension = {body, 20.0, 0.2, Vec3::UnitY()};
  rod::CoupledMassState m0{sigma0, v};
  rod::start_suspension(mass, model, initial, m0);
  for (const bool planar : {false, true}) {
    const Compared c = compare(model, initial, mass, m0, 0.5 * model.ds() / v, 24, planar);
    say("  sprung mass, %s path, %d rank(s): max |state difference| %.2e, max |mass difference| %.2e; coupling "
        "iterations %d (reference) / %d\n", planar ? "planar" : "3D", test::ranks(), c.worst_state, c.worst_mass,
        c.coupling_reference, c.coupling);
    EXPECT_GT(c.sigma, 0.6);
    EXPECT_LE(c.worst_state, 1e-11);
    EXPECT_LE(c.worst_mass, 1e-13);
    EXPECT_LE(std::abs(c.coupling_reference - c.coupling), c.coupling_reference / 10);
  }
}

}  // namespace
}  // namespace traverse::solver

// The coupled mass's rod step on the distributed stepper (solver::DistributedCoupledRodSolve) on
// 1 and 2 ranks, planar and 3D path, against the serial reference solve (docs/rod.md "Coupled
// mass"): a bead with drive and resistance on the hanging cable, crossing midspan (the rank
// boundary on 2 ranks).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rod_mpi_test_util.hpp"
#include "traverse/rod/planar.hpp"
#include "traverse/rod/static_solver.hpp"
#include "traverse/solver/coupled_rod_solve.hpp"

namespace traverse::solver {
namespace {

using test::say;

/// The hanging cable (scene rod, clamped / sliding along k, gravity -9.8 j), N cells, in static
/// equilibrium under gravity and the mass's weight M g at sigma0.
void cable(int N, double M, double sigma0, rod::RodModel& m, rod::RodState& state) {
  m.props = rod::RodProperties::scene_rod();
  m.num_cells = N;
  m.length = 1.0;
  m.left = rod::EndCondition::make_clamped();
  m.right = rod::EndCondition::make_sliding(Vec3::UnitZ());
  m.loads.gravity = Vec3(0.0, -9.8, 0.0);
  state = test::hanging_cable_equilibrium(m, Vec3(0.0, -M * 9.8, 0.0), sigma0);
}

TEST(CoupledRodSolve, DistributedTakesTheReferencesSteps) {
  rod::RodModel model;
  rod::RodState initial;
  const double M = 0.05, sigma0 = 0.4;
  cable(40, M, sigma0, model, initial);
  const rod::CoupledRodMass mass{M, 0.2, 0.05, 0.0};  // drive 0.2 N, resistance 0.05 N s/m
  const double dt = 0.5 * model.ds() / 2.0;
  const int steps = 24;  // at about 2 m/s: from 0.4 m past 0.6 m
  for (const bool planar : {false, true}) {
    rod::CoupledRodStepper reference(model, mass);
    DistributedCoupledRodSolve* made = nullptr;
    rod::CoupledRodStepper distributed(model, mass, [&](rod::RodModel with_mass) {
      auto st = std::make_unique<DistributedStepper>(std::move(with_mass), test::comm(), test::solver_params("auto"));
      auto solve = std::make_unique<DistributedCoupledRodSolve>(std::move(st), MPI_COMM_WORLD);
      made = solve.get();
      return solve;
    });
    ASSERT_NE(made, nullptr);
    made->stepper().set_state(initial);
    if (planar) {
      const rod::PlanarCheck c = rod::check_planar(model, initial, {});
      ASSERT_TRUE(c.planar) << c.reason;
      made->stepper().set_planar(&c.symmetry);
    }
    rod::RodState a = initial, b = initial;
    rod::CoupledMassState ma{sigma0, 2.0}, mb{sigma0, 2.0};
    double worst_state = 0.0, worst_mass = 0.0;
    int coupling_a = 0, coupling_b = 0;
    for (int i = 0; i < steps; ++i) {
      const auto ra = reference.step(a, ma, dt), rb = distributed.step(b, mb, dt);
      ASSERT_TRUE(ra.converged && rb.converged) << "step " << i;
      coupling_a += ra.coupling_iterations;
      coupling_b += rb.coupling_iterations;
      worst_state = std::max(worst_state, test::max_difference(a, b));
      worst_mass = std::max({worst_mass, std::abs(ma.sigma - mb.sigma), std::abs(ma.speed - mb.speed) * dt,
                             std::abs(ma.drive_work - mb.drive_work), std::abs(ma.dissipated - mb.dissipated)});
    }
    say("  %s path, %d rank(s): sigma %.6f -> %.6f m; max |state difference| %.2e, max |mass difference| %.2e; "
        "coupling iterations %d (reference) / %d; %s\n",
        planar ? "planar" : "3D", test::ranks(), sigma0, mb.sigma, worst_state, worst_mass, coupling_a, coupling_b,
        made->stepper().newton_implementation().c_str());
    EXPECT_GT(mb.sigma, 0.6);  // crossed midspan, where 2 ranks split the rod
    EXPECT_LE(worst_state, 1e-11);  // measured 2e-14 .. 3e-14
    EXPECT_LE(worst_mass, 1e-13);
    EXPECT_LE(std::abs(coupling_a - coupling_b), coupling_a / 10);  // measured: equal
  }
}

}  // namespace
}  // namespace traverse::solver

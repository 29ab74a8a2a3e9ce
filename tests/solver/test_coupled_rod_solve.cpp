// The coupled mass's rod step on the distributed stepper (solver::DistributedCoupledRodSolve) on
// 1 and 2 ranks, planar and 3D path, against the serial reference solve (docs/rod.md "Coupled
// mass"): a bead with drive and resistance on the hanging cable, crossing midspan (the rank
// boundary on 2 ranks).
#include <gtest/gtest.h>

#include "reference_stepper.hpp"

#include <cmath>
#include <vector>

#include "hanging_cable.hpp"
#include "rod_mpi_test_util.hpp"
#include "traverse/rod/planar.hpp"
#include "traverse/solver/coupled_rod_solve.hpp"

namespace traverse::solver {
namespace {

using test::say;

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
  const int steps = 24;  // at about 2 m/s: from 0.4 m past 0.6 m
  for (const bool planar : {false, true}) {
    rod::CoupledRodStepper reference(model, mass, rod::reference_rod_solve);
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
        "coupling iterations %d (reference) / %d\n",
        planar ? "planar" : "3D", test::ranks(), sigma0, mb.sigma, worst_state, worst_mass, coupling_a, coupling_b);
    EXPECT_GT(mb.sigma, 0.6);  // crossed midspan, where 2 ranks split the rod
    EXPECT_LE(worst_state, 1e-11);  // measured 2e-14 .. 3e-14
    EXPECT_LE(worst_mass, 1e-13);
    EXPECT_LE(std::abs(coupling_a - coupling_b), coupling_a / 10);  // measured: equal
  }
}

}  // namespace
}  // namespace traverse::solver

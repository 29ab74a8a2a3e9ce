// Numerical stress: long runs of the production stepper (solver::DistributedStepper).
//  - free vibration of a cantilever rod (scene rod, default scheme rho_inf = 1) released from
//    a small initial curvature: discrete energy drift, frame orthonormality, no NaN;
//  - a travelling point load on the same rod under gravity: orthonormality, no NaN,
//    energy bounded.
// Sizes: CI (ctest -L stress) N = 20 cells, 1e4 steps; TRAVERSE_STRESS_FULL=1 (scripts/stress.sh)
// N = 100, 1e5 steps. Measured values: docs/reliability.md.
#include <gtest/gtest.h>

#include <Teuchos_DefaultComm.hpp>
#include <Tpetra_Core.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "traverse/core/so3.hpp"
#include "traverse/rod/rod_model.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/solver/distributed_stepper.hpp"

using namespace traverse;

namespace {

bool full_size() {
  const char* f = std::getenv("TRAVERSE_STRESS_FULL");
  return f != nullptr && std::string(f) == "1";
}

struct LongRunResult {
  double e0 = 0.0, e_min = 0.0, e_max = 0.0, e_last = 0.0;
  double e1 = 0.0;           // energy at the first sample after stepping (step `every`)
  double max_drift = 0.0;    // max |E - E1| / E1: drift after the start-up step
  double start_jump = 0.0;   // |E1 - E0| / E0: change over the first `every` steps
  double max_defect = 0.0;   // max over nodes and samples of so3::orthonormality_defect(R)
  bool finite = true;
  int max_newton = 0;
  long steps = 0;
  double seconds = 0.0;
};

// Newton tolerances: the production defaults (docs/solver.md), or tight ones.
Teuchos::ParameterList solver_params(bool tight) {
  Teuchos::ParameterList params;
  params.set("Verbose", false);
  if (tight) {
    params.set("Residual Tolerance", 1e-13);
    params.set("Update Relative Tolerance", 1e-13);
    params.set("Update Absolute Tolerance", 1e-16);
  }
  return params;
}

long steps_override(long fallback) {
  const char* s = std::getenv("TRAVERSE_STRESS_STEPS");
  return s != nullptr ? std::atol(s) : fallback;
}

LongRunResult long_run(rod::RodModel model, const rod::RodState& initial, double dt, long steps, int every,
                       bool tight = false) {
  const Teuchos::ParameterList params = solver_params(tight);
  solver::DistributedStepper stepper(model, Tpetra::getDefaultComm(), params);
  stepper.set_state(initial);
  LongRunResult r;
  auto sample = [&](const rod::RodState& s) {
    const double e = rod::discrete_energy(s, model.props);
    for (const auto& nd : s.nodes) {
      r.max_defect = std::max(r.max_defect, so3::orthonormality_defect(nd.R));
      if (!nd.y.allFinite() || !nd.R.allFinite() || !nd.yt.allFinite()) r.finite = false;
    }
    if (!std::isfinite(e)) r.finite = false;
    return e;
  };
  r.e0 = r.e_min = r.e_max = sample(stepper.gather_state());
  const auto t0 = std::chrono::steady_clock::now();
  for (long i = 1; i <= steps; ++i) {
    const auto rep = stepper.step(dt);  // throws StepFailure: the test fails
    r.max_newton = std::max(r.max_newton, rep.newton_iterations);
    if (i % every == 0 || i == steps) {
      const double e = sample(stepper.gather_state());
      r.e_min = std::min(r.e_min, e);
      r.e_max = std::max(r.e_max, e);
      r.e_last = e;
      if (i == every) {
        r.e1 = e;
        r.start_jump = std::abs(e - r.e0) / r.e0;
      }
      if (r.e1 > 0.0) r.max_drift = std::max(r.max_drift, std::abs(e - r.e1) / r.e1);
      if (!r.finite) break;
    }
    r.steps = i;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

rod::RodModel scene_cantilever(int N) {
  rod::RodModel m;
  m.props = rod::RodProperties::scene_rod();  // r = 5 mm, E = 250 MPa, rho = 1500 kg/m^3
  m.alpha = rod::AlphaParameters::from_rho_inf(1.0);  // the scenes' default
  m.num_cells = N;
  m.length = 1.0;
  m.left = rod::EndCondition::make_clamped();
  m.right = rod::EndCondition::make_free();
  return m;
}

/// Round-off bound of the frames' orthonormality defect after `steps` time steps: one
/// rounding per step at most (each step multiplies R by an exactly orthogonal update computed
/// in floating point), i.e. steps * epsilon (2.2e-12 for 1e4 steps).
double defect_bound(long steps) { return static_cast<double>(steps) * std::numeric_limits<double>::epsilon(); }

}  // namespace

TEST(StressLongRun, FreeVibrationConservesEnergyAndFrames) {
  const bool full = full_size();
  const int N = full ? 100 : 20;
  const long steps = steps_override(full ? 100000 : 10000);
  const double dt = 1e-3;  // first cantilever period 1.75 s: 1e4 steps = 5.7 periods
  rod::RodModel m = scene_cantilever(N);
  m.loads.gravity = Vec3::Zero();
  // Small curvature perturbation in both bending directions and twist, released at rest.
  const auto init = rod::state_from_curvature(N, 1.0, [](double s) {
    return Vec3(0.05 * std::sin(constants::pi * s), 0.02 * s * s, 0.01 * s);
  });
  // Tight Newton tolerances (full size only) show whether the drift is the solver's.
  for (bool tight : full ? std::vector<bool>{false, true} : std::vector<bool>{false}) {
  const auto r = long_run(m, init, dt, steps, 10, tight);
  std::printf("free vibration, %s Newton tolerances, N = %d, dt = %g s, %ld steps (%.1f s): E0 = %.6e J, E in [%.6e, %.6e], "
              "change over the first 10 steps %.3e, then max relative drift %.3e, max orthonormality defect %.3e, "
              "max Newton its %d\n",
              tight ? "tight" : "default", N, dt, r.steps, r.seconds, r.e0, r.e_min, r.e_max, r.start_jump, r.max_drift,
              r.max_defect, r.max_newton);
  EXPECT_TRUE(r.finite);
  EXPECT_EQ(r.steps, steps);
  EXPECT_GT(r.e0, 0.0);
  // The release from rest with zero histories (yt = 0) is not a consistent start of the
  // generalised-alpha scheme: the first step changes E by about 1.5 %; afterwards E is
  // conserved (nonlinear rod: to the Newton tolerance, not exactly).
  EXPECT_LT(r.start_jump, 0.05);
  // Measured 4.8e-5 over 1e3 steps with default and with tight tolerances alike: the
  // nonlinear terms, bounded (an oscillation, not a trend).
  EXPECT_LT(r.max_drift, 1e-3);
  // R stays orthonormal to round-off: at most one rounding (epsilon) per step accumulated.
  // Measured 4.4e-14 after 1e4 steps (N = 20), 1.5e-12 after 1e5 steps (N = 100; the bound
  // is then 2.2e-11): a fixed 1e-12 failed at full size although nothing drifts beyond that.
  EXPECT_LT(r.max_defect, defect_bound(r.steps));
  }
}

TEST(StressLongRun, TravellingLoadKeepsFramesAndStaysBounded) {
  const bool full = full_size();
  const int N = full ? 100 : 20;
  const long steps = steps_override(full ? 100000 : 10000);
  const double dt = 1e-3;
  rod::RodModel m = scene_cantilever(N);
  m.loads.gravity = Vec3(0.0, -9.81, 0.0);
  // -0.05 j N from s = 0.1 m towards the tip, on the rod for the whole run.
  const double v = 0.8 / (dt * static_cast<double>(steps));
  m.loads.point_forces.push_back({[](double) { return Vec3(0.0, -0.05, 0.0); }, [v](double t) { return 0.1 + v * t; }});
  const auto init = rod::straight_rest_state(N, 1.0);
  const auto r = long_run(m, init, dt, steps, 10);
  std::printf("travelling load, N = %d, dt = %g s, %ld steps (%.1f s): E in [%.6e, %.6e] J, "
              "max orthonormality defect %.3e, max Newton its %d\n",
              N, dt, r.steps, r.seconds, r.e_min, r.e_max, r.max_defect, r.max_newton);
  EXPECT_TRUE(r.finite);
  EXPECT_EQ(r.steps, steps);
  EXPECT_LT(r.max_defect, defect_bound(r.steps));
  // Bounded: the work of gravity and the load on a 1 m rod of 0.118 kg is below 1 J.
  EXPECT_LT(r.e_max, 1.0);
}

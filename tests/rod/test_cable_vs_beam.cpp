// The hanging cable under a small travelling load against the small-deflection beam
// (beam module, clamped-clamped) of the same problem: the rod model must reproduce the
// beam in the stiff limit. Rod: clamped at s = 0, clamped and sliding along k at s = L,
// static initial state under gravity, box scheme with dt = ds / v. Beam: Galerkin on the
// clamped-clamped modes, RK4 at a small step, static initial state under its own weight.
#include <gtest/gtest.h>

#include "hanging_cable.hpp"

#include <cmath>

#include "traverse/beam/beam_simulation.hpp"
#include "reference_stepper.hpp"
#include "traverse/rod/static_load_steps.hpp"

using namespace traverse;

namespace {

struct Histories {
  std::vector<double> rod, beam;
};

// Midspan height histories under a load F moving at alpha v1 with gravity g.
Histories run(double F, double g, double alpha, int cells, int modes) {
  const rod::RodProperties props = rod::RodProperties::scene_rod();
  const double L = 1.0, EI = props.K(0), rhoA = props.rhoA;
  const double v1 = std::pow(4.7300 / L, 2) * std::sqrt(EI / rhoA) * L / M_PI;
  const double v = alpha * v1, ds = L / cells, dt = ds / v;

  bool converged = false;
  rod::RodState state = traverse::testing::static_start(traverse::testing::hanging_cable_statics(props, cells, L, g, F, 0.0), converged);
  EXPECT_TRUE(converged);
  rod::RodModel m = traverse::testing::hanging_cable_model(props, cells, L, g);
  m.loads.point_forces.push_back({[F](double) { return Vec3(0, -F, 0); }, [v](double t) { return v * t; }});
  rod::ReferenceStepper stepper(m);

  beam::BeamProblem p;
  p.length = L;
  p.EI = EI;
  p.rhoA = rhoA;
  p.support = beam::Support::ClampedClamped;
  p.n_modes = modes;
  p.gravity = g;
  beam::MovingLoad load;
  load.kind = beam::LoadKind::Force;
  load.force = -F;
  load.speed = v;
  p.loads.push_back(load);
  p.t_end = L / v;
  const int sub = 20;  // beam steps per rod step
  p.dt = dt / sub;
  p.output_every = sub;
  p.integrator = beam::Integrator::RK4;
  Histories h;
  beam::BeamSimulation sim(p);
  sim.run([&](const beam::BeamSnapshot& s) { h.beam.push_back(s.deflection(0.5 * L)); });

  for (int i = 0; i <= cells; ++i) {
    if (i > 0) {
      EXPECT_TRUE(stepper.step(state, dt).converged) << "rod step " << i;
    }
    h.rod.push_back(rod::centreline_in_space(state)[static_cast<size_t>(cells / 2)].y());
  }
  h.beam.resize(h.rod.size());
  return h;
}

double max_abs(const std::vector<double>& a) {
  double m = 0.0;
  for (double x : a) m = std::max(m, std::abs(x));
  return m;
}

double max_diff(const Histories& h) {
  double m = 0.0;
  for (size_t i = 0; i < h.rod.size(); ++i) m = std::max(m, std::abs(h.rod[i] - h.beam[i]));
  return m;
}

}  // namespace

TEST(CableVsBeam, SmallLoadMidspanHistoryMatchesTheBeam) {
  // Stiff limit: F = 0.02 N and g = 0.098 m/s^2, so the deflection stays near 1e-3 L and
  // geometric nonlinearity is O(1e-6) relative; what remains is the rod's discretisation
  // error (second order in ds = 0.01) and its rotary inertia ((r/L)^2 ~ 2.5e-5).
  for (double alpha : {0.25, 0.5, 1.0}) {
    const Histories h = run(0.02, 0.098, alpha, 100, 20);
    const double rel = max_diff(h) / max_abs(h.beam);
    std::cout << "  alpha = " << alpha << ": max |y_rod - w_beam| / max |w_beam| = " << rel
              << " (max |w| = " << max_abs(h.beam) << " m)\n";
    EXPECT_LT(rel, 5e-3) << "alpha " << alpha;
  }
}

TEST(CableVsBeam, TheDifferenceIsTheRodsSecondOrderDiscretisationError) {
  // Halving ds (and dt = ds / v with it) divides the difference by about 4.
  double d[3];
  const int cells[3] = {50, 100, 200};
  for (int c = 0; c < 3; ++c) {
    const Histories h = run(0.02, 0.098, 0.5, cells[c], 20);
    d[c] = max_diff(h) / max_abs(h.beam);
  }
  const double o1 = std::log2(d[0] / d[1]), o2 = std::log2(d[1] / d[2]);
  std::cout << "  relative differences " << d[0] << ", " << d[1] << ", " << d[2] << ": orders " << o1 << ", " << o2
            << "\n";
  EXPECT_NEAR(o1, 2.0, 0.3);
  EXPECT_NEAR(o2, 2.0, 0.3);
}

TEST(CableVsBeam, TheSceneLoadOfTwoNewtonsStaysCloseToTheBeam) {
  // The scene's F = 2 N with full gravity: deflections reach ~0.15 L, so the rod departs
  // from the linear beam (reported in docs/rod.md). The terms the linear beam drops are of
  // first order in the slopes, themselves of the order of the deflection ratio max |w| / L:
  // the relative difference stays below that ratio, and far above the small-load
  // difference of the same discretisation (F = 0.02 N, g = 0.098: the rod's ds^2 error).
  const Histories h = run(2.0, 9.8, 0.5, 100, 20), small = run(0.02, 0.098, 0.5, 100, 20);
  const double rel = max_diff(h) / max_abs(h.beam), floor = max_diff(small) / max_abs(small.beam);
  const double ratio = max_abs(h.beam) / 1.0;  // L = 1 m
  std::cout << "  F = 2 N, alpha = 0.5: max |y_rod - w_beam| / max |w_beam| = " << rel << " (max |w| = "
            << max_abs(h.beam) << " m, max |y| = " << max_abs(h.rod) << " m); deflection ratio " << ratio
            << ", small-load difference " << floor << "\n";
  EXPECT_LT(rel, ratio);
  EXPECT_GT(rel, 10.0 * floor);
}

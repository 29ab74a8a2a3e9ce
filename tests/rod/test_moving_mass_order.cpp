// Order of the rod's moving mass (inertia included) against the beam module's moving mass in
// the small-deflection limit. Scene: the hanging-cable rod (L = 1 m, r = 5 mm,
// E = 2.5e8 Pa, rho = 1500 kg/m^3), clamped at s = 0, clamped and sliding along k at s = L,
// gravity 0.0098 m/s^2 (deflections ~7e-5 m: geometric nonlinearity ~1e-8 relative), a mass
// of half the rod's mass (0.0589 kg) moving at v1 / 2 = 3.634 m/s from s = 0 to s = L,
// static initial state, box scheme. Beam: clamped-clamped, Galerkin modes, Newmark, static
// initial state. Compared: the midspan deflection minus its initial value; the largest
// difference over the crossing relative to the beam's peak.
//
// The rod's rotary inertia is switched off (rhoI = 0) since the Euler-Bernoulli beam has
// none: with it the rod's first frequency is 4e-5 lower and the difference levels off near
// 1e-4 of the peak (docs/rod.md). The beam needs 80 modes here: with 20 modes its own error
// is 7.8e-4 of the peak at the end of the crossing (80 modes: 3e-6, against 160 modes).
#include <gtest/gtest.h>

#include "hanging_cable.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "traverse/beam/beam_simulation.hpp"
#include "reference_stepper.hpp"
#include "traverse/rod/static_load_steps.hpp"

using namespace traverse;

namespace {

struct Scene {
  rod::RodProperties props = rod::RodProperties::scene_rod();
  double L = 1.0;
  double g = 0.0098;
  Scene() { props.rhoI = Vec3::Zero(); }
  double mass() const { return 0.5 * props.rhoA * L; }  // half the rod's mass, 0.0589 kg
  double speed() const {  // v1 / 2, v1 = (4.73 / L)^2 sqrt(EI / rhoA) L / pi
    return 0.5 * std::pow(4.7300 / L, 2) * std::sqrt(props.K(0) / props.rhoA) * L / M_PI;
  }
  double crossing_time() const { return L / speed(); }
};

/// Midspan deflection minus its initial value at t_k = k dt, k = 0..steps (moving mass with
/// inertia, or its weight only as a moving force).
std::vector<double> rod_history(const Scene& sc, int cells, double dt, int steps, bool inertia = true) {
  const double v = sc.speed(), M = sc.mass();
  bool converged = false;  // the mass's weight at s = 0 in the static start
  rod::RodState state =
      traverse::testing::static_start(traverse::testing::hanging_cable_statics(sc.props, cells, sc.L, sc.g, M * sc.g, 0.0), converged);
  EXPECT_TRUE(converged);
  rod::RodModel m = traverse::testing::hanging_cable_model(sc.props, cells, sc.L, sc.g);
  m.loads.masses.push_back(traverse::testing::uniform_mass(M, v, inertia));
  rod::ReferenceStepper stepper(m);
  const size_t mid = static_cast<size_t>(cells / 2);
  const double y0 = rod::centreline_in_space(state)[mid].y();
  std::vector<double> h{0.0};
  for (int i = 1; i <= steps; ++i) {
    const rod::ReferenceStepReport r = stepper.step(state, dt);
    EXPECT_TRUE(r.converged) << "rod step " << i;
    if (!r.converged) break;
    h.push_back(rod::centreline_in_space(state)[mid].y() - y0);
  }
  return h;
}

/// The beam's midspan deflection minus its initial value at t = k dt_out, k = 0..count-1,
/// stepping at dt_out / sub.
std::vector<double> beam_history(const Scene& sc, double dt_out, int count, int sub, int modes = 80,
                                 bool inertia = true) {
  beam::BeamProblem p;
  p.length = sc.L;
  p.EI = sc.props.K(0);
  p.rhoA = sc.props.rhoA;
  p.support = beam::Support::ClampedClamped;
  p.n_modes = modes;
  p.gravity = sc.g;
  beam::MovingLoad load;
  load.kind = inertia ? beam::LoadKind::Mass : beam::LoadKind::Force;
  load.mass = sc.mass();
  load.speed = sc.speed();
  p.loads.push_back(load);
  p.t_end = dt_out * (count - 1);
  p.dt = dt_out / sub;
  p.output_every = sub;
  p.integrator = beam::Integrator::Newmark;
  std::vector<double> h;
  beam::BeamSimulation sim(p);
  sim.run([&](const beam::BeamSnapshot& s) { h.push_back(s.deflection(0.5 * sc.L)); });
  const double w0 = h.front();
  for (double& w : h) w -= w0;
  h.resize(static_cast<size_t>(count));
  return h;
}

/// Beam steps per output step so that the beam steps at about 2e-5 s.
int beam_substeps(double dt_out) { return std::max(1, static_cast<int>(std::lround(dt_out / 2e-5))); }

double min_of(const std::vector<double>& a) {
  double m = 0.0;
  for (double x : a) m = std::min(m, x);
  return m;
}
double max_abs(const std::vector<double>& a) {
  double m = 0.0;
  for (double x : a) m = std::max(m, std::abs(x));
  return m;
}
/// max |a_i - b_{i stride}| over i = 0..last (default: all common samples).
double max_diff(const std::vector<double>& a, const std::vector<double>& b, int stride = 1, size_t last = SIZE_MAX) {
  double m = 0.0;
  for (size_t i = 0; i < a.size() && i <= last && i * static_cast<size_t>(stride) < b.size(); ++i)
    m = std::max(m, std::abs(a[i] - b[i * static_cast<size_t>(stride)]));
  return m;
}

/// One rod run at dt = f ds / v against the beam: the differences over the whole crossing and
/// over its first 90 % (the mass at least 0.1 L from the far clamp).
struct Comparison {
  double rod_min = 0.0, full = 0.0, bulk = 0.0;  // m; relative to the beam's peak
  std::vector<double> rod;
};

Comparison compare(const Scene& sc, int cells, double f, const std::vector<double>& beam, int beam_stride) {
  const double dt = f * sc.L / cells / sc.speed(), T = sc.crossing_time();
  const int steps = static_cast<int>(std::floor(T / dt * (1.0 + 1e-12)));
  Comparison c;
  c.rod = rod_history(sc, cells, dt, steps);
  const double peak = max_abs(beam);
  c.rod_min = min_of(c.rod);
  c.full = max_diff(c.rod, beam, beam_stride) / peak;
  c.bulk = max_diff(c.rod, beam, beam_stride, static_cast<size_t>(std::floor(0.9 * T / dt))) / peak;
  return c;
}

/// The order test of the issue at dt = f ds / v, ds = 0.01, 0.005, 0.0025; returns the
/// comparisons. The beam is sampled at the finest rod step (the coarser ones are multiples).
std::vector<Comparison> ds_series(const Scene& sc, double f, double& beam_min) {
  const int cells[3] = {100, 200, 400};
  const double dt_fine = f * sc.L / cells[2] / sc.speed();
  const int count = static_cast<int>(std::floor(sc.crossing_time() / dt_fine * (1.0 + 1e-12))) + 1;
  const auto beam = beam_history(sc, dt_fine, count, beam_substeps(dt_fine));
  beam_min = min_of(beam);
  std::vector<Comparison> out;
  for (int k = 0; k < 3; ++k) out.push_back(compare(sc, cells[k], f, beam, 4 >> k));
  std::printf("dt = %.2g ds / v, beam (80 modes, Newmark at %.3g s) min %.5e m:\n", f, dt_fine / beam_substeps(dt_fine),
              beam_min);
  std::printf("  ds      rod min (m)   diff, crossing  order   diff, first 90 %%  order\n");
  for (int k = 0; k < 3; ++k) {
    std::printf("  %-6.4f  %.5e   %.4f %%", 1.0 / cells[k], out[k].rod_min, 100.0 * out[k].full);
    if (k > 0) std::printf("        %.2f", std::log2(out[k - 1].full / out[k].full));
    else std::printf("            ");
    std::printf("    %.4f %%", 100.0 * out[k].bulk);
    if (k > 0) std::printf("         %.2f", std::log2(out[k - 1].bulk / out[k].bulk));
    std::printf("\n");
  }
  return out;
}

}  // namespace

TEST(MovingMassOrder, SecondOrderInDsWithTheMassOnTheNodes) {
  // dt = ds / v (the reference choice): the mass sits on a node at every level
  // (docs/validation.md, the moving-mass table).
  const Scene sc;
  double beam_min = 0.0;
  const auto c = ds_series(sc, 1.0, beam_min);
  const double o_bulk[2] = {std::log2(c[0].bulk / c[1].bulk), std::log2(c[1].bulk / c[2].bulk)};
  const double o_full = std::log2(c[1].full / c[2].full);
  // Over the whole crossing the largest difference comes in the last steps, where the mass
  // runs into the clamped end: there the trapezoidal rule's error at this step dominates, for
  // the rod as for the beam module itself integrated with Newmark at the same dt (its error
  // against the fine-step beam is printed; both converge at order 2 only below ds ~ 0.0025).
  const double dt = sc.L / 400 / sc.speed();
  const int count = static_cast<int>(std::floor(sc.crossing_time() / dt * (1.0 + 1e-12))) + 1;
  const auto beam_fine = beam_history(sc, dt, count, beam_substeps(dt));
  const auto beam_coarse = beam_history(sc, dt, count, 1);
  const double beam_own = max_diff(beam_coarse, beam_fine) / max_abs(beam_fine);
  std::printf("finest ds = 0.0025: rod - beam %.4f %% over the crossing, %.4f %% over its first 90 %%; the beam "
              "module's own Newmark at dt = ds / v against its fine step: %.4f %%\n",
              100.0 * c[2].full, 100.0 * c[2].bulk, 100.0 * beam_own);
  EXPECT_NEAR(o_bulk[0], 2.0, 0.2);
  EXPECT_NEAR(o_bulk[1], 2.0, 0.2);
  EXPECT_GT(o_full, 1.6);
  EXPECT_LT(c[2].bulk, 2e-4);
  EXPECT_LT(c[2].full, 1.3 * beam_own);
  EXPECT_NEAR(c[2].rod_min / beam_min, 1.0, 2e-4);
}

TEST(MovingMassOrder, SecondOrderInDsWithTheMassBetweenNodes) {
  // dt = 0.7 ds / v: the mass is between nodes at the levels and crosses nodes within steps.
  const Scene sc;
  double beam_min = 0.0;
  const auto c = ds_series(sc, 0.7, beam_min);
  const double o_full[2] = {std::log2(c[0].full / c[1].full), std::log2(c[1].full / c[2].full)};
  const double o_bulk = std::log2(c[1].bulk / c[2].bulk);
  std::printf("finest ds = 0.0025: rod - beam %.4f %% over the crossing (orders %.2f, %.2f)\n", 100.0 * c[2].full,
              o_full[0], o_full[1]);
  EXPECT_NEAR(o_full[1], 2.0, 0.2);
  EXPECT_NEAR(o_bulk, 2.0, 0.2);
  EXPECT_LT(c[2].full, 5e-4);
}

TEST(MovingMassOrder, RefiningDtAloneAtFixedDs) {
  // ds = 0.01, dt = ds / v, ds / (2 v), ds / (4 v), ds / (8 v): the rod converges to its
  // semi-discrete solution, whose difference to the beam is the spatial error at this ds.
  // Before the fix dt = ds / v was 11x further from the beam than dt = ds / (4 v).
  const Scene sc;
  const int cells = 100, divs[4] = {1, 2, 4, 8};
  const double dt_fine = sc.L / cells / (sc.speed() * divs[3]);
  const int count = cells * divs[3] + 1;
  const auto beam = beam_history(sc, dt_fine, count, beam_substeps(dt_fine));
  const double peak = max_abs(beam);
  std::vector<std::vector<double>> h;
  double to_beam[4], self_full[3], self_bulk[3];
  std::printf("ds = 0.01:\n  dt          rod - beam   |y(dt) - y(dt/2)|  order   (first 90 %%)  order\n");
  for (int k = 0; k < 4; ++k) {
    const int steps = cells * divs[k];
    h.push_back(rod_history(sc, cells, sc.L / cells / (sc.speed() * divs[k]), steps));
    to_beam[k] = max_diff(h[k], beam, divs[3] / divs[k]) / peak;
    if (k > 0) {
      self_full[k - 1] = max_diff(h[k - 1], h[k], 2) / peak;
      self_bulk[k - 1] = max_diff(h[k - 1], h[k], 2, static_cast<size_t>(0.9 * cells * divs[k - 1])) / peak;
    }
  }
  for (int k = 0; k < 4; ++k) {
    std::printf("  ds/(%d v)    %.4f %%", divs[k], 100.0 * to_beam[k]);
    if (k < 3) std::printf("     %.4f %%", 100.0 * self_full[k]);
    if (k > 0 && k < 3) std::printf("       %.2f", std::log2(self_full[k - 1] / self_full[k]));
    else if (k < 3) std::printf("           ");
    if (k < 3) std::printf("     %.4f %%", 100.0 * self_bulk[k]);
    if (k > 0 && k < 3) std::printf("     %.2f", std::log2(self_bulk[k - 1] / self_bulk[k]));
    std::printf("\n");
  }
  EXPECT_LT(self_full[1], 0.5 * self_full[0]);
  EXPECT_LT(self_full[2], 0.5 * self_full[1]);
  // Over the first 90 % the largest self-difference of the last pair sits at 0.885 of the
  // crossing, where a ~125 Hz oscillation of the midspan builds up as the mass nears the far
  // clamp: orders 1.74, 1.89 with the one-box impulse of the first fix, 1.96, 1.60 with the
  // line mass (over the first 85 %: 1.86, 1.81 and 1.96, 1.88). Asserted: above 1.5.
  EXPECT_GT(std::log2(self_bulk[0] / self_bulk[1]), 1.5);
  EXPECT_GT(std::log2(self_bulk[1] / self_bulk[2]), 1.5);
  EXPECT_LT(to_beam[0], 2.0 * to_beam[3]);  // dt = ds / v is not singled out
  EXPECT_LT(std::abs(to_beam[3] - to_beam[2]), 0.15 * to_beam[3]);
}

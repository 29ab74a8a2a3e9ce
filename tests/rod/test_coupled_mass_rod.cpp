// The rod's coupled mass on the serial reference stepper (docs/rod.md "Coupled mass"):
// prescribed-motion limit, order in dt, energy drift, rigid-wire limit.
#include <gtest/gtest.h>

#include "reference_stepper.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "traverse/rod/coupled_mass_rod.hpp"
#include "reference_statics.hpp"
#include "traverse/rod/static_load_steps.hpp"

using namespace traverse;

namespace {

constexpr double kG = 9.8;

struct RodSetup {
  rod::RodModel model;
  rod::RodState state;
};

/// The default cable's rod (clamped at s = 0, sliding along k at s = L, L = 1 m) with E scaled
/// by `stiffen`, in static equilibrium under gravity and the mass's weight at sigma0.
RodSetup cable(int cells, double stiffen, double M, double sigma0) {
  rod::StaticModel sm;
  sm.props = rod::RodProperties::scene_rod();
  sm.props.K *= stiffen;
  sm.num_cells = cells;
  sm.length = 1.0;
  sm.left.type = rod::EndCondition::Type::clamped;
  sm.right.type = rod::EndCondition::Type::sliding;
  sm.right.axis = Vec3::UnitZ();
  sm.right.position = Vec3(0, 0, 1.0);
  sm.gravity = Vec3(0, -kG, 0);
  sm.point_forces.push_back({Vec3(0, -M * kG, 0), sigma0});
  auto nodes = rod::straight_static_state(sm);
  EXPECT_TRUE(rod::serial_load_steps(sm, nodes).converged);
  RodSetup s;
  s.model.props = sm.props;
  s.model.num_cells = cells;
  s.model.length = 1.0;
  s.model.left = rod::EndCondition::make_clamped();
  s.model.right = rod::EndCondition::make_sliding(Vec3::UnitZ());
  s.model.loads.gravity = sm.gravity;
  s.state = rod::dynamic_state_from_static(sm, nodes);
  return s;
}

struct Trace {
  std::vector<double> t, sigma, speed, energy, mid_y;
  bool converged = true;
  bool stuck = false;  ///< a step reported a stop where the friction holds the mass
  int max_coupling = 0;
};

/// Steps rod + mass by dt to t_end (or until sigma leaves [0.02, 0.98] L), recording every
/// `every` steps; the energies from the centreline advanced in time.
Trace advance(RodSetup s, const rod::CoupledRodMass& mass, rod::CoupledMassState m, double dt, double t_end, int every = 1) {
  rod::CoupledRodStepper stepper(s.model, mass, rod::reference_rod_solve);
  std::vector<Vec3> r = rod::centreline_in_space(s.state);
  Trace tr;
  auto record = [&]() {
    const auto e = rod::coupled_energies(stepper.model(), s.state, r, m, stepper.coupled_mass());
    tr.t.push_back(s.state.t);
    tr.sigma.push_back(m.sigma);
    tr.speed.push_back(m.speed);
    tr.energy.push_back(e.balance());
    tr.mid_y.push_back(r[r.size() / 2].y());
  };
  record();
  const long steps = std::lround(t_end / dt);
  for (long k = 1; k <= steps; ++k) {
    const rod::RodState old = s.state;
    const auto rep = stepper.step(s.state, m, dt);
    if (!rep.converged) {
      tr.converged = false;
      break;
    }
    tr.max_coupling = std::max(tr.max_coupling, rep.coupling_iterations);
    tr.stuck = tr.stuck || m.sticks();
    r = rod::advance_centreline_in_time(r, old, s.state);
    if (k % every == 0) record();
    if (m.sigma < 0.02 || m.sigma > 0.98) break;
  }
  return tr;
}

double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0.0;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

}  // namespace

// A driven mass on a stiff horizontal cable: sigma(t) = sigma0 + v0 t + D t^2 / (2M); the
// deviation is the cable's sag and falls like 1/E.
TEST(CoupledMassRod, PrescribedMotionLimit) {
  const double M = 0.05, s0 = 0.2, v0 = 1.0, D = 0.5, dt = 0.005, T = 0.25;
  std::vector<double> dev;
  for (double stiffen : {1e2, 1e3, 1e4}) {
    RodSetup s = cable(20, stiffen, M, s0);
    const Trace tr = advance(s, {M, D, 0.0}, {s0, v0}, dt, T);
    ASSERT_TRUE(tr.converged);
    double d = 0.0;
    for (size_t i = 0; i < tr.t.size(); ++i)
      d = std::max(d, std::abs(tr.sigma[i] - (s0 + v0 * tr.t[i] + D * tr.t[i] * tr.t[i] / (2 * M))));
    std::printf("E x %.0e: max |sigma - (s0 + v0 t + D t^2/2M)| = %.4e m, sigma(T) = %.6f, coupling iterations <= %d\n",
                stiffen, d, tr.sigma.back(), tr.max_coupling);
    dev.push_back(d);
  }
  for (size_t i = 1; i < dev.size(); ++i) {
    std::printf("deviation ratio per E x 10: %.3f\n", dev[i - 1] / dev[i]);
    EXPECT_NEAR(dev[i - 1] / dev[i], 10.0, 2.5);
  }
  EXPECT_LT(dev.back(), 1e-5);
}

// The soft cable (sag ~2.5 % of L) with a 0.05 kg mass launched at 2 m/s from 0.1 m, to 0.3 s.
// At fixed ds (20 cells) the time discretisation error (self-differences at halved dt, max over
// common times of sigma and of the midspan's height) falls at second order once dt is below
// ds / (2 v) (at ds / v the mass sits on nodes at every level, at smaller steps between them:
// the first pairs mix the line mass's spatial error in).
TEST(CoupledMassRod, OrderInDt) {
  const double M = 0.05, s0 = 0.1, v0 = 2.0, T = 0.3;
  const int cells = 20;
  const double dt0 = (1.0 / cells) / v0;  // ds / v
  std::vector<Trace> tr;
  int every = 1;
  for (int k = 0; k < 6; ++k) {
    RodSetup s = cable(cells, 1.0, M, s0);
    tr.push_back(advance(s, {M, 0.0, 0.0}, {s0, v0}, dt0 / every, T, every));
    ASSERT_TRUE(tr.back().converged);
    every *= 2;
  }
  std::vector<double> es, ey;
  for (size_t k = 1; k < tr.size(); ++k) {
    es.push_back(max_abs_diff(tr[k].sigma, tr[k - 1].sigma));
    ey.push_back(max_abs_diff(tr[k].mid_y, tr[k - 1].mid_y));
  }
  for (size_t k = 0; k < tr.size(); ++k)
    std::printf("dt = ds/v / %2d: sigma(T) = %.9f m, coupling iterations <= %d\n", 1 << k, tr[k].sigma.back(),
                tr[k].max_coupling);
  for (size_t k = 0; k < es.size(); ++k)
    std::printf("pair %zu: max |d sigma| = %.4e m, max |d y_mid| = %.4e m\n", k, es[k], ey[k]);
  for (size_t k = 1; k < es.size(); ++k) {
    const double os = std::log2(es[k - 1] / es[k]), oy = std::log2(ey[k - 1] / ey[k]);
    std::printf("orders: sigma %.3f, midspan %.3f\n", os, oy);
    if (k >= 2) {
      EXPECT_GT(os, 1.6);
    }
    if (k == es.size() - 1) {
      EXPECT_GT(oy, 1.6);  // the midspan carries the start's undamped high modes
    }
  }
}

// Energy of rod + mass (frictionless, no drive, no resistance, rho_inf = 1): its largest change
// over the run for ds and dt = ds / v refined together; it falls with the discretisation (the
// line mass's energy is that of a point mass only to O(ds^2)).
TEST(CoupledMassRod, EnergyDrift) {
  const double M = 0.05, s0 = 0.1, v0 = 2.0, T = 0.3, E_kin = 0.5 * M * v0 * v0;
  std::vector<double> drift;
  for (int cells : {20, 40, 80}) {
    RodSetup s = cable(cells, 1.0, M, s0);
    const Trace tr = advance(s, {M, 0.0, 0.0}, {s0, v0}, (1.0 / cells) / v0, T);
    ASSERT_TRUE(tr.converged);
    double d = 0.0;
    for (double e : tr.energy) d = std::max(d, std::abs(e - tr.energy.front()));
    drift.push_back(d);
    std::printf("%d cells, dt = ds/v: max |E - E0| = %.4e J (%.3e of M v0^2/2), sigma(T) = %.6f\n", cells, d, d / E_kin,
                tr.sigma.back());
  }
  for (size_t k = 1; k < drift.size(); ++k) std::printf("order %.3f\n", std::log2(drift[k - 1] / drift[k]));
  EXPECT_GT(std::log2(drift[0] / drift[1]), 1.2);
  EXPECT_GT(std::log2(drift[1] / drift[2]), 1.6);
  EXPECT_LT(drift.back(), 1e-3 * E_kin);
}

// Rigid-wire limit: a cantilever formed as a circular arc (intrinsic curvature 1/m, clamped
// horizontally at s = 0, curving down; E raised 1e4 times), in static equilibrium under
// gravity and the mass's weight. A mass released at rest near the crest (s = 0.05 m) slides down
// like a bead on a rigid wire of the static shape: sigma'' = g . d3(sigma) = -g sin phi(sigma),
// phi the static state's tangent angle below the horizontal (interpolated linearly between the
// nodes), integrated here by RK4 at a small step. sigma(t) within 0.1 % of the ODE's travel.
/// A cantilever formed as a circular arc (intrinsic curvature 1/m, clamped horizontally at
/// s = 0, curving down; E raised 1e4 times) in static equilibrium under gravity and the mass's
/// weight at s0.
RodSetup rigid_arc(int cells, double M, double s0) {
  const double L = 1.0;
  rod::StaticModel sm;
  sm.props = rod::RodProperties::scene_rod();
  sm.props.K *= 1e4;
  sm.props.kappa0 = Vec3(1.0, 0.0, 0.0);
  sm.num_cells = cells;
  sm.length = L;
  sm.left.type = rod::EndCondition::Type::clamped;
  sm.right.type = rod::EndCondition::Type::free;
  sm.gravity = Vec3(0, -kG, 0);
  sm.point_forces.push_back({Vec3(0, -M * kG, 0), s0});
  const rod::RodState rest = rod::state_from_curvature(cells, L, [&](double) { return sm.props.kappa0; });
  const std::vector<Vec3> r_rest = rod::centreline_in_space(rest);
  std::vector<rod::StaticNode> nodes(static_cast<size_t>(cells + 1));
  for (int j = 0; j <= cells; ++j) {
    auto& nd = nodes[static_cast<size_t>(j)];
    nd.Rbar = rest.nodes[static_cast<size_t>(j)].R;
    nd.x.segment<3>(rod::svar::r) = r_rest[static_cast<size_t>(j)];
    nd.x.segment<3>(rod::svar::kappa) = sm.props.kappa0;
  }
  EXPECT_LT(r_rest.back().y(), -0.3) << "the arc must curve down from the clamp";
  EXPECT_TRUE(rod::serial_load_steps(sm, nodes).converged);
  RodSetup s;
  s.model.props = sm.props;
  s.model.num_cells = cells;
  s.model.length = L;
  s.model.left = rod::EndCondition::make_clamped();
  s.model.right = rod::EndCondition::make_free();
  s.model.loads.gravity = sm.gravity;
  s.state = rod::dynamic_state_from_static(sm, nodes);
  return s;
}

/// The static shape's tangent angle phi at sigma (interpolated linearly between the nodes).
std::function<double(double)> tangent_angle(const rod::RodState& state, double L, int cells) {
  std::vector<double> phi;
  for (const auto& nd : state.nodes) {
    const Vec3 d3 = nd.R.row(2).transpose();
    phi.push_back(std::atan2(-d3.y(), d3.z()));
  }
  return [phi, L, cells](double sigma) {
    const rod::NodeInterpolation at = rod::locate_on_nodes(sigma, L / cells, cells);
    return (1.0 - at.xi) * phi[static_cast<size_t>(at.j)] + at.xi * phi[static_cast<size_t>(at.j + 1)];
  };
}

/// max |sigma_rod - sigma_ODE| over the trace's times for sigma'' = accel(sigma, sigma') from
/// (s0, v0), by RK4 at a twentieth of the trace's steps; `travel` the ODE's largest |sigma - s0|.
double ode_error(const Trace& tr, double s0, double v0, const std::function<double(double, double)>& accel,
                 double& travel) {
  double sg = s0, v = v0, err = 0.0;
  travel = 0.0;
  const int sub = 20;
  for (size_t i = 1; i < tr.t.size(); ++i) {
    const double h = (tr.t[i] - tr.t[i - 1]) / sub;
    for (int k = 0; k < sub; ++k) {
      const double k1v = accel(sg, v), k1s = v;
      const double k2v = accel(sg + 0.5 * h * k1s, v + 0.5 * h * k1v), k2s = v + 0.5 * h * k1v;
      const double k3v = accel(sg + 0.5 * h * k2s, v + 0.5 * h * k2v), k3s = v + 0.5 * h * k2v;
      const double k4v = accel(sg + h * k3s, v + h * k3v), k4s = v + h * k3v;
      sg += h / 6 * (k1s + 2 * k2s + 2 * k3s + k4s);
      v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
    err = std::max(err, std::abs(tr.sigma[i] - sg));
    travel = std::max(travel, std::abs(sg - s0));
  }
  return err;
}

TEST(CoupledMassRod, RigidWireLimit) {
  const int cells = 40;
  const double L = 1.0, M = 0.05, s0 = 0.05, dt = 1e-3;
  RodSetup s = rigid_arc(cells, M, s0);
  const auto phi = tangent_angle(s.state, L, cells);
  const double T = 0.9;
  const Trace tr = advance(s, {M, 0.0, 0.0}, {s0, 0.0}, dt, T);
  ASSERT_TRUE(tr.converged);
  double travel = 0.0;
  const double err = ode_error(tr, s0, 0.0, [&](double sg, double) { return kG * std::sin(phi(sg)); }, travel);
  std::printf("rigid wire: to t = %.4f s the bead travels %.6f m (ODE), rod sigma(T) = %.6f m; max |sigma_rod - "
              "sigma_ODE| = %.4e m = %.4f %% of the travel; coupling iterations <= %d\n",
              tr.t.back(), travel, tr.sigma.back(), err, 100.0 * err / travel, tr.max_coupling);
  EXPECT_GT(travel, 0.3);
  EXPECT_LT(err / travel, 1e-3);
}

// Friction that cannot hold the mass where it stops (mu = 0.1 below the slope's tangent): on
// RigidWireLimit's arc, launched uphill (towards s = 0) from s0 = 0.5 m at 1.2 m/s, the mass
// decelerates, stops near s = 0.37 m, reverses and slides back down. Against the rigid-wire ODE
// sigma'' = g sin phi - mu |g cos phi - kappa0 sigma'^2| sign(sigma') (RK4 at dt / 20) to 0.6 s:
// sigma within 0.1 % of the travel; the rod's step never reports a stick.
TEST(CoupledMassRod, FrictionReversesOnAnInclinedWire) {
  const int cells = 40;
  const double L = 1.0, M = 0.05, s0 = 0.5, v0 = -1.2, mu = 0.1, dt = 1e-3, T = 0.6;
  RodSetup s = rigid_arc(cells, M, s0);
  const auto phi = tangent_angle(s.state, L, cells);
  const Trace tr = advance(s, {M, 0.0, 0.0, mu}, {s0, v0}, dt, T);
  ASSERT_TRUE(tr.converged);
  auto accel = [&](double sg, double v) {
    const double p = phi(sg), sgn = v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0);
    return kG * std::sin(p) - mu * std::abs(kG * std::cos(p) - v * v) * sgn;
  };
  double travel = 0.0;
  const double err = ode_error(tr, s0, v0, accel, travel);
  const double lowest = *std::min_element(tr.sigma.begin(), tr.sigma.end());
  std::printf("reversal: lowest sigma %.6f m, sigma(T) = %.6f m, speed(T) = %.5f m/s; max |sigma_rod - sigma_ODE| = "
              "%.4e m = %.4f %% of the travel %.4f m; sticks: %d\n", lowest, tr.sigma.back(), tr.speed.back(), err,
              100.0 * err / travel, travel, tr.stuck ? 1 : 0);
  EXPECT_LT(lowest, 0.4);
  EXPECT_GT(tr.speed.back(), 0.3);
  EXPECT_FALSE(tr.stuck);
  EXPECT_LT(err / travel, 1e-3);
}

/// max |balance - balance0| over the steps to T of the soft cable with `cells` cells, 0.05 kg
/// launched at v0 = 2 m/s from 0.1 m, dt = ds / v0; `end` the mass's state at T.
double balance_error(int cells, const rod::CoupledRodMass& mass, double T, rod::CoupledMassState& end) {
  const double s0 = 0.1, v0 = 2.0;
  RodSetup s = cable(cells, 1.0, mass.mass, s0);
  rod::CoupledRodStepper stepper(s.model, mass, rod::reference_rod_solve);
  rod::CoupledMassState m{s0, v0};
  std::vector<Vec3> r = rod::centreline_in_space(s.state);
  const double dt = (1.0 / cells) / v0;
  auto balance = [&]() { return rod::coupled_energies(stepper.model(), s.state, r, m, stepper.coupled_mass()).balance(); };
  const double b0 = balance();
  double err = 0.0;
  for (long k = 1; k <= std::lround(T / dt); ++k) {
    const rod::RodState old = s.state;
    if (!stepper.step(s.state, m, dt).converged) return std::nan("");
    r = rod::advance_centreline_in_time(r, old, s.state);
    err = std::max(err, std::abs(balance() - b0));
  }
  end = m;
  return err;
}

// With a drive and a viscous resistance the balance E - E0 - W_drive + W_loss closes as the
// discretisation is refined (40 and 80 cells, dt = ds / v0), at the level of the frictionless
// drift (EnergyDrift), while W_loss itself is much larger.
TEST(CoupledMassRod, EnergyBalanceWithDriveAndResistance) {
  std::vector<double> errs;
  for (int cells : {40, 80}) {
    rod::CoupledMassState m;
    const double err = balance_error(cells, {0.05, 0.2, 0.05}, 0.25, m);
    std::printf("%d cells: drive 0.2 N, resistance 0.05 N s/m: W_drive = %.5f J, W_loss = %.5f J, max |balance - "
                "balance0| = %.4e J, sigma(T) = %.5f m\n", cells, m.drive_work, m.dissipated, err, m.sigma);
    EXPECT_GT(m.dissipated, 0.05);
    EXPECT_LT(err, 0.01 * m.dissipated);
    errs.push_back(err);
  }
  std::printf("order %.3f\n", std::log2(errs[0] / errs[1]));
  EXPECT_GT(std::log2(errs[0] / errs[1]), 1.2);
}

// The resistance as a force pair with the rod (resistance_through: structure, wheels or a
// motor): the rod takes +c sigma' d3, its load is M (g - p''), and the loss c sigma'^2 is the
// whole of what the pair dissipates. On the sagging cable the rod's material moves along its
// tangent, so this loss differs from the air resistance's c sigma' d3 . p' (the same scene as
// EnergyBalanceWithDriveAndResistance); the balance closes with it as the discretisation is refined.
TEST(CoupledMassRod, EnergyBalanceWithResistanceThroughTheRod) {
  std::vector<double> errs, differences;
  for (int cells : {40, 80}) {
    rod::CoupledMassState m, m_air;
    rod::CoupledRodMass mass{0.05, 0.2, 0.05};
    mass.resistance_through_rod = true;
    const double err = balance_error(cells, mass, 0.25, m);
    balance_error(cells, {0.05, 0.2, 0.05}, 0.25, m_air);
    std::printf("%d cells: drive 0.2 N, resistance 0.05 N s/m through the rod: W_drive = %.5f J, W_loss = %.5f J "
                "(through the air %.5f J), max |balance - balance0| = %.4e J, sigma(T) = %.5f m (air %.5f m)\n",
                cells, m.drive_work, m.dissipated, m_air.dissipated, err, m.sigma, m_air.sigma);
    EXPECT_GT(m.dissipated, 0.05);
    EXPECT_LT(err, 0.01 * m.dissipated);
    errs.push_back(err);
    differences.push_back(m.dissipated - m_air.dissipated);
  }
  std::printf("order %.3f; W_loss(rod) - W_loss(air) = %.4e, %.4e J\n", std::log2(errs[0] / errs[1]), differences[0],
              differences[1]);
  EXPECT_GT(std::log2(errs[0] / errs[1]), 1.2);
  // The losses differ by the model (the rod's material velocity along d3), not by the mesh: the
  // same difference at both resolutions, above the balance's error.
  EXPECT_NEAR(differences[0], differences[1], 0.1 * std::abs(differences[1]));
  EXPECT_GT(std::abs(differences[1]), 5.0 * errs[1]);
}

// Coulomb friction mu = 0.1 on the sagging cable (the normal force swings with the cable's motion):
// the balance E - E0 + W_friction closes as the discretisation is refined (40 and 80 cells,
// dt = ds / v0), while W_friction ~ mu M g (travel) is 0.02 J.
TEST(CoupledMassRod, EnergyBalanceWithFriction) {
  std::vector<double> errs;
  for (int cells : {40, 80}) {
    rod::CoupledMassState m;
    const double err = balance_error(cells, {0.05, 0.0, 0.0, 0.1}, 0.25, m);
    std::printf("%d cells: friction 0.1: W_friction = %.5f J (mu M g travel = %.5f J), max |balance - balance0| = "
                "%.4e J, sigma(T) = %.5f m, speed %.4f m/s\n", cells, m.friction_work, 0.1 * 0.05 * kG * (m.sigma - 0.1),
                err, m.sigma, m.speed);
    EXPECT_GT(m.friction_work, 0.015);
    EXPECT_LT(err, 0.02 * m.friction_work);
    errs.push_back(err);
  }
  std::printf("order %.3f\n", std::log2(errs[0] / errs[1]));
  EXPECT_GT(std::log2(errs[0] / errs[1]), 1.2);
}

// A mass launched at v0 along a level rod stiff enough to stay straight (E raised 1e4 times, the
// default cable's ends) decelerates at mu g: it stops at t = v0 / (mu g) after v0^2 / (2 mu g), and
// the friction holds it there (the step reports the stop: the zero of v linear in the step).
// The deviation is the rod's sag (as in PrescribedMotionLimit); the midpoint rule is exact for a
// constant deceleration, so halving dt changes nothing beyond it.
TEST(CoupledMassRod, FrictionStopsAMassOnALevelRod) {
  const double M = 0.05, s0 = 0.2, v0 = 1.0, mu = 0.2;
  const double t_exact = v0 / (mu * kG), d_exact = v0 * v0 / (2 * mu * kG);
  std::vector<double> et;
  for (double dt : {5e-3, 2.5e-3}) {
    RodSetup s = cable(20, 1e4, M, s0);
    rod::CoupledRodStepper stepper(s.model, {M, 0.0, 0.0, mu}, rod::reference_rod_solve);
    rod::CoupledMassState m{s0, v0};
    std::vector<Vec3> r = rod::centreline_in_space(s.state);
    const double b0 = rod::coupled_energies(stepper.model(), s.state, r, m, stepper.coupled_mass()).balance();
    double t_stop = -1.0, d_stop = 0.0, drift = 0.0;
    for (long k = 1; k <= std::lround(2.0 * t_exact / dt) && t_stop < 0.0; ++k) {
      const rod::RodState old = s.state;
      const rod::CoupledMassState m_old = m;
      ASSERT_TRUE(stepper.step(s.state, m, dt).converged);
      r = rod::advance_centreline_in_time(r, old, s.state);
      if (m.sticks()) {
        t_stop = old.t + m.stick_fraction * dt;
        d_stop = m_old.sigma + 0.5 * m_old.speed * m.stick_fraction * dt - s0;
      } else {
        drift = std::max(drift, std::abs(rod::coupled_energies(stepper.model(), s.state, r, m, stepper.coupled_mass()).balance() - b0));
      }
    }
    std::printf("dt = %.4g s: stops at t = %.7f s (v0 / (mu g) = %.7f s, error %.3e s) after %.7f m (v0^2 / (2 mu g) "
                "= %.7f m, error %.3e m); W_friction %.6f J (M v0^2 / 2 = %.6f J), balance drift before the stop "
                "%.3e J\n", dt, t_stop, t_exact, t_stop - t_exact, d_stop, d_exact, d_stop - d_exact, m.friction_work,
                0.5 * M * v0 * v0, drift);
    ASSERT_GT(t_stop, 0.0) << "no stop";
    EXPECT_NEAR(t_stop, t_exact, 1e-4 * t_exact);
    EXPECT_NEAR(d_stop, d_exact, 1e-4 * d_exact);
    EXPECT_LT(drift, 1e-4 * 0.5 * M * v0 * v0);
    et.push_back(t_stop);
  }
  std::printf("stop time at dt minus dt / 2: %.3e s\n", et[0] - et[1]);
  EXPECT_LT(std::abs(et[0] - et[1]), 1e-5 * t_exact);
}

// Lift-off from a rigid convex wire: a mass launched at v0 = 1 m/s from s0 = 0.05 m over the arc
// of radius R = 1 m (RigidWireLimit's wire) keeps contact while g cos(theta) > v^2 / R; with
// v^2 = v0^2 + 2 g R (cos theta0 - cos theta) the normal force vanishes at
// cos theta = (v0^2 / (g R) + 2 cos theta0) / 3 (the classic bead-on-a-sphere answer), sigma =
// R theta = 0.7956 m. The rod's contact force along d2 (step_contact, the mass's momentum balance)
// changes sign there (zero interpolated between the steps' midpoints): within 0.5 %.
TEST(CoupledMassRod, LiftOffFromARigidWire) {
  const int cells = 40;
  const double M = 0.05, s0 = 0.05, v0 = 1.0, dt = 1e-3, R = 1.0;
  RodSetup s = rigid_arc(cells, M, s0);
  const rod::CoupledRodMass mass{M, 0.0, 0.0};
  rod::CoupledRodStepper stepper(s.model, mass, rod::reference_rod_solve);
  rod::CoupledMassState m{s0, v0};
  double up_prev = 0.0, s_prev = s0, lift = -1.0, tang = 0.0, up_first = 0.0;
  for (int k = 1; k <= 800 && lift < 0.0; ++k) {
    const rod::RodState old = s.state;
    const rod::CoupledMassState m_old = m;
    ASSERT_TRUE(stepper.step(s.state, m, dt).converged);
    const auto c = rod::step_contact(old, m_old, s.state, m, mass, s.model, dt);
    const double s_mid = 0.5 * (m_old.sigma + m.sigma);
    if (k == 1) up_first = c.up;
    if (k > 1 && up_prev > 0.0 && c.up <= 0.0) lift = s_prev + (s_mid - s_prev) * up_prev / (up_prev - c.up);
    tang = std::max(tang, std::abs(c.tangential));
    up_prev = c.up;
    s_prev = s_mid;
  }
  const double theta = std::acos((v0 * v0 / (kG * R) + 2.0 * std::cos(s0 / R)) / 3.0);
  std::printf("lift-off: C . d2 = %.5f N after the first step (M g cos(theta0) - M v0^2 / R = %.5f N); zero at "
              "sigma = %.6f m, rigid wire R theta = %.6f m (%.4f %%); max |tangential contact force| %.2e N\n", up_first,
              M * kG * std::cos(s0 / R) - M * v0 * v0 / R, lift, R * theta, 100.0 * (lift - R * theta) / (R * theta), tang);
  ASSERT_GT(lift, 0.0) << "no lift-off found";
  EXPECT_NEAR(lift, R * theta, 5e-3 * R * theta);
  EXPECT_LT(tang, 1e-9);
}

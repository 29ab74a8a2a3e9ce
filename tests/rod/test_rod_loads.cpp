// Point loads, moving masses, the jump of n and the centreline reconstruction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rod_test_util.hpp"
#include "reference_stepper.hpp"

namespace traverse::rod {
namespace {

TEST(RodLoads, SharesGiveExactlyTheTotalForce) {
  // The interior nodes' shares through the scheme's spatial average (1 - beta) w_j +
  // beta w_{j-1}, summed over the cells, plus the end nodes' shares: exactly the load; the
  // shares are the hat functions (linear interpolation), the ends' only in the end cells.
  const int N = 10;
  const double ds = 0.1;
  double worst = 0.0, interpolation = 0.0;
  for (double beta : {0.5, 0.3889, 0.1667, 0.7}) {
    for (double sigma : {0.0, 1e-17, 0.05, 0.1, 0.2999999999, 0.3, 0.55, 0.9, 0.95, 1.0 - 1e-16, 1.0}) {
      const PointLoadWeights w = point_load_weights(sigma, N, ds);
      ASSERT_TRUE(w.on_rod);
      double total = w.left + w.right, first = 0.0;
      for (int j = 1; j <= N; ++j) total += (1.0 - beta) * w.at(j) + beta * w.at(j - 1);
      for (int j = 0; j <= N; ++j) {
        const double share = w.share(j);
        first += share * j * ds;  // the shares' centroid is sigma
        interpolation = std::max(interpolation, std::abs(share - std::max(0.0, 1.0 - std::abs(sigma / ds - j))));
      }
      worst = std::max({worst, std::abs(total - 1.0), std::abs(first - sigma)});
    }
  }
  std::printf("max |sum of weighted contributions - 1|, |centroid - sigma|: %.2e; shares vs hats %.2e\n", worst,
              interpolation);
  EXPECT_LT(worst, 1e-14);
  EXPECT_LT(interpolation, 1e-14);
  EXPECT_NEAR(point_load_weights(0.07, N, ds).left, 0.3, 1e-15);
  EXPECT_EQ(point_load_weights(0.07, N, ds).at(0), 0.0);  // an end node takes no load density
  EXPECT_FALSE(point_load_weights(-0.01, N, ds).on_rod);
  EXPECT_FALSE(point_load_weights(1.01, N, ds).on_rod);
}

/// Sum over all cells of ds * (point-load part of the momentum rows) at R = I.
Vec3 summed_load_rows(const RodModel& m, const StepTimes& st) {
  const RodState s = straight_rest_state(m.num_cells, m.length);
  Vec3 total = Vec3::Zero();
  const VecX x = node_unknowns(m, s.nodes[0]);
  for (int j = 1; j <= m.num_cells; ++j)
    total += m.ds() * load_block(m, st, j, s.nodes[j - 1], s.nodes[j], x, x).residual.head<3>();
  return total;
}

TEST(RodLoads, ResidualCarriesExactlyTheAppliedForceAtEveryStep) {
  const StepTimes st{0.3, 0.01};
  double worst = 0.0;
  for (const AlphaParameters& a :
       {AlphaParameters{}, AlphaParameters::from_rho_inf(0.6), AlphaParameters::from_rho_inf(0.8, 0.7)}) {
    RodModel m = test::scene_model(10, a);
    // (sigma_old, sigma_new): on nodes, between nodes, at both ends, crossing nodes.
    const std::vector<std::pair<double, double>> paths = {
        {0.3, 0.4}, {0.33, 0.47}, {0.0, 0.06}, {0.96, 1.0}, {0.0, 0.0}, {1.0, 1.0}, {0.12, 0.88}};
    for (const auto& [s0, s1] : paths) {
      PointForce P;
      P.force_fixed = [](double t) { return Vec3(0.1, -2.0 - 10.0 * t, 0.3); };
      P.sigma = [=, t0 = st.t_old, dt = st.dt](double t) { return s0 + (s1 - s0) * (t - t0) / dt; };
      m.loads.point_forces = {P};
      // The cells carry the interior nodes' shares (the ends' shares act in the end rows).
      auto interior = [&](double t) {
        const PointLoadWeights W = point_load_weights(P.sigma(t), m.num_cells, m.ds());
        return 1.0 - W.left - W.right;
      };
      const Vec3 applied = (1.0 - a.bt) * interior(st.t_new()) * P.force_fixed(st.t_new()) +
                           a.bt * interior(st.t_old) * P.force_fixed(st.t_old);
      const Vec3 total = summed_load_rows(m, st);
      const double e = (total + applied).norm() / applied.norm();
      worst = std::max(worst, e);
    }
  }
  std::printf("max relative |sum_cells ds * load rows + time-averaged F| = %.2e\n", worst);
  EXPECT_LT(worst, 1e-10);
}

TEST(RodLoads, AnEndShareActsInTheEndRows) {
  // A free end's force rows read n - sign R F_end: at n = 0 the residual is -sign R F_end,
  // F_end the end node's share of the load at the new level; a clamped end's rows read no
  // force (its reaction absorbs the share). The Jacobian against differences in omega.
  const StepTimes st{0.3, 0.01};
  RodModel m = test::scene_model(10);
  m.left = EndCondition::make_free();
  m.right = EndCondition::make_free();
  PointForce P;
  P.force_fixed = [](double t) { return Vec3(0.1, -2.0 - 10.0 * t, 0.3); };
  test::Rng rng;
  for (double sigma : {0.03, 0.0, 0.96, 1.0, 0.5}) {
    P.sigma = [sigma](double) { return sigma; };
    m.loads.point_forces = {P};
    const PointLoadWeights W = point_load_weights(sigma, m.num_cells, m.ds());
    for (int end = 0; end < 2; ++end) {
      const RodNode o = rng.node();
      VecX x = node_unknowns(m, o);
      x.segment<3>(var::n).setZero();
      x.segment<3>(var::kappa) = m.props.kappa0;
      const LocalBlock b = end == 0 ? left_block(m, st, o, x) : right_block(m, st, o, x);
      const Mat3 R = new_level_node(m, o, x.head<12>(), st.dt).R;
      const double share = end == 0 ? W.left : W.right, sign = end == 0 ? -1.0 : 1.0;
      const Vec3 expected = -sign * share * (R * P.force_fixed(st.t_new()));
      EXPECT_LT((b.residual.head<3>() - expected).norm(), 1e-13) << sigma << " end " << end;
      for (int i = 0; i < 3; ++i) {  // d rows / d omega_i
        const double h = 1e-6;
        VecX xp = x, xm = x;
        xp(var::omega + i) += h;
        xm(var::omega + i) -= h;
        const VecX fd = ((end == 0 ? left_block(m, st, o, xp) : right_block(m, st, o, xp)).residual -
                         (end == 0 ? left_block(m, st, o, xm) : right_block(m, st, o, xm)).residual) / (2.0 * h);
        EXPECT_LT((fd - b.jac[0].col(var::omega + i)).cwiseAbs().maxCoeff(), 1e-7) << sigma << " end " << end;
      }
      RodModel held = m;
      held.left = held.right = EndCondition::make_clamped();
      const LocalBlock c = end == 0 ? left_block(held, st, o, x) : right_block(held, st, o, x);
      EXPECT_EQ((c.residual.head<3>() - x.segment<3>(var::u)).norm(), 0.0) << "a clamped end reads no force";
    }
  }
}

TEST(RodLoads, MassWithoutInertiaEqualsItsWeightAsAPointForce) {
  const StepTimes st{0.1, 0.01};
  RodModel a = test::scene_model(10);
  a.loads.gravity = Vec3(0.0, -9.8, 0.0);
  RodModel b = a;
  MovingMass M;
  M.mass = 0.2;
  M.inertia = false;
  M.sigma = [](double t) { return 0.37 + 2.0 * t; };
  a.loads.masses = {M};
  PointForce P;
  P.force_fixed = [](double) { return Vec3(0.0, -0.2 * 9.8, 0.0); };
  P.sigma = M.sigma;
  b.loads.point_forces = {P};
  test::Rng rng;
  double e = 0.0;
  for (int j = 1; j <= 10; ++j) {
    const RodNode o0 = rng.node(), o1 = rng.node();
    const VecX x0 = rng.unknowns(a, o0), x1 = rng.unknowns(a, o1);
    e = std::max(e, (cell_block(a, st, j, o0, o1, x0, x1).residual -
                     cell_block(b, st, j, o0, o1, x0, x1).residual).cwiseAbs().maxCoeff());
  }
  std::printf("moving force vs point force residual difference %.2e\n", e);
  EXPECT_LT(e, 1e-12);
}

TEST(RodLoads, MassPathSegmentsTileThePathOnTheRod) {
  // (sigma_old, sigma_new): inside a cell, node to node, across nodes both ways, at rest on a
  // node and inside a cell, entering at 0, leaving at L, passing the whole rod.
  const int N = 10;
  const double ds = 0.1, L = 1.0;
  const std::vector<std::pair<double, double>> paths = {{0.33, 0.37}, {0.3, 0.4},   {0.27, 0.55}, {0.55, 0.27},
                                                        {0.4, 0.4},   {0.43, 0.43}, {-0.05, 0.12}, {0.93, 1.2},
                                                        {-0.5, 1.5},  {1.0, 1.0},   {0.0, 0.0}};
  double worst = 0.0;
  for (const auto& [a, b] : paths) {
    // tau at which the path is on the rod
    double on0 = 0.0, on1 = 1.0;
    if (a != b) {
      const double t0 = (0.0 - a) / (b - a), t1 = (L - a) / (b - a);
      on0 = std::max(0.0, std::min(t0, t1));
      on1 = std::min(1.0, std::max(t0, t1));
    }
    double covered = 0.0, last_tau = -1.0, last_s = 0.0;
    int cells = 0;
    for (int k = 0; k < N; ++k) {
      const int j = b >= a ? k + 1 : N - k;  // along the path
      const MassPathSegment g = mass_path_in_cell(a, b, j, N, ds);
      if (!g.valid) continue;
      ++cells;
      covered += g.tau_b - g.tau_a;
      EXPECT_GE(g.s_a, (j - 1) * ds - 1e-15);
      EXPECT_LE(g.s_b, j * ds + 1e-15);
      EXPECT_GE(std::min(g.s_a, g.s_b), (j - 1) * ds - 1e-15);
      EXPECT_LE(std::max(g.s_a, g.s_b), j * ds + 1e-15);
      if (last_tau >= 0.0) {  // consecutive segments share their end point exactly
        EXPECT_EQ(g.tau_a, last_tau);
        EXPECT_EQ(g.s_a, last_s);
      }
      last_tau = g.tau_b;
      last_s = g.s_b;
    }
    worst = std::max(worst, std::abs(covered - (on1 - on0)));
    std::printf("path %.2f -> %.2f: %d cells, time on the rod %.15f of the step (expected %.15f)\n", a, b, cells, covered,
                on1 - on0);
    if (a == b) {
      EXPECT_EQ(cells, 1);
    }
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_FALSE(mass_path_in_cell(-0.2, -0.1, 1, N, ds).valid);
  EXPECT_FALSE(mass_path_in_cell(std::nan(""), 0.1, 1, N, ds).valid);
  // At rest on a node: the cell on its right (cell N at L); ds = 1/8 so that nodes are exact.
  EXPECT_TRUE(mass_path_in_cell(0.375, 0.375, 4, 8, 0.125).valid);
  EXPECT_FALSE(mass_path_in_cell(0.375, 0.375, 3, 8, 0.125).valid);
  EXPECT_TRUE(mass_path_in_cell(1.0, 1.0, 8, 8, 0.125).valid);
}

TEST(RodLoads, LineMassPartsTileItAndShareLikeAPointForce) {
  // The parts of a moving mass's line mass [sigma - ds, sigma + ds] in the cells tile its
  // on-rod part, and each cell's share of it is the share a point force at sigma gets
  // through the scheme's average at bs = 1/2 (so the shares' alternating sum over the cells
  // vanishes away from the ends): sigma on nodes, between them, at and near 0 and L.
  const int N = 10;
  const double ds = 0.1, L = 1.0;
  double worst = 0.0, alternating = 0.0;
  for (double sigma : {0.0, 1e-17, 0.05, 0.1, 0.2999999999, 0.3, 0.37, 0.55, 0.9, 0.95, 1.0 - 1e-16, 1.0}) {
    const PointLoadWeights w = point_load_weights(sigma, N, ds);
    double covered = 0.0, alt = 0.0, last_r = std::max(sigma - ds, 0.0);
    for (int j = 1; j <= N; ++j) {
      double l = 0.0, r = 0.0;
      const bool in = line_mass_part(sigma, j, N, ds, l, r);
      double share = 0.0;  // a point force's share of cell j: (1 - bs) w_j + bs w_{j-1}
      share += 0.5 * (w.at(j) + w.at(j - 1));
      if (!in) {
        EXPECT_EQ(share, 0.0) << sigma << " cell " << j;
        continue;
      }
      EXPECT_NEAR(l, last_r, 1e-15) << sigma << " cell " << j;  // consecutive parts touch
      last_r = r;
      covered += r - l;
      // Away from the ends the part is the point force's share of the mass; at the ends the
      // line mass's part beyond the rod is missing, the point force's end share acts in the end rows.
      if (sigma >= ds && sigma <= L - ds) worst = std::max(worst, std::abs((r - l) / (2.0 * ds) - share));
      alt += (j % 2 == 0 ? 1.0 : -1.0) * (r - l);
    }
    EXPECT_NEAR(covered, std::min(sigma + ds, L) - std::max(sigma - ds, 0.0), 1e-15) << sigma;
    if (sigma >= ds && sigma <= L - ds) alternating = std::max(alternating, std::abs(alt) / (2.0 * ds));
  }
  std::printf("line mass vs point force shares: %.2e; alternating sum of the shares %.2e\n", worst, alternating);
  EXPECT_LT(worst, 1e-14);
  EXPECT_LT(alternating, 1e-14);
  double l = 0.0, r = 0.0;
  EXPECT_FALSE(line_mass_part(-0.01, 1, N, ds, l, r));  // off the rod
  EXPECT_FALSE(line_mass_part(1.01, N, N, ds, l, r));
  EXPECT_FALSE(line_mass_part(std::nan(""), 1, N, ds, l, r));
  EXPECT_FALSE(line_mass_part(0.55, 4, N, ds, l, r));  // the line mass covers cells 5..7
  EXPECT_TRUE(line_mass_part(0.55, 5, N, ds, l, r));
  EXPECT_FALSE(line_mass_part(0.55, 0, N, ds, l, r));  // no such cell
}

TEST(RodLoads, MassImpulsesTelescopeToTheChangeOfItsMomentum) {
  // Frames all I (omega = 0 at both levels) and velocities linear in s at each level, so that
  // p' = u + v e3 is bilinear in (s, t) and the kernels' interpolation is exact: the momentum
  // rows of all cells times ds dt add up to the change of the line mass's momentum on the rod,
  // Pi = M / (2 ds) times the integral of p' over its part on the rod, plus the momentum it
  // carries through the rod's ends while they lie inside it; where it is on the rod at both
  // levels, to M (p'(sigma_i, t_i) - p'(sigma_{i-1}, t_{i-1})). Paths inside a cell, node to
  // node, across nodes both ways, across several cells, at rest, and near and at both ends.
  test::Rng rng;
  const StepTimes st{0.2, 0.01};
  double worst = 0.0, worst_dp = 0.0;
  for (const AlphaParameters& al : {AlphaParameters{}, AlphaParameters::from_rho_inf(0.6, 0.8)}) {
    for (const auto& [a, b] : std::vector<std::pair<double, double>>{{0.33, 0.37}, {0.3, 0.4}, {0.27, 0.55},
                                                                      {0.55, 0.12}, {0.4, 0.4}, {0.03, 0.12},
                                                                      {0.85, 1.0}, {0.0, 0.25}}) {
      RodModel m = test::scene_model(10, al);
      const double ds = m.ds(), dt = st.dt, L = 1.0, rho = 0.3 / (2.0 * ds);
      MovingMass M;
      M.mass = 0.3;
      const double v = (b - a) / dt, t0 = st.t_old;
      M.sigma = [=](double t) { return a + v * (t - t0); };
      M.speed = [=](double) { return v; };
      M.accel = [](double) { return 0.0; };
      m.loads.masses = {M};
      const Vec3 A0 = rng.vec3(0.3), B0 = rng.vec3(0.3), A1 = rng.vec3(0.3), B1 = rng.vec3(0.3);
      auto p_at = [&](double s, double tau) {  // p' at (s, t_old + tau dt)
        return Vec3((1 - tau) * (A0 + s * B0) + tau * (A1 + s * B1) + v * Vec3::UnitZ());
      };
      std::vector<RodNode> old(11);
      std::vector<VecX> x(11);
      for (int k = 0; k <= 10; ++k) {
        old[k].y.segment<3>(var::u) = A0 + k * ds * B0;
        x[k] = node_unknowns(m, old[k]);
        x[k].segment<3>(var::u) = A1 + k * ds * B1;
      }
      Vec3 total = Vec3::Zero();
      for (int j = 1; j <= 10; ++j)
        total += ds * dt * load_block(m, st, j, old[j - 1], old[j], x[j - 1], x[j]).residual.head<3>();
      auto Pi = [&](double sigma, double tau) {  // the line mass's momentum on the rod
        const double l = std::max(sigma - ds, 0.0), r = std::min(sigma + ds, L);
        return Vec3(rho * (r - l) * p_at(0.5 * (l + r), tau));
      };
      // Times (tau) during which the rod's ends lie inside the line mass.
      auto inside = [&](double edge, double sign) {  // {tau0, tau1}: sign (sigma(tau) - edge) < ds
        double lo = 0.0, hi = 1.0;
        if (a == b) return std::abs(a - edge) < ds ? std::make_pair(lo, hi) : std::make_pair(0.0, 0.0);
        const double tx = (edge + sign * ds - a) / (b - a);  // where sigma(tau) = edge + sign ds
        if ((b - a) * sign > 0) hi = std::min(hi, tx); else lo = std::max(lo, tx);
        return hi > lo ? std::make_pair(lo, hi) : std::make_pair(0.0, 0.0);
      };
      const auto e0 = inside(0.0, 1.0), eL = inside(L, -1.0);
      Vec3 expected = Pi(b, 1.0) - Pi(a, 0.0);
      expected -= rho * v * (e0.second - e0.first) * dt * p_at(0.0, 0.5 * (e0.first + e0.second));
      expected += rho * v * (eL.second - eL.first) * dt * p_at(L, 0.5 * (eL.first + eL.second));
      const double e = (total - expected).norm() / expected.norm();
      worst = std::max(worst, e);
      const bool whole = std::min(a, b) >= ds && std::max(a, b) <= L - ds;
      double edp = 0.0;
      if (whole) {
        const Vec3 dp = M.mass * (p_at(b, 1.0) - p_at(a, 0.0));
        edp = (total - dp).norm() / dp.norm();
        worst_dp = std::max(worst_dp, edp);
        std::printf("path %.2f -> %.2f: momentum rows vs the line mass's impulse %.2e, vs M dp' %.2e\n", a, b, e, edp);
      } else {
        std::printf("path %.2f -> %.2f: momentum rows vs the line mass's impulse %.2e (partly off the rod)\n", a, b, e);
      }
    }
  }
  EXPECT_LT(worst, 1e-13);
  EXPECT_LT(worst_dp, 1e-13);
}

TEST(RodLoads, AxialPointLoadBetweenNodesJumpsNByTheForce) {
  // Straight cantilever (clamped at 0, free at L), axial load F k at sigma, switched on
  // after t = 0 (so that the old level of the first step is consistent): n3 = F left of the
  // load's cell, 0 right of it, at every step (exact discrete solution). A load at the clamp
  // goes into its reaction (n3 = 0 all along); one at the free end is its end force (n3 = F
  // all along).
  for (double sigma : {0.43, 0.5, 0.0, 1.0}) {
    RodModel m = test::scene_model(10);
    m.right = EndCondition::make_free();
    const double F = 3.7;
    PointForce P;
    P.force_fixed = [F](double t) { return Vec3(0.0, 0.0, t > 0.0 ? F : 0.0); };
    P.sigma = [sigma](double) { return sigma; };
    m.loads.point_forces = {P};
    const ReferenceStepper st(m);
    RodState s = straight_rest_state(10, 1.0);
    for (int i = 0; i < 3; ++i) {
      const ReferenceStepReport r = st.step(s, 0.01);
      ASSERT_TRUE(r.converged);
      const double n_left = s.nodes[0].y(var::n + 2), n_right = s.nodes[10].y(var::n + 2);
      std::printf("sigma = %.2f, step %d: n3(0) = %.15f, n3(L) = %.3e, jump %.15f (F = %.1f)\n",
                  sigma, i + 1, n_left, n_right, n_right - n_left, F);
      const double left = sigma > 0.0 ? F : 0.0, right = sigma == 1.0 ? F : 0.0;
      EXPECT_NEAR(n_left, left, 1e-10);
      EXPECT_NEAR(n_right, right, 1e-10);
    }
  }
}

TEST(RodLoads, TransverseQuasiStaticLoadReaction) {
  // Cantilever under a transverse point load between nodes, raised quasi-statically in 10
  // huge steps with rho_inf = 0 (bt = 0: load and flux at the new level only, inertia
  // ~ 1/dt): the clamp reaction R(0)^T n(0) must approach F. The orientation is advanced in
  // time only (R_new = exp(-hat(dt omega_c)) R_old), so its compatibility with kappa is
  // O((rotation increment)^2) per step: the error measures that, not the load treatment.
  const Vec3 F(0.0, -1e-3, 0.0);
  const double sigma = 0.53;
  for (int N : {10, 40}) {
    RodModel m = test::scene_model(N, AlphaParameters::from_rho_inf(0.0));
    m.right = EndCondition::make_free();
    PointForce P;
    P.force_fixed = [F](double t) { return Vec3(F * std::min(t / 10.0e6, 1.0)); };
    P.sigma = [sigma](double) { return sigma; };
    m.loads.point_forces = {P};
    const ReferenceStepper st(m);
    RodState s = straight_rest_state(N, 1.0);
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(st.step(s, 1e6).converged);
    const Vec3 n0 = s.nodes[0].R.transpose() * s.nodes[0].y.segment<3>(var::n);
    double beyond = 0.0;  // n beyond the load's cell is zero
    for (int j = static_cast<int>(sigma * N) + 2; j <= N; ++j)
      beyond = std::max(beyond, s.nodes[j].y.segment<3>(var::n).norm());
    const double err = (n0 - F).norm() / F.norm();
    const auto r_c = centreline_in_space(s);
    std::printf("N = %d: reaction n(0) = (%.3e, %.12f, %.3e), rel. error %.3e, |n| beyond load "
                "%.1e, tip deflection %.6e m\n", N, n0(0), n0(1), n0(2), err, beyond, r_c.back()(1));
    EXPECT_LT(beyond, 1e-12);
    EXPECT_LT(err, 1e-4);
  }
}

TEST(RodLoads, MovingLoadAndMassRunsOnAndBetweenNodes) {
  // Clamped / clamped-sliding rod (hanging-cable ends) from the straight rest state under a
  // moving 2 N load (switched on at t = 0, so the box scheme's undamped algebraic mode is
  // excited a little) at the resonant speed v1 and a moving 0.1 kg mass; dt = ds / v (load on
  // nodes) and dt = 0.7 ds / v (between nodes).
  const RodProperties p = RodProperties::scene_rod();
  const double v = std::pow(4.73, 2) * std::sqrt(p.K(0) / p.rhoA) / constants::pi;
  for (double frac : {1.0, 0.7}) {
    for (bool mass : {false, true}) {
      RodModel m = test::scene_model(50);
      m.right = EndCondition::make_sliding(Vec3::UnitZ());
      if (mass) {
        MovingMass M;
        M.mass = 0.1;
        M.sigma = [v](double t) { return v * t; };
        M.speed = [v](double) { return v; };
        M.accel = [](double) { return 0.0; };
        m.loads.gravity = Vec3(0.0, -9.8, 0.0);
        m.loads.masses = {M};
      } else {
        PointForce P;
        P.force_fixed = [](double) { return Vec3(0.0, -2.0, 0.0); };
        P.sigma = [v](double t) { return v * t; };
        m.loads.point_forces = {P};
      }
      const ReferenceStepper st(m);
      RodState s = straight_rest_state(50, 1.0);
      std::vector<Vec3> r = centreline_in_space(s);
      const double dt = frac * m.ds() / v;
      int its = 0;
      double ymin = 0.0;
      bool ok = true;
      while (s.t < 0.9 / v) {  // stop before the mass reaches the end (see docs/rod.md)
        const RodState old = s;
        const ReferenceStepReport rep = st.step(s, dt);
        ok = ok && rep.converged;
        if (!rep.converged) break;
        its = std::max(its, rep.iterations);
        r = advance_centreline_in_time(r, old, s);
        ymin = std::min(ymin, r[25](1));
      }
      EXPECT_TRUE(ok);
      const auto rs = centreline_in_space(s);
      double diff = 0.0;
      for (size_t j = 0; j < r.size(); ++j) diff = std::max(diff, (r[j] - rs[j]).norm());
      std::printf("%s, dt = %.1f ds/v: max Newton its %d, min midspan y %.6f m, |r(time) - "
                  "r(space)| = %.2e m\n", mass ? "moving mass 0.1 kg + gravity" : "moving force 2 N",
                  frac, its, ymin, diff);
      EXPECT_LT(diff, 0.05 * std::abs(ymin));
    }
  }
}

TEST(RodLoads, CentrelineOfACircularArcIsSecondOrder) {
  const double k = 2.0;
  double err[3];
  for (int i = 0; i < 3; ++i) {
    const int N = 10 << i;
    const RodState s = state_from_curvature(N, 1.0, [k](double) { return Vec3(k, 0.0, 0.0); });
    const auto r = centreline_in_space(s);
    const Vec3 exact(0.0, (std::cos(k) - 1.0) / k, std::sin(k) / k);
    err[i] = (r.back() - exact).norm();
    EXPECT_LT(so3::orthonormality_defect(s.nodes.back().R), 1e-14);
  }
  std::printf("arc end-point error N=10/20/40: %.3e %.3e %.3e, order %.3f\n", err[0], err[1],
              err[2], std::log2(err[1] / err[2]));
  EXPECT_NEAR(std::log2(err[1] / err[2]), 2.0, 0.1);
}

}  // namespace
}  // namespace traverse::rod

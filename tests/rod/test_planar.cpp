// Planar fast path, rod level (rod/planar.hpp): the parity split of the kernels at states
// symmetric about a plane, the in-plane cell kernel against the restricted full kernel, the
// end-row split of every end condition, and check_planar's verdicts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>

#include "rod_test_util.hpp"
#include "traverse/rod/planar.hpp"

namespace traverse::rod {
namespace {

struct ParamCase {
  const char* name;
  AlphaParameters alpha;
};

std::vector<ParamCase> param_cases() {
  return {{"default 1/2", AlphaParameters{}},
          {"rho_t=0.6", AlphaParameters::from_rho_inf(0.6)},
          {"carried ys rho_t=0.8 rho_s=0.7", AlphaParameters::from_rho_inf(0.8, 0.7)}};
}

/// A frame (rows d1, d2, d3) whose axis `axis` (0 or 1) is the unit vector n.
Mat3 frame_with_axis(const Vec3& n, int axis, test::Rng& rng) {
  Vec3 b = n.cross(rng.vec3(1.0)).normalized();
  Mat3 R;
  if (axis == 0) {
    R.row(0) = n;
    R.row(1) = b;
    R.row(2) = n.cross(b);
  } else {
    R.row(1) = n;
    R.row(2) = b;
    R.row(0) = n.cross(b);
  }
  return R;
}

/// A random vector in the plane normal to n.
Vec3 in_plane(const Vec3& n, test::Rng& rng, double scale) {
  const Vec3 v = rng.vec3(scale);
  return v - v.dot(n) * n;
}

/// A 12-vector with random in-plane components (scales like Rng::y) and zero elsewhere.
Vec12 symmetric(int axis, test::Rng& rng, double scale) {
  const Vec12 full = rng.y(0.3 * scale, 2.0 * scale, 3.0 * scale, 5.0 * scale);
  Vec12 v = Vec12::Zero();
  for (int k : in_plane_components(axis)) v(k) = full(k);
  return v;
}

RodNode symmetric_node(const Vec3& n, int axis, test::Rng& rng) {
  RodNode nd;
  nd.R = frame_with_axis(n, axis, rng);
  nd.y = symmetric(axis, rng, 1.0);
  nd.yt = symmetric(axis, rng, 10.0);
  nd.ys = symmetric(axis, rng, 10.0);
  nd.kst(axis) = 30.0 * rng.uniform();  // the carried kappa_s's rate about the normal
  return nd;
}

/// Symmetric new unknowns near the old node.
VecX symmetric_unknowns(const RodModel& m, const RodNode& old, int axis, test::Rng& rng) {
  VecX x = node_unknowns(m, old);
  x.head<12>() += symmetric(axis, rng, 0.2);
  if (m.carries_ys()) x.tail<12>() += symmetric(axis, rng, 2.0);
  return x;
}

/// A model with an anisotropic section, intrinsic curvature about the normal, gravity and a
/// point force in the plane and a moving mass, the loads crossing cell j during the step.
RodModel planar_model(const AlphaParameters& alpha, const Vec3& n, int axis, int j, const StepTimes& st,
                      test::Rng& rng) {
  RodModel m = test::scene_model(10, alpha);
  m.props.K = Vec3(0.9, 1.4, 0.6) * m.props.K(0);
  m.props.rhoI = Vec3(1.1, 0.8, 1.7) * m.props.rhoI(0);
  m.props.kappa0 = Vec3::Zero();
  m.props.kappa0(axis) = 0.7;
  const double ds = m.ds();
  m.loads.gravity = in_plane(n, rng, 9.8);
  const Vec3 F = in_plane(n, rng, 2.0);
  const double s0 = (j - 1 + 0.3) * ds, v = 0.9 * ds / st.dt, t0 = st.t_old;
  m.loads.point_forces.push_back({[F](double) { return F; }, [=](double t) { return s0 + v * (t - t0); }});
  MovingMass M;
  M.mass = 0.3;
  M.sigma = [=](double t) { return s0 - 0.5 * ds + v * (t - t0); };
  M.speed = [=](double) { return v; };
  M.accel = [](double) { return 1.5; };
  m.loads.masses.push_back(M);
  return m;
}

/// Entries of a node block (12 or 24) that are in-plane.
std::vector<bool> even_entries(int axis, int p) {
  std::vector<bool> e(static_cast<size_t>(p), false);
  for (int k : in_plane_components(axis)) {
    e[static_cast<size_t>(k)] = true;
    if (p == 24) e[static_cast<size_t>(12 + k)] = true;
  }
  return e;
}

struct Parity {
  double odd_residual = 0.0, residual = 0.0;  // max |r| over out-of-plane rows, all rows
  double cross = 0.0, jac = 0.0;              // max |J| over the parity-mixing entries, all
};

Parity parity_of(const LocalBlock& b, const std::vector<bool>& even_rows, const std::vector<bool>& even_cols) {
  Parity p;
  for (Eigen::Index i = 0; i < b.residual.size(); ++i) {
    p.residual = std::max(p.residual, std::abs(b.residual(i)));
    if (!even_rows[static_cast<size_t>(i)]) p.odd_residual = std::max(p.odd_residual, std::abs(b.residual(i)));
    for (const MatX& J : b.jac)
      for (Eigen::Index c = 0; c < J.cols(); ++c) {
        p.jac = std::max(p.jac, std::abs(J(i, c)));
        if (even_rows[static_cast<size_t>(i)] != even_cols[static_cast<size_t>(c)])
          p.cross = std::max(p.cross, std::abs(J(i, c)));
      }
  }
  return p;
}

// The rod models the planar path takes (docs/rod.md): the inextensible rod, the rods that
// strain and the viscosities (compliances and retardation times large enough to show).
std::vector<std::pair<std::string, RodProperties>> strain_variants(const RodProperties& base) {
  std::vector<std::pair<std::string, RodProperties>> v{{"", base}};
  RodProperties ext = base, shear = base;
  ext.C = RodProperties::compliance(RodStrain::extensible, 200.0, 0.0);
  shear.C = RodProperties::compliance(RodStrain::shearable, 200.0, 50.0);
  shear.B_se = Vec3(0.3, 0.2, 0.5);
  v.push_back({" extensible", ext});
  v.push_back({" shearable B_se", shear});
  shear.B_bt = Vec3(1e-3, 2e-3, 3e-3);
  v.push_back({" shearable B_se B_bt", shear});
  return v;
}

// The physics behind the planar path: at a state symmetric about the plane, the cell rows'
// out-of-plane residuals vanish and the Jacobian has no entry coupling in-plane and
// out-of-plane unknowns (the cell rows split with the same indices as the unknowns).
TEST(Planar, CellKernelDecouplesAtSymmetricStates) {
  test::Rng rng;
  const StepTimes st{0.37, 0.01};
  for (const auto& pc : param_cases()) {
    for (int axis = 0; axis < 2; ++axis) {
      const Vec3 n = rng.vec3(1.0).normalized();
      const int j = 4;
      const RodModel base = planar_model(pc.alpha, n, axis, j, st, rng);
      for (const auto& [variant, props] : strain_variants(base.props)) {
        RodModel m = base;
        m.props = props;
        const int p = m.unknowns_per_node();
        const std::vector<bool> even = even_entries(axis, p);
        double odd = 0.0, cross = 0.0;
        for (int trial = 0; trial < 5; ++trial) {
          const RodNode o0 = symmetric_node(n, axis, rng);
          RodNode o1 = symmetric_node(n, axis, rng);
          o1.R = o0.R;  // neighbouring nodes: the same plane
          const VecX x0 = symmetric_unknowns(m, o0, axis, rng), x1 = symmetric_unknowns(m, o1, axis, rng);
          ASSERT_TRUE(loads_touch_cell(m, st, j));
          const Parity P = parity_of(cell_block(m, st, j, o0, o1, x0, x1), even, even);
          odd = std::max(odd, P.odd_residual / P.residual);
          cross = std::max(cross, P.cross / P.jac);
      }
      std::printf("  %-32s%s normal d%d: out-of-plane residual / max %.2e, coupling entries / max %.2e\n", pc.name,
                  variant.c_str(), axis + 1, odd, cross);
      EXPECT_LT(odd, 1e-13) << pc.name << variant;
      EXPECT_LT(cross, 1e-13) << pc.name << variant;
      }
    }
  }
  // The check can fail: a force with an out-of-plane component gives out-of-plane residuals.
  const Vec3 n = Vec3::UnitX();
  RodModel m = planar_model(AlphaParameters{}, n, 0, 4, st, rng);
  m.loads.gravity += Vec3(0.5, 0.0, 0.0);
  const RodNode o0 = symmetric_node(n, 0, rng), o1 = symmetric_node(n, 0, rng);
  const std::vector<bool> even = even_entries(0, 12);
  const Parity P = parity_of(cell_block(m, st, 4, o0, o1, symmetric_unknowns(m, o0, 0, rng),
                                        symmetric_unknowns(m, o1, 0, rng)),
                             even, even);
  std::printf("  gravity with an out-of-plane component: out-of-plane residual / max %.2e\n",
              P.odd_residual / P.residual);
  EXPECT_GT(P.odd_residual / P.residual, 1e-4);
}

// The in-plane cell kernel (PlanarReduction: the 6-component flux, its 6 x 6 Jacobian and the
// frame's turn about the normal) against the in-plane rows and columns of the full kernel,
// with and without loads on the cell, both normals, every scheme variant.
TEST(Planar, InPlaneCellKernelEqualsRestrictedFullKernel) {
  test::Rng rng;
  const StepTimes st{0.37, 0.01};
  for (const auto& pc : param_cases()) {
    for (int axis = 0; axis < 2; ++axis) {
      const Vec3 n = rng.vec3(1.0).normalized();
      const RodModel base = planar_model(pc.alpha, n, axis, 4, st, rng);
      for (const auto& [variant, props] : strain_variants(base.props)) {
        RodModel m = base;
        m.props = props;
        PlanarSymmetry sym;  // the end rows do not matter for a cell
        sym.normal = n;
        sym.axis = axis;
        sym.left_rows = {{1, 2, 3}};
        sym.right_rows = {{1, 2, 3}};
        if (axis == 1) sym.left_rows = sym.right_rows = {{0, 2, 4}};
        const PlanarReduction red(m, sym);
        double dr = 0.0, dj = 0.0, dd = 0.0;
        for (int j : {4, 7}) {  // with (4) and without (7) the loads
          const RodNode o0 = symmetric_node(n, axis, rng);
          RodNode o1 = symmetric_node(n, axis, rng);
          o1.R = o0.R;
          const VecX x0 = symmetric_unknowns(m, o0, axis, rng), x1 = symmetric_unknowns(m, o1, axis, rng);
          LocalBlock full = cell_block(m, st, j, o0, o1, x0, x1), expected, got;
          const double drop_expected = red.restrict_block(full, expected);
          const PlanarReduction::OldNode p0 = red.old_node(m, st, j - 1, o0), p1 = red.old_node(m, st, j, o1);
          const VecX q0 = red.restrict_unknowns(x0), q1 = red.restrict_unknowns(x1);
          PlanarReduction::NewLevels l0, l1;
          red.new_levels(m, st, p0, q0.data(), l0);
          red.new_levels(m, st, p1, q1.data(), l1);
          double drop_got = red.cell_block_into(got, m, st, j, p0, p1, q0.data(), q1.data(), l0, l1);
          if (loads_touch_cell(m, st, j))
            drop_got = std::max(drop_got, red.add_loads(got, load_block(m, st, j, o0, o1, x0, x1)));
          ASSERT_EQ(got.row, expected.row);
          ASSERT_EQ(got.cols, expected.cols);
          dr = std::max(dr, test::relative_difference(got.residual, expected.residual));
          for (size_t k = 0; k < 2; ++k) dj = std::max(dj, test::relative_difference(got.jac[k], expected.jac[k]));
          dd = std::max(dd, std::abs(drop_got - drop_expected));
      }
      std::printf("  %-32s%s normal d%d: residual %.2e, Jacobian %.2e (relative), dropped residual %.2e\n", pc.name,
                  variant.c_str(), axis + 1, dr, dj, dd);
      EXPECT_LT(dr, 1e-14) << pc.name << variant;
      EXPECT_LT(dj, 1e-14) << pc.name << variant;
      EXPECT_LT(dd, 1e-12) << pc.name << variant;
      }
    }
  }
}

/// check_planar of a straight rod along k (frame I, plane normal i = d1) with these ends.
PlanarCheck straight_check(const EndCondition& left, const EndCondition& right,
                           const Vec3& gravity = Vec3(0.0, -9.8, 0.0)) {
  RodModel m = test::scene_model(8);
  m.left = left;
  m.right = right;
  m.loads.gravity = gravity;
  return check_planar(m, straight_rest_state(m.num_cells, m.length), {});
}

std::array<int, 3> rows(int a, int b, int c) { return {{a, b, c}}; }

// The in-plane rows of each end condition for the plane normal i = d1 (x): derived by hand
// from end_condition_rows (docs/solver.md, "Planar fast path").
TEST(Planar, EndRowsSplitThreePlusThree) {
  using E = EndCondition;
  const Vec3 i = Vec3::UnitX(), j = Vec3::UnitY(), k = Vec3::UnitZ();
  struct Case {
    const char* name;
    EndCondition c;
    std::array<int, 3> expected;
  };
  const std::vector<Case> cases = {
      {"clamped (u2, u3, omega1)", E::make_clamped(), rows(1, 2, 3)},
      {"pinned about i (u2, u3, m.i)", E::make_pinned(i), rows(1, 2, 5)},
      {"pinned about j (u2, u3, omega.i)", E::make_pinned(j), rows(1, 2, 4)},
      {"sliding along k (u.j, omega1, n.k)", E::make_sliding(k), rows(0, 2, 5)},
      {"free (n2, n3, m1)", E::make_free(), rows(1, 2, 3)},
      {"roller pin i, slide k (u.j, n.k, m.i)", E::make_roller(i, k, 0.3), rows(0, 2, 5)},
      {"prescribed in-plane (u2, u3, omega1)",
       E::make_prescribed([](double t) { return Vec3(0.0, 0.1 * t, 0.2); }, [](double) { return Vec3(0.3, 0, 0); }),
       rows(1, 2, 3)},
  };
  for (const auto& c : cases) {
    const PlanarCheck chk = straight_check(c.c, E::make_clamped());
    ASSERT_TRUE(chk.planar) << c.name << ": " << chk.reason;
    EXPECT_EQ(chk.symmetry.axis, 0) << c.name;
    EXPECT_EQ(chk.symmetry.left_rows, c.expected) << c.name;
    std::printf("  %-40s in-plane rows %d %d %d\n", c.name, chk.symmetry.left_rows[0], chk.symmetry.left_rows[1],
                chk.symmetry.left_rows[2]);
  }
  // Sliding along the normal is planar (in the plane it holds like a clamp: u.j = u.k = 0,
  // omega1 = 0; n.i = 0 is out of the plane).
  const PlanarCheck s = straight_check(E::make_sliding(i), E::make_clamped());
  ASSERT_TRUE(s.planar) << s.reason;
  EXPECT_EQ(s.symmetry.left_rows, rows(0, 1, 2));
  // Out-of-plane prescribed motion, and an oblique slide axis, are not planar about i.
  const PlanarCheck a = straight_check(
      E::make_prescribed([](double) { return Vec3(0.1, 0.0, 0.0); }, [](double) { return Vec3::Zero(); }),
      E::make_clamped(), Vec3(0.0, -9.8, 0.0));
  EXPECT_FALSE(a.planar);
  EXPECT_NE(a.reason.find("about d1: left end"), std::string::npos) << a.reason;
  const PlanarCheck b = straight_check(E::make_clamped(), E::make_sliding(Vec3(0.6, 0.0, 0.8)));
  EXPECT_FALSE(b.planar);
  EXPECT_NE(b.reason.find("about d1: right end"), std::string::npos) << b.reason;
  std::printf("  prescribed u along i: %s\n  sliding along (0.6, 0, 0.8): %s\n", a.reason.c_str(), b.reason.c_str());
}

// The scenes' verdicts at model level: the hanging cable is planar, the deep arch with its
// lateral trigger is not, and so on for each ingredient that can break the symmetry.
// The hanging cable of 20 cells with a 2 N force F moving along it.
RodModel planar_cable(const Vec3& F) {
  using E = EndCondition;
  RodModel cable = test::scene_model(20);
  cable.left = E::make_clamped();
  cable.right = E::make_sliding(Vec3::UnitZ());
  cable.loads.gravity = Vec3(0.0, -9.8, 0.0);
  cable.loads.point_forces.push_back({[F](double) { return F; }, [](double t) { return 3.6 * t; }});
  return cable;
}

// A sagging state of that cable: curvature about d1, some in-plane velocity and force.
RodState sagging_state() {
  RodState sag = state_from_curvature(20, 1.0, [](double s) { return Vec3(0.8 * (s - 0.5), 0.0, 0.0); });
  for (auto& nd : sag.nodes) {
    nd.y(var::u + 1) = 0.01;
    nd.y(var::n + 2) = 3.0;
  }
  return sag;
}

TEST(Planar, CheckPlanarVerdicts) {
  using E = EndCondition;
  const Vec3 F(0.0, -2.0, 0.0);
  const RodModel cable = planar_cable(F);
  const RodState sag = sagging_state();
  PlanarCheck c = check_planar(cable, sag, {F});
  ASSERT_TRUE(c.planar) << c.reason;
  EXPECT_EQ(c.symmetry.axis, 0);
  EXPECT_LT((c.symmetry.normal - Vec3::UnitX()).norm(), 1e-12);
  std::printf("  cable: planar, %s\n", c.symmetry.describe().c_str());

  auto verdict = [](const char* what, const PlanarCheck& k, const char* fragment) {
    std::printf("  %-38s -> %s\n", what, k.planar ? "planar" : k.reason.c_str());
    EXPECT_FALSE(k.planar) << what;
    EXPECT_NE(k.reason.find(fragment), std::string::npos) << what << ": " << k.reason;
  };
  // Deep arch: pinned about i at both ends, arch state in the (j, k) plane, the load with its
  // lateral trigger 1e-6 F along i.
  RodModel arch = cable;
  arch.left = E::make_pinned(Vec3::UnitX());
  arch.right = E::make_pinned(Vec3::UnitX());
  const Vec3 trigger(3.8e-6, -3.8, 0.0);
  arch.loads.point_forces[0].force_fixed = [trigger](double) { return trigger; };
  const RodState arch_state = state_from_curvature(20, 1.0, [](double) { return Vec3(-2.0, 0.0, 0.0); });
  verdict("deep arch with the lateral trigger", check_planar(arch, arch_state, {trigger}), "point force 0");
  EXPECT_TRUE(check_planar(arch, arch_state, {Vec3(0.0, -3.8, 0.0)}).planar) << "the same arch without the trigger";

  RodState bent = state_from_curvature(20, 1.0, [](double s) { return Vec3(0.8, 0.3 * s, 0.0); });
  verdict("state bent out of the plane", check_planar(cable, bent, {F}), "the frame at node");
  RodState moving = sag;
  moving.nodes[7].y(var::u) = 1e-3;  // u1: out of the plane
  verdict("out-of-plane velocity at one node", check_planar(cable, moving, {F}), "out-of-plane components");
  RodModel twisted = cable;
  twisted.props.kappa0 = Vec3(0.0, 0.5, 0.0);
  verdict("intrinsic curvature about d2", check_planar(twisted, sag, {F}), "intrinsic curvature");
  RodModel sideways = cable;
  sideways.loads.gravity = Vec3(-9.8, 0.0, 0.0);
  verdict("gravity along -i", check_planar(sideways, sag, {F}), "gravity");
  RodModel distributed = cable;
  distributed.loads.f_fixed = [](double, double) { return Vec3(0.0, -1.0, 0.0); };
  verdict("distributed load function", check_planar(distributed, sag, {F}), "f_fixed");
  verdict("force vectors not given", check_planar(cable, sag, {}), "were not given");
}

// The check of a state held in pieces (one per rank): each piece summed up on its own and the
// summaries merged in node order give the verdict and the reason of the whole state.
TEST(Planar, PiecewiseSummaryGivesTheWholeStatesVerdict) {
  const Vec3 F(0.0, -2.0, 0.0);
  const RodModel cable = planar_cable(F);
  const RodState sag = sagging_state();  // whole, and in two pieces below
  RodState moving = sag, bent = state_from_curvature(20, 1.0, [](double s) { return Vec3(0.8, 0.3 * s, 0.0); });
  moving.nodes[14].y(var::u) = 1e-3;  // out of the plane, in the second piece
  for (const RodState* st : std::initializer_list<const RodState*>{&sag, &moving, &bent}) {
    const PlanarCheck whole = check_planar(cable, *st, {F});
    for (int cut : {1, 7, 14, 20}) {  // pieces 0..cut-1 and cut..20
      RodState a, b;
      a.t = b.t = st->t;
      a.nodes.assign(st->nodes.begin(), st->nodes.begin() + cut);
      b.nodes.assign(st->nodes.begin() + cut, st->nodes.end());
      const Mat3 R0 = st->nodes.front().R;
      PlanarStateSummary sum = summarize_planarity(a, 0, R0);
      merge(sum, summarize_planarity(b, cut, R0));
      const PlanarCheck k = check_planar(cable, sum, st->nodes.front(), st->nodes.back(), st->t, {F});
      EXPECT_EQ(k.planar, whole.planar) << "cut " << cut;
      EXPECT_EQ(k.reason, whole.reason) << "cut " << cut;
    }
  }
  EXPECT_NE(check_planar(cable, moving, {F}).reason.find("at node 14"), std::string::npos);
}

// The planar layout: q unknowns per node, rows [3, q per cell, 3] (+ 6 collocation rows when
// ys is carried), so that row r belongs to node r / q; embed / restrict round trip.
TEST(Planar, ReductionLayout) {
  for (const auto& pc : param_cases()) {
    RodModel m = test::scene_model(5, pc.alpha);
    PlanarSymmetry sym;
    sym.left_rows = sym.right_rows = {{1, 2, 3}};
    const PlanarReduction red(m, sym);
    const int q = red.unknowns_per_node();
    EXPECT_EQ(q, m.unknowns_per_node() / 2);
    EXPECT_EQ(red.num_rows(), static_cast<Eigen::Index>(q) * 6);
    test::Rng rng;
    const RodNode o = rng.node();
    const VecX x = rng.unknowns(m, o);
    LocalBlock L, C, R;
    red.restrict_block(left_block(m, StepTimes{0.0, 0.01}, o, x), L);
    red.restrict_block(cell_block(m, StepTimes{0.0, 0.01}, 3, o, o, x, x), C);
    red.restrict_block(right_block(m, StepTimes{0.0, 0.01}, o, x), R);
    const bool carried = m.carries_ys();
    EXPECT_EQ(L.row, 0);
    EXPECT_EQ(L.residual.size(), carried ? 9 : 3);
    EXPECT_EQ(C.row, (carried ? 9 : 3) + 2 * q);
    EXPECT_EQ(C.residual.size(), q);
    EXPECT_EQ(R.row, (carried ? 9 : 3) + 5 * q);
    EXPECT_EQ(R.row + R.residual.size(), red.num_rows());
    EXPECT_EQ(C.cols[0], 2 * q);
    EXPECT_EQ(C.jac[0].cols(), q);
    VecX full;
    const VecX qx = red.restrict_unknowns(x);
    red.embed(qx.data(), full);
    EXPECT_EQ(red.restrict_unknowns(full), qx);
    double outside = 0.0;
    for (Eigen::Index k = 0; k < full.size(); ++k)
      if (std::find(red.kept_unknowns().begin(), red.kept_unknowns().end(), static_cast<int>(k)) ==
          red.kept_unknowns().end())
        outside = std::max(outside, std::abs(full(k)));
    EXPECT_EQ(outside, 0.0);
  }
}

// The static form (StaticPlanarSplit, rod::static_planar_split): the hanging cable and a pinned
// arch split about d1 = i; at random states symmetric about that plane the static blocks
// decouple (in-plane rows free of out-of-plane unknowns and the other way round, out-of-plane
// residuals zero) and restrict_static_block puts the in-plane rows where the planar layout
// has them; a load or curvature out of every candidate plane has no split.
TEST(Planar, StaticSplitOfTheCableAndTheArch) {
  auto cable = [] {
    StaticModel m;
    m.props = RodProperties::scene_rod();
    m.num_cells = 6;
    m.left = static_end(EndSpec{}, Vec3::Zero());
    m.right.type = EndCondition::Type::sliding;
    m.right.axis = Vec3::UnitZ();
    m.right.position = Vec3(0.0, 0.0, 1.0);
    m.gravity = Vec3(0.0, -9.8, 0.0);
    m.point_forces.push_back({Vec3(0.0, -2.0, 0.0), 0.37});
    return m;
  };
  StaticModel arch = cable();
  arch.left.type = arch.right.type = EndCondition::Type::pinned;
  arch.left.axis = arch.right.axis = Vec3::UnitX();
  arch.right.position = Vec3(0.0, 0.0, 0.8);
  test::Rng rng;
  for (const StaticModel& m : {cable(), arch}) {
    const std::optional<StaticPlanarSplit> split = static_planar_split(m);
    ASSERT_TRUE(split.has_value());
    EXPECT_EQ(split->axis, 0);
    const std::array<int, 6> S = in_plane_components(0);
    auto in_plane = [&](int k) { return std::find(S.begin(), S.end(), k) != S.end(); };
    std::vector<StaticNode> nodes(static_cast<size_t>(m.num_cells + 1));
    for (StaticNode& n : nodes) {
      n.Rbar = so3::exp(rng.uniform() * Vec3::UnitX());
      for (int k : S) n.x(k) = rng.uniform();
    }
    std::vector<LocalBlock> blocks{static_left_block(m, nodes.front())};
    for (int j = 1; j <= m.num_cells; ++j)
      blocks.push_back(static_cell_block(m, j, nodes[static_cast<size_t>(j - 1)], nodes[static_cast<size_t>(j)]));
    blocks.push_back(static_right_block(m, nodes.back()));
    for (size_t b = 0; b < blocks.size(); ++b) {
      const LocalBlock& full = blocks[b];
      LocalBlock out;
      const double dropped = restrict_static_block(m, *split, full, out);
      const bool left = b == 0, right = b + 1 == blocks.size();
      const std::array<int, 3>& end_rows = left ? split->left_rows : split->right_rows;
      std::vector<int> keep = left || right ? std::vector<int>(end_rows.begin(), end_rows.end())
                                            : std::vector<int>(S.begin(), S.end());
      EXPECT_EQ(out.row, left ? 0 : right ? 3 + 6 * m.num_cells : 3 + 6 * static_cast<Eigen::Index>(b - 1));
      ASSERT_EQ(out.residual.size(), static_cast<Eigen::Index>(keep.size()));
      double jmax = 0.0, fmax = full.residual.cwiseAbs().maxCoeff();
      for (const MatX& J : full.jac) jmax = std::max(jmax, J.cwiseAbs().maxCoeff());
      double coupling = 0.0, dropped_max = 0.0;
      for (Eigen::Index i = 0; i < full.residual.size(); ++i) {
        const bool kept = std::find(keep.begin(), keep.end(), static_cast<int>(i)) != keep.end();
        if (!kept) dropped_max = std::max(dropped_max, std::abs(full.residual(i)));
        for (const MatX& J : full.jac)
          for (int k = 0; k < 12; ++k)
            if (kept != in_plane(k)) coupling = std::max(coupling, std::abs(J(i, k)));
      }
      EXPECT_LE(coupling, 1e-14 * jmax) << "block " << b;
      EXPECT_LE(dropped_max, 1e-14 * std::max(1.0, fmax)) << "block " << b;
      EXPECT_EQ(dropped, dropped_max);
      for (size_t k = 0; k < full.cols.size(); ++k) {
        EXPECT_EQ(out.cols[k], full.cols[k] / 2);
        for (Eigen::Index i = 0; i < out.residual.size(); ++i) {
          EXPECT_EQ(out.residual(i), full.residual(keep[static_cast<size_t>(i)]));
          for (int c = 0; c < 6; ++c) EXPECT_EQ(out.jac[k](i, c), full.jac[k](keep[static_cast<size_t>(i)], S[static_cast<size_t>(c)]));
        }
      }
    }
  }
  // Out of every candidate plane: a point force along i besides gravity along j; gravity with
  // an i component; a natural twist of d1 = i with gravity along j.
  StaticModel a = cable(), b = cable(), c = cable();
  a.point_forces[0].force = Vec3(0.5, -2.0, 0.0);
  b.gravity = Vec3(0.3, -9.8, 0.0);
  c.props.kappa0 = Vec3(0.0, 0.2, 0.0);
  EXPECT_FALSE(static_planar_split(a).has_value());
  EXPECT_FALSE(static_planar_split(b).has_value());
  EXPECT_FALSE(static_planar_split(c).has_value());
  // In the plane of i and k instead (normal d2 = j): gravity along i.
  StaticModel d = cable();
  d.gravity = Vec3(-9.8, 0.0, 0.0);
  d.point_forces[0].force = Vec3(-2.0, 0.0, 0.0);
  ASSERT_TRUE(static_planar_split(d).has_value());
  EXPECT_EQ(static_planar_split(d)->axis, 1);
}

}  // namespace
}  // namespace traverse::rod

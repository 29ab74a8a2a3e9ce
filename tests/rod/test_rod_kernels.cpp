// Exact Jacobians of the rod kernels against central differences, and frame invariance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "rod_test_util.hpp"
#include "traverse/rod/planar.hpp"
#include "traverse/rod/static_kernels.hpp"

namespace traverse::rod {
namespace {

using test::central_jacobian;
using test::relative_difference;

struct ParamCase {
  const char* name;
  AlphaParameters alpha;
};

std::vector<ParamCase> param_cases() {
  return {{"default 1/2", AlphaParameters{}},
          {"rho_t=0.6", AlphaParameters::from_rho_inf(0.6)},
          {"carried ys rho_t=0.8 rho_s=0.7", AlphaParameters::from_rho_inf(0.8, 0.7)}};
}

/// A model with every kind of load; the point force and the mass move through cell j
/// during the step [t_old, t_old + dt].
RodModel loaded_model(const AlphaParameters& alpha, int j, const StepTimes& st) {
  RodModel m = test::scene_model(10, alpha);
  const double ds = m.ds();
  m.loads.gravity = Vec3(0.0, -9.8, 0.0);
  m.loads.f_fixed = [](double s, double t) { return Vec3(0.3 * s, std::sin(s + t), 0.2); };
  m.loads.l_fixed = [](double s, double t) { return Vec3(0.01 * t, 0.02 * s, -0.03); };
  const double s0 = (j - 1 + 0.3) * ds, v = 0.9 * ds / st.dt, t0 = st.t_old;
  PointForce P;
  P.force_fixed = [](double t) { return Vec3(0.5, -2.0 - t, 0.7); };
  P.sigma = [=](double t) { return s0 + v * (t - t0); };
  m.loads.point_forces.push_back(P);
  MovingMass M;
  M.mass = 0.3;
  M.sigma = [=](double t) { return s0 - 0.5 * ds + v * (t - t0); };
  M.speed = [=](double) { return v; };
  M.accel = [](double) { return 1.5; };
  m.loads.masses.push_back(M);
  return m;
}

TEST(RodKernels, CellAndLoadJacobiansMatchCentralDifferences) {
  test::Rng rng;
  const StepTimes st{0.37, 0.01};
  for (const auto& pc : param_cases()) {
    for (int j : {1, 5, 10}) {
      const RodModel m = loaded_model(pc.alpha, j, st);
      const RodNode o0 = rng.node(), o1 = rng.node();
      const VecX x0 = rng.unknowns(m, o0), x1 = rng.unknowns(m, o1);
      const LocalBlock b = cell_block(m, st, j, o0, o1, x0, x1);
      const LocalBlock l = load_block(m, st, j, o0, o1, x0, x1);
      EXPECT_EQ(b.row, m.cell_row(j));
      EXPECT_EQ(b.cols[0], m.node_col(j - 1));
      for (int q = 0; q < 2; ++q) {
        auto fc = [&](const VecX& x) {
          return cell_block(m, st, j, o0, o1, q == 0 ? x : x0, q == 1 ? x : x1).residual;
        };
        auto fl = [&](const VecX& x) {
          return load_block(m, st, j, o0, o1, q == 0 ? x : x0, q == 1 ? x : x1).residual;
        };
        const VecX& xq = q == 0 ? x0 : x1;
        const double ec = relative_difference(b.jac[q], central_jacobian(fc, xq));
        const double el = relative_difference(l.jac[q], central_jacobian(fl, xq));
        std::printf("[%s] cell %d node %d: cell rel err %.2e, load rel err %.2e (|load J| %.2e)\n",
                    pc.name, j, j - 1 + q, ec, el, l.jac[q].cwiseAbs().maxCoeff());
        EXPECT_LT(ec, 1e-7);
        EXPECT_LT(el, 1e-7);
        EXPECT_GT(l.jac[q].cwiseAbs().maxCoeff(), 0.0);
      }
    }
  }
}

/// The rods that strain and the viscosities (docs/rod.md, "Extensible and shearable rods"):
/// the compliance law in the compatibility rows (- v_t - omega x v), v x n in the couple rows,
/// the strain rate's history in the n slot of yt, the Kelvin-Voigt terms in n and m (the
/// moment's s-derivative in the cells, its value in the free and pinned ends). Compliances and
/// retardation times are chosen large enough (tau / (gt dt) of order one) that every term
/// shows in the Jacobian; the cells carry every kind of load.
struct StrainCase {
  const char* name;
  RodStrain strain;
  bool damped;
};

RodModel strain_model(const RodModel& base, const StrainCase& c) {
  RodModel m = base;
  m.props.C = RodProperties::compliance(c.strain, 200.0, 50.0);
  if (c.damped) {
    m.props.B_se = Vec3(0.3, 0.2, 0.5);
    m.props.B_bt = Vec3(1e-3, 2e-3, 3e-3);
  }
  return m;
}

const std::vector<StrainCase> kStrainCases = {{"extensible", RodStrain::extensible, false},
                                              {"shearable", RodStrain::shearable, false},
                                              {"extensible damped", RodStrain::extensible, true},
                                              {"shearable damped", RodStrain::shearable, true},
                                              {"inextensible damped", RodStrain::inextensible, true}};

TEST(RodKernels, StrainAndViscosityJacobiansMatchCentralDifferences) {
  test::Rng rng;
  const StepTimes st{0.37, 0.01};
  for (const auto& pc : param_cases()) {
    for (const StrainCase& sc : kStrainCases) {
      for (int j : {1, 5}) {
        const RodModel m = strain_model(loaded_model(pc.alpha, j, st), sc);
        EXPECT_EQ(m.props.compliant(), sc.strain != RodStrain::inextensible);
        EXPECT_EQ(m.props.strain_kind(), sc.strain);
        const RodNode o0 = rng.node(), o1 = rng.node();
        const VecX x0 = rng.unknowns(m, o0), x1 = rng.unknowns(m, o1);
        const LocalBlock b = cell_block(m, st, j, o0, o1, x0, x1);
        for (int q = 0; q < 2; ++q) {
          auto fc = [&](const VecX& x) {
            return cell_block(m, st, j, o0, o1, q == 0 ? x : x0, q == 1 ? x : x1).residual;
          };
          const double ec = relative_difference(b.jac[q], central_jacobian(fc, q == 0 ? x0 : x1));
          std::printf("[%s] %s cell %d node %d: rel err %.2e\n", pc.name, sc.name, j, j - 1 + q, ec);
          EXPECT_LT(ec, 1e-7) << pc.name << " " << sc.name;
        }
      }
      for (const EndCondition& e : {EndCondition::make_free(), EndCondition::make_pinned(Vec3(1.0, 0.2, -0.1))}) {
        RodModel m = strain_model(loaded_model(pc.alpha, 1, st), sc);
        m.left = m.right = e;
        const RodNode o = rng.node();
        const VecX x = rng.unknowns(m, o);
        const double el = relative_difference(
            left_block(m, st, o, x).jac[0],
            central_jacobian([&](const VecX& z) { return left_block(m, st, o, z).residual; }, x));
        const double er = relative_difference(
            right_block(m, st, o, x).jac[0],
            central_jacobian([&](const VecX& z) { return right_block(m, st, o, z).residual; }, x));
        std::printf("[%s] %s %s ends: left rel err %.2e, right %.2e\n", pc.name, sc.name,
                    e.type == EndType::free ? "free" : "pinned", el, er);
        EXPECT_LT(el, 1e-7);
        EXPECT_LT(er, 1e-7);
      }
    }
  }
}

/// The n slot of a strained node's yt is the strain rate: with the level's v from n and v_t
/// (RodProperties::strain), the new level's v_t is the scheme's recursion of v, and n equals
/// C^-1 (v - e3) + B_se v_t in the directions that strain (the Kelvin-Voigt law, solved).
TEST(RodKernels, StrainRateHistoryIsTheRecursionOfTheStrain) {
  test::Rng rng;
  const double dt = 0.01;
  for (const auto& pc : param_cases()) {
    for (const StrainCase& sc : kStrainCases) {
      if (sc.strain == RodStrain::inextensible) continue;
      const RodModel m = strain_model(test::scene_model(4, pc.alpha), sc);
      const RodProperties& p = m.props;
      RodNode old = rng.node();
      if (sc.strain == RodStrain::extensible) old.yt.segment<2>(var::n).setZero();  // no lateral strain rate
      const Vec12 y = rng.unknowns(m, old).head<12>();
      const NewLevelNode nn = new_level_node(m, old, y, dt);
      const Vec3 vt = nn.yt.segment<3>(var::n), vt_old = old.yt.segment<3>(var::n);
      const Vec3 v = p.strain(y.segment<3>(var::n), vt), v_old = p.strain(old.y.segment<3>(var::n), vt_old);
      const double g = pc.alpha.gt;
      const Vec3 recursion = (v - v_old) / (g * dt) - (1.0 - g) / g * vt_old;
      double law = 0.0;
      for (int i = 0; i < 3; ++i)
        if (p.C(i) != 0.0)
          law = std::max(law, std::abs((v(i) - (i == 2 ? 1.0 : 0.0)) / p.C(i) + p.B_se(i) * vt(i) - y(var::n + i)));
      const double er = (vt - recursion).cwiseAbs().maxCoeff();
      std::printf("[%s] %s: |v_t - recursion| %.2e, |Kelvin-Voigt law| %.2e N, lateral v %.1e\n", pc.name, sc.name,
                  er, law, v.head<2>().cwiseAbs().maxCoeff());
      EXPECT_LT(er, 1e-9 * (1.0 + vt.cwiseAbs().maxCoeff()));
      EXPECT_LT(law, 1e-10 * (1.0 + y.segment<3>(var::n).norm()));
      if (sc.strain == RodStrain::extensible) {
        EXPECT_TRUE(v.head<2>().isZero(0.0));
      }
    }
  }
}

/// The moving mass's inertia (momentum form over the cells' space-time boxes, for
/// its line mass over [sigma - ds, sigma + ds]) on every kind of path through cell j during
/// the step: inside the cell, node to node (dt = ds / v), across a node (forwards and
/// backwards), at rest inside the cell and on its left node, across several cells in one
/// step, entering at s = 0 and leaving at L. Exact Jacobians (with the weight, gravity on)
/// against central differences; loads_touch_cell wherever the line mass is, and the load
/// block exactly zero where loads_touch_cell says no load acts.
TEST(RodKernels, MovingMassJacobiansOnEveryKindOfPath) {
  test::Rng rng;
  const StepTimes st{0.37, 0.01};
  struct Path {
    const char* name;
    int j;
    double a, b;  // sigma_old, sigma_new in cells, relative to node j-1
  };
  const std::vector<Path> paths = {{"inside", 5, 0.2, 0.7},        {"node to node", 5, 0.0, 1.0},
                                   {"across a node", 5, -0.4, 0.5}, {"backwards", 5, 0.6, -0.3},
                                   {"at rest", 5, 0.4, 0.4},        {"at rest on node j-1", 5, 0.0, 0.0},
                                   {"three cells", 5, -1.5, 1.7},   {"entering", 1, -0.3, 0.4},
                                   {"leaving", 10, 0.6, 1.4}};
  // carried: a part of the mass without weight and inertia along an axis (a sprung body);
  // strained: on a shearable rod with viscosities (the path's tangent is the strain v, which
  // reads the new level's n and v_t)
  struct Variant {
    double carried;
    bool strained;
  };
  for (const Variant var : {Variant{0.0, false}, Variant{0.2, false}, Variant{0.0, true}})
  for (const auto& pc : param_cases()) {
    const double carried = var.carried;
    for (const Path& P : paths) {
      RodModel m = test::scene_model(10, pc.alpha);
      if (var.strained) {
        m.props.C = RodProperties::compliance(RodStrain::shearable, 50.0, 20.0);  // strains of a few %
        m.props.B_se = Vec3(0.02, 0.02, 0.05);
      }
      const double ds = m.ds();
      m.loads.gravity = Vec3(0.0, -9.8, 0.0);
      const double s0 = (P.j - 1 + P.a) * ds, v = (P.b - P.a) * ds / st.dt, t0 = st.t_old;
      MovingMass M;
      M.mass = 0.3;
      M.sigma = [=](double t) { return s0 + v * (t - t0); };
      M.speed = [=](double) { return v; };
      M.accel = [](double) { return 0.0; };
      M.carried = carried;
      M.carried_axis = Vec3(0.3, 1.0, 0.2).normalized();
      m.loads.masses.push_back(M);
      // Error relative to the largest load Jacobian entry over the cells (a cell the line mass
      // only grazes has a block near zero).
      double worst = 0.0, size = 0.0, scale = 0.0;
      for (int j = std::max(1, P.j - 2); j <= std::min(10, P.j + 2); ++j) {
        const RodNode o0 = rng.node(), o1 = rng.node();
        const VecX x0 = rng.unknowns(m, o0), x1 = rng.unknowns(m, o1);
        const LocalBlock l = load_block(m, st, j, o0, o1, x0, x1);
        double lo = 0.0, hi = 0.0;
        const bool reached = line_mass_part(M.sigma(st.t_old), j, 10, ds, lo, hi) ||
                             line_mass_part(M.sigma(st.t_new()), j, 10, ds, lo, hi);
        size = std::max(size, l.residual.segment<3>(3).cwiseAbs().maxCoeff());
        EXPECT_TRUE(!reached || loads_touch_cell(m, st, j)) << P.name << " cell " << j;
        if (!loads_touch_cell(m, st, j)) {
          EXPECT_TRUE(l.residual.isZero(0.0) && l.jac[0].isZero(0.0) && l.jac[1].isZero(0.0)) << P.name << " cell " << j;
        }
        for (int q = 0; q < 2; ++q) {
          auto fl = [&](const VecX& x) {
            return load_block(m, st, j, o0, o1, q == 0 ? x : x0, q == 1 ? x : x1).residual;
          };
          const MatX num = central_jacobian(fl, q == 0 ? x0 : x1);
          worst = std::max(worst, (l.jac[q] - num).cwiseAbs().maxCoeff());
          scale = std::max(scale, num.cwiseAbs().maxCoeff());
        }
      }
      worst /= scale;
      std::printf("[%s] %s%s: load Jacobian rel err %.2e (couple rows up to %.2e)\n", pc.name, P.name,
                  carried > 0.0 ? " (part carried)" : (var.strained ? " (shearable, damped)" : ""), worst, size);
      EXPECT_LT(worst, 1e-7) << pc.name << ", " << P.name << ", carried " << carried << ", strained " << var.strained;
    }
  }
}

TEST(RodKernels, EndConditionJacobiansMatchCentralDifferences) {
  test::Rng rng;
  const StepTimes st{0.2, 0.02};
  const std::vector<std::pair<const char*, EndCondition>> ends = {
      {"clamped", EndCondition::make_clamped()},
      {"pinned", EndCondition::make_pinned(Vec3(1.0, 0.2, -0.1))},
      {"sliding", EndCondition::make_sliding(Vec3(0.1, 0.0, 1.0))},
      {"free", EndCondition::make_free()},
      {"prescribed", EndCondition::make_prescribed(
                         [](double t) { return Vec3(0.1 * t, -0.2, 0.3); },
                         [](double t) { return Vec3(0.0, 1.0 + t, -0.5); })}};
  for (const auto& pc : param_cases()) {
    for (const auto& [name, ec] : ends) {
      RodModel m = loaded_model(pc.alpha, 1, st);
      m.left = ec;
      m.right = ec;
      const RodNode o = rng.node();
      const VecX x = rng.unknowns(m, o);
      const LocalBlock L = left_block(m, st, o, x);
      const LocalBlock R = right_block(m, st, o, x);
      const double el = relative_difference(
          L.jac[0], central_jacobian([&](const VecX& z) { return left_block(m, st, o, z).residual; }, x));
      const double er = relative_difference(
          R.jac[0], central_jacobian([&](const VecX& z) { return right_block(m, st, o, z).residual; }, x));
      std::printf("[%s] %s: left (%ld rows) rel err %.2e, right rel err %.2e\n", pc.name, name,
                  static_cast<long>(L.residual.size()), el, er);
      EXPECT_LT(el, 1e-7);
      EXPECT_LT(er, 1e-7);
      EXPECT_EQ(L.residual.size(), m.carries_ys() ? 18 : 6);
      EXPECT_EQ(R.row, m.right_row());
    }
  }
}

/// Every end condition type declared for the scene (traverse/core/end_types.hpp)
/// has its entry in the rod's table: the conversion from the scene's spec, 6 dynamic rows, a
/// static reading with 6 static rows and the continuation's end load and position.
TEST(RodKernels, EveryDeclaredEndTypeHasRowsStaticRowsAndAConversion) {
  const RodProperties props = RodProperties::circular(0.005, 2.5e8, 0.25, 1500.0);
  StaticModel sm;
  sm.props = props;
  sm.num_cells = 4;
  const std::vector<StaticNode> nodes = straight_static_state(sm);
  size_t count = 0;
  for (const auto& d : end_type_declarations()) {
    EndSpec spec;
    spec.type = d.type;
    spec.velocity = Vec3(0.0, 0.1, 0.0);
    const EndCondition c = end_condition(spec);
    EXPECT_EQ(c.type, d.type) << d.word;
    EXPECT_EQ(c.num_rows(), 6) << d.word;
    Vec6 r;
    Eigen::Matrix<double, 6, 12> J;
    EXPECT_NO_THROW(end_condition_rows(c, props, 0.0, Vec12::Zero(), Mat3::Identity(), Mat3::Zero(), r, J)) << d.word;
    const EndConditionCheck check = validate_end_conditions(c, EndCondition::make_clamped());
    EXPECT_TRUE(check.ok) << d.word << ": " << check.message;
    sm.left = static_end(spec, Vec3::Zero());
    sm.right = static_end(spec, Vec3(0.0, 0.0, sm.length));
    EXPECT_EQ(sm.left.type, c.static_type()) << d.word;
    EXPECT_NO_THROW(static_left_block(sm, nodes.front())) << d.word;
    EXPECT_EQ(static_right_block(sm, nodes.back()).residual.size(), 6) << d.word;
    EXPECT_TRUE(set_end_load(sm.right, 1.0, -Vec3::UnitZ())) << d.word;
    EXPECT_NO_THROW(end_load_derivative(sm.right, nodes.back(), -Vec3::UnitZ())) << d.word;
    EXPECT_NO_THROW(end_position_derivative(sm.right, Vec3::UnitZ())) << d.word;
    std::printf("%-10s dynamic rows, static reading %s (%s), moves %d\n", d.word,
                end_type_declarations()[static_cast<size_t>(c.static_type())].word,
                end_holds_position(sm.right) ? "holds its position" : "free position", c.end_moves() ? 1 : 0);
    ++count;
  }
  EXPECT_EQ(count, static_cast<size_t>(EndType::prescribed) + 1);
  // A type outside the table is refused, not read as another one.
  EndSpec bad;
  bad.type = static_cast<EndType>(count);
  EXPECT_THROW(end_condition(bad), std::logic_error);
}

TEST(RodKernels, ValidationOfEndConditionPairs) {
  const auto c = EndCondition::make_clamped(), f = EndCondition::make_free();
  const auto p = EndCondition::make_pinned(Vec3::UnitX()), s = EndCondition::make_sliding(Vec3::UnitZ());
  EXPECT_TRUE(validate_end_conditions(c, f).ok);
  EXPECT_TRUE(validate_end_conditions(p, p).ok);
  EXPECT_TRUE(validate_end_conditions(c, s).ok);
  EXPECT_TRUE(validate_end_conditions(f, f).ok);
  EndCondition bad = EndCondition::make_pinned(Vec3::Zero());
  const auto r1 = validate_end_conditions(c, bad);
  EXPECT_FALSE(r1.ok);
  std::printf("zero pin axis: %s\n", r1.message.c_str());
  EndCondition nofun;
  nofun.type = EndCondition::Type::prescribed;
  const auto r2 = validate_end_conditions(nofun, c);
  EXPECT_FALSE(r2.ok);
  std::printf("prescribed without functions: %s\n", r2.message.c_str());
}

TEST(RodKernels, LayoutCountsRowsAndUnknowns) {
  for (const auto& pc : param_cases()) {
    const RodModel m = test::scene_model(7, pc.alpha);
    Eigen::Index rows = 0;
    for (int j = 0; j <= m.num_cells; ++j) {
      EXPECT_EQ(m.node_first_row(j), rows);
      rows += m.node_row_count(j);
    }
    EXPECT_EQ(rows, m.num_unknowns());
    EXPECT_EQ(m.right_row() + 6, m.num_unknowns());
    std::printf("[%s] %d unknowns per node, %ld rows for N = 7\n", pc.name,
                m.unknowns_per_node(), static_cast<long>(rows));
  }
}

TEST(RodKernels, FrameInvariance) {
  test::Rng rng;
  const StepTimes st{0.37, 0.01};
  const Mat3 Q = so3::exp(Vec3(0.3, -1.1, 0.7));
  for (const auto& pc : param_cases()) {
    const int j = 4;
    RodModel a = loaded_model(pc.alpha, j, st);
    a.left = EndCondition::make_pinned(Vec3(1.0, 0.2, -0.1));
    a.right = EndCondition::make_prescribed([](double t) { return Vec3(0.1 * t, -0.2, 0.3); },
                                            [](double t) { return Vec3(0.0, 1.0 + t, -0.5); });
    RodModel b = a;
    b.loads.gravity = Q * a.loads.gravity;
    b.loads.f_fixed = [f = a.loads.f_fixed, Q](double s, double t) { return Vec3(Q * f(s, t)); };
    b.loads.l_fixed = [f = a.loads.l_fixed, Q](double s, double t) { return Vec3(Q * f(s, t)); };
    b.loads.point_forces[0].force_fixed = [f = a.loads.point_forces[0].force_fixed, Q](double t) {
      return Vec3(Q * f(t));
    };
    b.left.axis = Q * a.left.axis;
    b.right.u_fixed = [f = a.right.u_fixed, Q](double t) { return Vec3(Q * f(t)); };
    b.right.omega_fixed = [f = a.right.omega_fixed, Q](double t) { return Vec3(Q * f(t)); };
    RodNode o0 = rng.node(), o1 = rng.node();
    const VecX x0 = rng.unknowns(a, o0), x1 = rng.unknowns(a, o1);
    RodNode q0 = o0, q1 = o1;
    q0.R = o0.R * Q.transpose();
    q1.R = o1.R * Q.transpose();
    const VecX ra = cell_block(a, st, j, o0, o1, x0, x1).residual;
    const VecX rb = cell_block(b, st, j, q0, q1, x0, x1).residual;
    const double ec = (ra - rb).cwiseAbs().maxCoeff() / ra.cwiseAbs().maxCoeff();
    const VecX la = left_block(a, st, o0, x0).residual, lb = left_block(b, st, q0, x0).residual;
    const VecX ha = right_block(a, st, o1, x1).residual, hb = right_block(b, st, q1, x1).residual;
    // The pinned rows 3, 4 use a fixed-frame basis (b1, b2) perpendicular to the axis,
    // chosen from the axis alone, so under a frame rotation they change by a rotation
    // within the pair: compare rows 0-2 and 5 (and the remaining collocation rows) exactly
    // and the pair by its norm.
    VecX la2 = la, lb2 = lb;
    la2(3) = la.segment<2>(3).norm();
    lb2(3) = lb.segment<2>(3).norm();
    la2(4) = lb2(4) = 0.0;
    const double el = (la2 - lb2).cwiseAbs().maxCoeff() / la2.cwiseAbs().maxCoeff();
    const double er = (ha - hb).cwiseAbs().maxCoeff() / ha.cwiseAbs().maxCoeff();
    std::printf("[%s] frame invariance: cell %.2e, left (pinned) %.2e, right (prescribed) %.2e\n",
                pc.name, ec, el, er);
    EXPECT_LT(ec, 1e-13);
    EXPECT_LT(el, 1e-13);
    EXPECT_LT(er, 1e-13);
  }
}

/// A scene without gravity computes no gravity terms. The model says so
/// (has_gravity, has_frame_loads, NodeFlux::frame_loads), and skipping them changes nothing:
/// the same model with a distributed force that is identically zero (which forces the general
/// path: R f and its frame sensitivity formed and added) gives exactly the same residuals and
/// Jacobians - cells with a moving mass and a point force, both ends.
TEST(RodKernels, ZeroGravityComputesNoGravityTermsAndMatchesTheGeneralPath) {
  test::Rng rng;
  const StepTimes st{0.37, 0.01};
  for (const auto& pc : param_cases()) {
    const int j = 5;
    RodModel bare = loaded_model(pc.alpha, j, st);  // point force and moving mass in cell j
    bare.loads.gravity = Vec3::Zero();
    bare.loads.f_fixed = nullptr;
    bare.loads.l_fixed = nullptr;
    RodModel general = bare;
    general.loads.f_fixed = [](double, double) { return Vec3(Vec3::Zero()); };
    RodModel heavy = bare;
    heavy.loads.gravity = Vec3(0.0, -9.8, 0.0);

    EXPECT_FALSE(bare.loads.has_gravity());
    EXPECT_FALSE(bare.loads.has_frame_loads());
    EXPECT_TRUE(general.loads.has_frame_loads());
    EXPECT_TRUE(heavy.loads.has_gravity());
    EXPECT_TRUE(heavy.loads.has_frame_loads());

    const RodNode o0 = rng.node(), o1 = rng.node();
    const VecX x0 = rng.unknowns(bare, o0), x1 = rng.unknowns(bare, o1);
    const NodeFlux fb = node_flux(bare, o0.y, o0.R, 0.3, 0.2);
    const NodeFlux fg = node_flux(general, o0.y, o0.R, 0.3, 0.2);
    const NodeFlux fh = node_flux(heavy, o0.y, o0.R, 0.3, 0.2);
    EXPECT_FALSE(fb.frame_loads);
    EXPECT_TRUE(fg.frame_loads);
    EXPECT_TRUE(fh.frame_loads);
    EXPECT_TRUE(fb.dF_dRrot.isZero(0.0));
    EXPECT_GT(fh.dF_dRrot.cwiseAbs().maxCoeff(), 0.0);
    EXPECT_TRUE(fb.F == fg.F);
    EXPECT_TRUE(fb.dF_dy == fg.dF_dy);
    EXPECT_FALSE(fb.F == fh.F);

    auto same = [](const LocalBlock& a, const LocalBlock& b) {
      if (a.row != b.row || a.cols != b.cols || a.jac.size() != b.jac.size() || !(a.residual == b.residual))
        return false;
      for (size_t k = 0; k < a.jac.size(); ++k)
        if (!(a.jac[k] == b.jac[k])) return false;
      return true;
    };
    const LocalBlock cb = cell_block(bare, st, j, o0, o1, x0, x1);
    EXPECT_TRUE(same(cb, cell_block(general, st, j, o0, o1, x0, x1))) << pc.name;
    EXPECT_TRUE(same(left_block(bare, st, o0, x0), left_block(general, st, o0, x0))) << pc.name;
    EXPECT_TRUE(same(right_block(bare, st, o1, x1), right_block(general, st, o1, x1))) << pc.name;
    // Gravity does enter when present (the moving mass's weight and the rod's own).
    EXPECT_FALSE(cb.residual == cell_block(heavy, st, j, o0, o1, x0, x1).residual);
    EXPECT_GT(load_block(heavy, st, j, o0, o1, x0, x1).residual.cwiseAbs().maxCoeff(), 0.0);

    // The planar path's in-plane kernel forms the rod's weight only (its frame-load term is
    // skipped without gravity): distributed loads given as functions are refused.
    PlanarSymmetry sym;  // the end rows do not matter for a cell
    sym.axis = 0;
    sym.left_rows = sym.right_rows = {{1, 2, 3}};
    EXPECT_NO_THROW(PlanarReduction(bare, sym));
    EXPECT_THROW(PlanarReduction(general, sym), std::invalid_argument);
  }
}

/// The static cell without gravity: no gravity terms, and exactly the gravity cell minus its
/// gravity contribution (-rhoA/2 (R_{j-1} + R_j) g in the force rows, +rhoA/2 hat(R g) D in
/// their theta columns, which do not change otherwise).
TEST(RodKernels, StaticCellWithoutGravityIsTheGravityCellMinusItsWeight) {
  test::Rng rng;
  StaticModel m;
  m.props = RodProperties::scene_rod();
  m.num_cells = 10;
  m.length = 1.0;
  m.point_forces.push_back({Vec3(0.1, -0.5, 0.2), 0.43});
  StaticModel g = m;
  g.gravity = Vec3(0.0, -9.8, 0.0);
  StaticNode a, b;
  a.x = rng.y();
  b.x = rng.y();
  a.x.segment<3>(svar::theta) = rng.vec3(0.3);
  b.x.segment<3>(svar::theta) = rng.vec3(0.3);
  a.Rbar = rng.rotation();
  b.Rbar = rng.rotation();
  const int j = 5;
  const LocalBlock c0 = static_cell_block(m, j, a, b), cg = static_cell_block(g, j, a, b);
  const Vec3 weight = 0.5 * m.props.rhoA * (a.frame() * g.gravity + b.frame() * g.gravity);
  const VecX d = cg.residual - c0.residual;
  EXPECT_LT((d.head<3>() + weight).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + weight.norm()));
  EXPECT_TRUE(d.tail<9>().isZero(0.0));
  for (int q = 0; q < 2; ++q) {
    MatX dj = cg.jac[static_cast<size_t>(q)] - c0.jac[static_cast<size_t>(q)];
    const double dtheta = dj.block<3, 3>(0, svar::theta).cwiseAbs().maxCoeff();
    EXPECT_GT(dtheta, 0.0);
    dj.block<3, 3>(0, svar::theta).setZero();
    EXPECT_TRUE(dj.isZero(0.0));
  }
}

// advance_node keeps the step's secant yv = (y_new - y_old) / dt (Newton's initial guess of
// the next step extrapolates along it); pack_node / unpack_node carry every member.
TEST(RodKernels, AdvanceNodeKeepsTheSecantAndPackingRoundTrips) {
  RodModel m;
  m.props = RodProperties::scene_rod();
  m.num_cells = 4;
  RodNode old;
  VecX x(12);
  const double dt = 0.002;
  // The old slope predicts the change d of each entry as dt yv_old = c d: exactly (c = 1),
  // within half of it (1.4, 0.6), not within half (1.6, 0.4), with the wrong sign (-1), not at
  // all (0). The blend extrapolates the first three.
  const double c[12] = {1.0, 1.4, 0.6, 1.6, 0.4, -1.0, 0.0, 1.0, 1.45, 0.55, 1.55, 0.45};
  for (int i = 0; i < 12; ++i) {
    old.y(i) = 0.1 * (i + 1);
    old.yt(i) = -0.05 * i;
    const double d = 0.003 * (i - 5.5);
    x(i) = old.y(i) + d;
    old.yv(i) = c[i] * d / dt;  // the slope of the step before: replaced
  }
  const RodNode n = advance_node(m, old, x, dt);
  for (int i = 0; i < 12; ++i) {
    const double yv = 0.003 * (i - 5.5) / dt;
    EXPECT_NEAR(n.yv(i), yv, 1e-12) << i;
    const bool within_half = std::abs(c[i] - 1.0) < 0.5;
    EXPECT_EQ(n.yg(i), within_half ? n.yv(i) : 0.0) << i << " (c = " << c[i] << ")";
  }
  RodNode with_kst = n;
  with_kst.kst = Vec3(0.5, -1.5, 2.5);
  double packed[kPackedNodeValues];
  pack_node(with_kst, packed);
  const RodNode back = unpack_node(packed);
  EXPECT_EQ(back.kst, with_kst.kst);
  EXPECT_EQ(back.y, n.y);
  EXPECT_EQ(back.R, n.R);
  EXPECT_EQ(back.yt, n.yt);
  EXPECT_EQ(back.ys, n.ys);
  EXPECT_EQ(back.yv, n.yv);
  EXPECT_EQ(back.yg, n.yg);
  EXPECT_NE(n.yg, Vec12::Zero());  // the round trip carries a non-trivial blend
}

/// Random old nodes and new unknowns at every node of m.
void random_levels(test::Rng& rng, const RodModel& m, std::vector<RodNode>& old, std::vector<VecX>& x) {
  for (int j = 0; j <= m.num_cells; ++j) {
    old.push_back(rng.node());
    x.push_back(rng.unknowns(m, old.back()));
  }
}

TEST(RodKernels, AssembleNodesOnARangeMatchesWholeRod) {
  test::Rng rng;
  const StepTimes st{0.37, 0.01};
  for (const auto& pc : param_cases()) {
    const RodModel m = loaded_model(pc.alpha, 6, st);
    std::vector<RodNode> old;
    std::vector<VecX> x;
    random_levels(rng, m, old, x);
    const auto whole = assemble_nodes(m, st, 0, m.num_cells, 0, old, x);
    // Nodes 4..7 with one ghost on each side: nodes 3..8.
    std::vector<RodNode> o2(old.begin() + 3, old.begin() + 9);
    std::vector<VecX> x2(x.begin() + 3, x.begin() + 9);
    const auto part = assemble_nodes(m, st, 4, 7, 3, o2, x2);
    ASSERT_EQ(part.size(), 4u);
    double e = 0.0;
    for (const auto& b : part)
      for (const auto& w : whole)
        if (w.row == b.row) e = std::max(e, (w.residual - b.residual).cwiseAbs().maxCoeff());
    std::printf("[%s] range assembly difference %.1e\n", pc.name, e);
    EXPECT_EQ(e, 0.0);
  }
}

TEST(RodKernels, ResidualAloneIsTheSameResidual) {
  // The time step evaluates the residual alone where no Jacobian is wanted: the same bits as
  // the residual of the full cell block, with loads on the cell or not, and no Jacobian.
  test::Rng rng;
  const StepTimes st{0.37, 0.01};
  for (const auto& pc : param_cases()) {
    const RodModel m = loaded_model(pc.alpha, 6, st);
    std::vector<RodNode> old;
    std::vector<VecX> x;
    random_levels(rng, m, old, x);
    // The levels with their Jacobians (for the full block) and without (for the residual alone).
    std::vector<NodeLevels> lv(static_cast<size_t>(m.num_cells + 1)), lr(lv.size());
    for (int j = 0; j <= m.num_cells; ++j) {
      const auto J = static_cast<size_t>(j);
      new_level_quantities(m, st, j, old[J], x[J], lv[J]);
      new_level_quantities(m, st, j, old[J], x[J], lr[J], false);
      lv[J].F_old = lr[J].F_old = old_level_flux(m, st, j, old[J]);
    }
    int touched = 0;
    for (int j = 1; j <= m.num_cells; ++j) {
      const auto J = static_cast<size_t>(j);
      const bool loads = loads_touch_cell(m, st, j);
      touched += loads ? 1 : 0;
      LocalBlock full, alone;
      cell_block_into(full, m, st, j, old[J - 1], old[J], x[J - 1], x[J], lv[J - 1], lv[J], loads, true);
      cell_block_into(alone, m, st, j, old[J - 1], old[J], x[J - 1], x[J], lr[J - 1], lr[J], loads, false);
      ASSERT_EQ(full.residual.size(), alone.residual.size());
      EXPECT_EQ((full.residual - alone.residual).cwiseAbs().maxCoeff(), 0.0) << pc.name << ", cell " << j;
      EXPECT_GT(full.jac[0].cwiseAbs().maxCoeff(), 0.0);
      EXPECT_EQ(alone.jac[0].cwiseAbs().maxCoeff() + alone.jac[1].cwiseAbs().maxCoeff(), 0.0);
    }
    EXPECT_GE(touched, 1) << pc.name << ": no cell carries the moving loads";
  }
}

TEST(RodKernels, CellsTouchedByLoadsAreTheCellsThatLoadsTouch) {
  // The cells found from the loads' positions are those loads_touch_cell finds visiting every
  // cell: loads inside the rod, at its ends, off it, a mass crossing several cells in a step
  // (its inertia's path), over the whole rod and over a piece of it (a rank's cells).
  const double dt = 0.01;
  int touched = 0;
  for (double s0 : {-0.3, 0.0, 0.013, 0.27, 0.5, 0.96, 1.0, 1.4})
    for (double cells_per_step : {0.0, 0.4, 3.5, -2.2})
      for (bool inertia : {true, false}) {
        const StepTimes st{0.37, dt};
        RodModel m = test::scene_model(40, AlphaParameters{});
        const double ds = m.ds(), v = cells_per_step * ds / dt, t0 = st.t_old;
        PointForce P;
        P.force_fixed = [](double) { return Vec3(0.0, -1.0, 0.0); };
        P.sigma = [=](double t) { return s0 + v * (t - t0); };
        m.loads.point_forces.push_back(P);
        MovingMass M;
        M.mass = 0.2;
        M.inertia = inertia;
        M.sigma = [=](double t) { return 1.0 - s0 - 0.7 * v * (t - t0); };
        M.speed = [=](double) { return -0.7 * v; };
        M.accel = [](double) { return 0.0; };
        m.loads.masses.push_back(M);
        for (const auto& [c0, c1] : {std::pair{1, 40}, std::pair{7, 19}, std::pair{0, 3}}) {
          std::vector<int> all;
          for (int j = std::max(c0, 1); j <= c1; ++j)
            if (loads_touch_cell(m, st, j)) all.push_back(j);
          EXPECT_EQ(cells_touched_by_loads(m, st, c0, c1), all) << "s0 = " << s0 << ", " << cells_per_step
                                                                << " cells per step, cells " << c0 << ".." << c1;
          touched += static_cast<int>(all.size());
        }
      }
  EXPECT_GT(touched, 100);  // the cases do reach cells
}

}  // namespace
}  // namespace traverse::rod

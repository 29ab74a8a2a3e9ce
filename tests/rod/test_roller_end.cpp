// The roller end (pin about a, sliding along e, n . e held): dynamic rows and their exact
// Jacobian, validation, and the static rows' Jacobian, against central differences.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "../rod/rod_test_util.hpp"
#include "traverse/rod/static_kernels.hpp"

namespace traverse::rod {
namespace {

TEST(RollerEnd, DynamicRowsJacobianMatchesCentralDifferences) {
  test::Rng rng;
  const StepTimes st{0.2, 0.02};
  for (const auto& alpha : {AlphaParameters{}, AlphaParameters::from_rho_inf(0.8, 0.7)}) {
    RodModel m = test::scene_model(10, alpha);
    m.left = EndCondition::make_roller(Vec3(1.0, 0.2, -0.1), Vec3(0.1, 0.0, 1.0), 0.7);
    m.right = EndCondition::make_roller(Vec3::UnitX(), Vec3::UnitZ(), -1.3);
    const RodNode o = rng.node();
    const VecX x = rng.unknowns(m, o);
    const LocalBlock L = left_block(m, st, o, x), R = right_block(m, st, o, x);
    const double el = test::relative_difference(
        L.jac[0], test::central_jacobian([&](const VecX& z) { return left_block(m, st, o, z).residual; }, x));
    const double er = test::relative_difference(
        R.jac[0], test::central_jacobian([&](const VecX& z) { return right_block(m, st, o, z).residual; }, x));
    std::printf("  roller (%s): left rel err %.2e, right rel err %.2e\n", m.carries_ys() ? "carried ys" : "box", el, er);
    EXPECT_LT(el, 1e-7);
    EXPECT_LT(er, 1e-7);
  }
}

TEST(RollerEnd, ValidationAcceptsRollerAndRejectsZeroAxes) {
  const auto r = EndCondition::make_roller(Vec3::UnitX(), Vec3::UnitZ(), 1.0);
  EXPECT_TRUE(validate_end_conditions(EndCondition::make_pinned(Vec3::UnitX()), r).ok);
  EXPECT_TRUE(validate_end_conditions(r, EndCondition::make_clamped()).ok);
  const auto bad_pin = validate_end_conditions(EndCondition::make_roller(Vec3::Zero(), Vec3::UnitZ()), r);
  EXPECT_FALSE(bad_pin.ok);
  EXPECT_NE(bad_pin.message.find("zero axis"), std::string::npos) << bad_pin.message;
  const auto bad_slide = validate_end_conditions(r, EndCondition::make_roller(Vec3::UnitX(), Vec3::Zero()));
  EXPECT_FALSE(bad_slide.ok);
  EXPECT_NE(bad_slide.message.find("right end: zero slide axis"), std::string::npos) << bad_slide.message;
  std::printf("  messages: '%s', '%s'\n", bad_pin.message.c_str(), bad_slide.message.c_str());
}

TEST(RollerEnd, StaticRowsJacobianMatchesCentralDifferences) {
  StaticModel m;
  m.props = RodProperties::scene_rod();
  m.num_cells = 4;
  for (StaticEnd* e : {&m.left, &m.right}) {
    e->type = EndCondition::Type::roller;
    e->axis = Vec3(1.0, 0.3, -0.2);
    e->slide_axis = Vec3(0.1, -0.2, 1.0);
    e->position = Vec3(0.1, 0.2, 0.9);
    e->frame = so3::exp(Vec3(0.2, -0.4, 0.3));
    e->axial_force = 0.8;
  }
  std::mt19937 g(7);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  StaticNode node;
  for (int i = 0; i < 12; ++i) node.x(i) = 0.4 * d(g);
  node.Rbar = so3::exp(Vec3(d(g), d(g), d(g)));
  for (int side = 0; side < 2; ++side) {
    auto f = [&](const StaticNode& n) { return side == 0 ? static_left_block(m, n) : static_right_block(m, n); };
    const LocalBlock b = f(node);
    MatX fd(6, 12);
    for (int c = 0; c < 12; ++c) {
      StaticNode p = node, q = node;
      p.x(c) += 1e-6;
      q.x(c) -= 1e-6;
      fd.col(c) = (f(p).residual - f(q).residual) / 2e-6;
    }
    const double err = test::relative_difference(b.jac[0], fd);
    std::printf("  static roller %s: rel err %.2e\n", side == 0 ? "left" : "right", err);
    EXPECT_LT(err, 1e-7);
  }
}

TEST(RollerEnd, StaticMassBlockIsTheLinearisedInertia) {
  // At theta = 0 the moment-row inertia is rhoI / 2 per node and the force-row inertia
  // rhoA R / 2 (u = R r').
  StaticModel m;
  m.props = RodProperties::scene_rod();
  m.num_cells = 3;
  StaticNode a, b;
  a.Rbar = so3::exp(Vec3(0.3, 0.1, -0.2));
  b.Rbar = so3::exp(Vec3(-0.1, 0.4, 0.2));
  const LocalBlock M = static_mass_block(m, 2, a, b);
  EXPECT_EQ(M.row, 6 + 12);
  EXPECT_LT((M.jac[0].block<3, 3>(0, svar::r) - 0.5 * m.props.rhoA * a.Rbar).norm(), 1e-15);
  EXPECT_LT((M.jac[1].block<3, 3>(3, svar::theta) - 0.5 * Mat3(m.props.rhoI.asDiagonal())).norm(), 1e-15);
  EXPECT_EQ(M.jac[0].bottomRows(6).norm(), 0.0);
}

}  // namespace
}  // namespace traverse::rod

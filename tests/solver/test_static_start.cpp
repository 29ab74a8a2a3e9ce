// The static initial state solved over the ranks (solver/static_start.hpp: load steps of NOX
// Newton solves) on 1, 2 and 3 ranks against the serial sparse-LU solve of the whole rod
// (reference_statics.hpp: its own Newton with the same tests and load steps, so the same
// load steps and iterations): each rank's nodes with their two-node halo, the linear solver
// chosen from the left end, the fallback when the block LU does not apply, large rotations.
#include <gtest/gtest.h>

#include <Teuchos_CommHelpers.hpp>

#include <algorithm>
#include <cmath>

#include "rod_mpi_test_util.hpp"
#include "reference_statics.hpp"
#include "traverse/rod/static_load_steps.hpp"
#include "traverse/solver/static_start.hpp"

namespace traverse::solver {
namespace {

using test::say;

rod::StaticModel cable(int N, rod::EndCondition::Type left) {
  rod::StaticModel m;
  m.props = rod::RodProperties::scene_rod();
  m.num_cells = N;
  m.length = 1.0;
  m.left.type = left;
  m.left.axis = Vec3::UnitX();
  m.right.type = rod::EndCondition::Type::sliding;
  m.right.axis = Vec3::UnitZ();
  m.right.position = Vec3(0.0, 0.0, 1.0);
  m.gravity = Vec3(0.0, -9.8, 0.0);
  m.point_forces.push_back({Vec3(0.0, -2.0, 0.0), 0.37});
  return m;
}

struct Agreement {
  double r = 0.0, kappa = 0.0, n = 0.0, frame = 0.0;  // max |difference|
};

// This rank's nodes against the same nodes of the serial solution (max over the ranks).
Agreement against_serial(const StaticStart& st, const std::vector<rod::StaticNode>& serial) {
  Agreement a;
  for (size_t k = 0; k < st.nodes.size(); ++k) {
    const rod::StaticNode& x = st.nodes[k];
    const rod::StaticNode& y = serial[static_cast<size_t>(st.first_node) + k];
    auto d = [&](int v) { return (x.x.segment<3>(v) - y.x.segment<3>(v)).cwiseAbs().maxCoeff(); };
    a.r = std::max(a.r, d(rod::svar::r));
    a.kappa = std::max(a.kappa, d(rod::svar::kappa));
    a.n = std::max(a.n, d(rod::svar::n));
    a.frame = std::max(a.frame, (x.frame() - y.frame()).cwiseAbs().maxCoeff());
  }
  double mine[4] = {a.r, a.kappa, a.n, a.frame}, all[4];
  Teuchos::reduceAll<int, double>(*test::comm(), Teuchos::REDUCE_MAX, 4, mine, all);
  return {all[0], all[1], all[2], all[3]};
}

// The halo: this rank's nodes and two more on each side where the rod has them.
void expect_halo(const StaticStart& st, int N) {
  const int P = test::ranks(), r = test::comm()->getRank();
  ASSERT_FALSE(st.nodes.empty());
  const int last = st.first_node + static_cast<int>(st.nodes.size()) - 1;
  EXPECT_EQ(st.first_node == 0, r == 0) << "rank " << r << " of " << P;
  EXPECT_EQ(last == N, r == P - 1) << "rank " << r << " of " << P;
}

// The same model solved serially (the reference on the whole rod) and over the ranks.
struct Solved {
  rod::StaticReport serial;
  StaticStart start;
  Agreement agreement;
};
Solved solve_both(const rod::StaticModel& m) {
  Solved out;
  auto serial = rod::straight_static_state(m);
  out.serial = rod::serial_load_steps(m, serial);
  out.start = solve_static_start(m, test::comm());
  if (out.serial.converged && out.start.report.converged) out.agreement = against_serial(out.start, serial);
  return out;
}

TEST(StaticStart, ClampedCableEqualsTheSerialSolveWithTheBlockLU) {
  const int N = 60;
  const rod::StaticModel m = cable(N, rod::EndCondition::Type::clamped);
  const Solved both = solve_both(m);
  ASSERT_TRUE(both.serial.converged) << both.serial.message;
  ASSERT_TRUE(both.start.report.converged) << both.start.report.message;
  const rod::StaticReport& ser = both.serial;
  const StaticStart& st = both.start;
  const Agreement& a = both.agreement;
  say("  clamped cable, %d rank(s), %s: %d load steps, %d Newton iterations (serial %d, %d); max |dr| %.2e m, "
      "|dkappa| %.2e 1/m, |dn| %.2e N, |dR| %.2e\n",
      test::ranks(), st.linear_solver.c_str(), st.report.load_steps, st.report.iterations, ser.load_steps,
      ser.iterations, a.r, a.kappa, a.n, a.frame);
  EXPECT_NE(st.linear_solver.find("block-tridiagonal LU"), std::string::npos) << st.linear_solver;
  EXPECT_TRUE(st.first_failure.empty()) << st.first_failure;
  EXPECT_EQ(st.report.load_steps, ser.load_steps);
  EXPECT_EQ(st.report.iterations, ser.iterations);
  // Both converge to a residual of 1e-9 of the load scale; rounding differs (another LU).
  EXPECT_LT(a.r, 1e-12);
  EXPECT_LT(a.kappa, 1e-10);
  EXPECT_LT(a.n, 1e-10);
  EXPECT_LT(a.frame, 1e-12);
  expect_halo(st, N);
}

// Eliminated from the left, a pinned end leaves each piece of the rod free to turn about the
// pin (a singular Schur complement): the block LU factorises the rod clamped there and corrects
// each solve exactly for the end's own rows (Woodbury), on any number of ranks, and reaches the
// serial solve's state (KLU2 on one rank) with its iterations.
TEST(StaticStart, PinnedLeftEndIsFactorisedClampedAndCorrected) {
  const int N = 40;
  const rod::StaticModel m = cable(N, rod::EndCondition::Type::pinned);
  const Solved both = solve_both(m);
  ASSERT_TRUE(both.serial.converged) << both.serial.message;
  ASSERT_TRUE(both.start.report.converged) << both.start.report.message;
  const rod::StaticReport& ser = both.serial;
  const StaticStart& st = both.start;
  const Agreement& a = both.agreement;
  say("  pinned-sliding cable, %d rank(s), %s: %d Newton iterations (serial %d); max |dr| %.2e m\n", test::ranks(),
      st.linear_solver.c_str(), st.report.iterations, ser.iterations, a.r);
  EXPECT_NE(st.linear_solver.find("block-tridiagonal LU"), std::string::npos) << st.linear_solver;
  EXPECT_NE(st.linear_solver.find("left end clamped and corrected"), std::string::npos) << st.linear_solver;
  EXPECT_TRUE(st.first_failure.empty()) << st.first_failure;
  EXPECT_EQ(st.report.iterations, ser.iterations);
  EXPECT_LT(a.r, 1e-12);
  EXPECT_LT(a.kappa, 1e-10);
  EXPECT_LT(a.n, 1e-10);
  EXPECT_LT(a.frame, 1e-12);
  expect_halo(st, N);
}

// A soft cantilever under its weight (q L^3 / EI = 40) turns from straight through nearly a
// right angle at its tip in one load step. The frames stay fixed within a Newton solve
// (rebased only after it converges), so the tip's rotation unknowns grow to about 1.5 rad; the
// solve still converges, to the serial reference's state and with its iterations.
TEST(StaticStart, ASoftCantileverTurnsThroughNearlyARightAngle) {
  const int N = 40;
  rod::StaticModel m = cable(N, rod::EndCondition::Type::clamped);
  m.right.type = rod::EndCondition::Type::free;
  m.point_forces.clear();
  m.gravity = Vec3(0.0, -40.0 * m.props.K(0) / m.props.rhoA, 0.0);  // L = 1
  const Solved both = solve_both(m);
  ASSERT_TRUE(both.serial.converged) << both.serial.message;
  ASSERT_TRUE(both.start.report.converged) << both.start.report.message;
  const StaticStart& st = both.start;
  double angle = 0.0;  // of the last cell's chord from the straight rod's axis k [deg]
  if (st.first_node + static_cast<int>(st.nodes.size()) - 1 == N) {
    const Vec3 d = st.nodes.back().x.segment<3>(rod::svar::r) - st.nodes[st.nodes.size() - 2].x.segment<3>(rod::svar::r);
    angle = std::acos(d.normalized().z()) * 180.0 / M_PI;
  }
  double tip = 0.0;
  Teuchos::reduceAll<int, double>(*test::comm(), Teuchos::REDUCE_MAX, angle, Teuchos::outArg(tip));
  say("  soft cantilever, %d rank(s): tip turned %.1f deg; %d load steps, %d Newton iterations (serial %d, %d); "
      "max |dr| %.2e m\n",
      test::ranks(), tip, st.report.load_steps, st.report.iterations, both.serial.load_steps, both.serial.iterations,
      both.agreement.r);
  EXPECT_GT(tip, 80.0);
  EXPECT_LT(tip, 90.0);
  EXPECT_EQ(st.report.load_steps, 1);
  EXPECT_EQ(st.report.load_steps, both.serial.load_steps);
  EXPECT_EQ(st.report.iterations, both.serial.iterations);
  EXPECT_LT(both.agreement.r, 1e-12);
  EXPECT_LT(both.agreement.frame, 1e-12);
}

// A load the rod cannot carry: the same failure report on every rank, no nodes.
TEST(StaticStart, AFailedSolveReportsHowFarTheLoadSteppingGot) {
  rod::StaticModel m = cable(20, rod::EndCondition::Type::clamped);
  m.right.type = rod::EndCondition::Type::free;
  m.point_forces[0] = {Vec3(0.0, -1e9, 0.0), 1.0};
  const StaticStart st = solve_static_start(m, test::comm());
  EXPECT_FALSE(st.report.converged);
  EXPECT_TRUE(st.nodes.empty());
  EXPECT_FALSE(st.report.message.empty());
  EXPECT_LT(st.report.load_factor, 1.0);
  int mine = st.report.load_steps, lo = 0, hi = 0;
  Teuchos::reduceAll<int, int>(*test::comm(), Teuchos::REDUCE_MIN, 1, &mine, &lo);
  Teuchos::reduceAll<int, int>(*test::comm(), Teuchos::REDUCE_MAX, 1, &mine, &hi);
  EXPECT_EQ(lo, hi);
  say("  a 1e9 N tip load: %s\n", st.report.message.c_str());
}

}  // namespace
}  // namespace traverse::solver

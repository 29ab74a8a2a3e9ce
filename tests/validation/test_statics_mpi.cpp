// The same continuation answers on 1 and 2 ranks: Euler pitchfork at N = 20 and a branch-
// switched elastica point, against values computed on 1 rank (the serial reference).
#include <gtest/gtest.h>

#include <Tpetra_Core.hpp>
#include <cmath>
#include <cstdio>

#include "statics_test_util.hpp"
#include "traverse/rod/static_solver.hpp"
#include "traverse/solver/static_continuation.hpp"

using namespace traverse;

TEST(StaticsMpi, SameAnswersOnOneAndTwoRanks) {
  auto comm = Tpetra::getDefaultComm();
  const auto pr = statics_test::pinned_roller(20);
  const double PE = M_PI * M_PI * statics_test::bending_stiffness(pr);
  solver::ContinuationOptions o;
  o.parameter = rod::StaticParameter::end_load;
  o.max_value = 1.05 * PE;
  o.initial_step = 0.2 * PE;
  o.max_step = 0.3 * PE;
  const auto res = solver::continue_(pr, rod::straight_static_state(pr.base), o, comm);
  ASSERT_EQ(res.bifurcations.size(), 1u);
  const double Pstar = res.bifurcations[0].parameter;
  const double Pstar_1rank = 1.216180938363;  // measured on 1 rank
  o.max_value = 1.15 * PE;
  o.min_value = 0.5 * PE;
  o.initial_step = 0.02 * PE;
  o.max_step = 0.05 * PE;
  o.stability.enabled = false;
  o.probes = {rod::probe_position(0.5, 1, "mid_y")};
  const auto br = solver::switch_branch(pr, res.bifurcations[0], 0.05, o, comm);
  ASSERT_TRUE(br.completed) << br.message;
  const double w = br.points.back().probes[0];
  if (comm->getRank() == 0)
    std::printf("  branch: %s, %zu points, last P/P_E = %.12f\n", br.message.c_str(), br.points.size(), br.points.back().parameter / PE);
  const double w_1rank = 0.2897410356;  // measured on 1 rank
  if (comm->getRank() == 0)
    std::printf("  %d rank(s): P* = %.12f N (1 rank %.12f), w(P = 1.15 P_E) = %.10f m (1 rank %.10f)\n",
                comm->getSize(), Pstar, Pstar_1rank, w, w_1rank);
  EXPECT_NEAR(Pstar, Pstar_1rank, 1e-8);
  EXPECT_NEAR(br.points.back().parameter, 1.15 * PE, 1e-12);
  EXPECT_NEAR(w, w_1rank, 1e-8);
}

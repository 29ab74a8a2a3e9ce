// The same continuation answers on every rank count: Euler pitchfork at N = 20 and a branch-
// switched elastica point, on all ranks of the run against the same continuation on this
// process alone (MPI_COMM_SELF: the serial reference, computed in the same run).
#include <gtest/gtest.h>

#include <Teuchos_DefaultMpiComm.hpp>
#include <Tpetra_Core.hpp>
#include <cmath>
#include <cstdio>

#include "statics_test_util.hpp"
#include "traverse/rod/static_load_steps.hpp"
#include "traverse/solver/static_continuation.hpp"

using namespace traverse;

namespace {

struct Answers {
  double Pstar = 0.0, P_last = 0.0, w = 0.0;
  std::size_t bifurcations = 0;
  bool completed = false;
  std::string message;
};

// The pitchfork of the pinned-roller column (N = 20) and the buckled branch to 1.15 P_E.
Answers continuation_answers(const solver::Comm& comm) {
  Answers a;
  const auto pr = statics_test::pinned_roller(20);
  const double PE = M_PI * M_PI * statics_test::bending_stiffness(pr);
  solver::ContinuationOptions o;
  o.parameter = rod::StaticParameter::end_load;
  o.max_value = 1.05 * PE;
  o.initial_step = 0.2 * PE;
  o.max_step = 0.3 * PE;
  const auto res = solver::continue_(pr, rod::straight_static_state(pr.base), o, comm);
  a.bifurcations = res.bifurcations.size();
  if (a.bifurcations != 1) return a;
  a.Pstar = res.bifurcations[0].parameter;
  o.max_value = 1.15 * PE;
  o.min_value = 0.5 * PE;
  o.initial_step = 0.02 * PE;
  o.max_step = 0.05 * PE;
  o.stability.enabled = false;
  o.probes = {rod::probe_position(0.5, 1, "mid_y")};
  const auto br = solver::switch_branch(pr, res.bifurcations[0], 0.05, o, comm);
  a.completed = br.completed;
  a.message = br.message;
  if (br.completed) {
    a.P_last = br.points.back().parameter / PE;
    a.w = br.points.back().probes[0];
  }
  return a;
}

}  // namespace

TEST(StaticsMpi, SameAnswersOnOneAndTwoRanks) {
  auto comm = Tpetra::getDefaultComm();
  const Answers all = continuation_answers(comm);
  const solver::Comm self = Teuchos::rcp(new Teuchos::MpiComm<int>(MPI_COMM_SELF));
  const Answers alone = continuation_answers(self);
  ASSERT_EQ(alone.bifurcations, 1u);
  ASSERT_TRUE(alone.completed) << alone.message;
  ASSERT_EQ(all.bifurcations, 1u);
  ASSERT_TRUE(all.completed) << all.message;
  if (comm->getRank() == 0)
    std::printf("  %d rank(s): P* = %.12f N (one process %.12f), w(P = 1.15 P_E) = %.10f m (one process %.10f)\n",
                comm->getSize(), all.Pstar, alone.Pstar, all.w, alone.w);
  // The distributed solves differ from the serial ones in the order of their sums only.
  EXPECT_NEAR(all.Pstar, alone.Pstar, 1e-8);
  EXPECT_NEAR(all.P_last, 1.15, 1e-12);
  EXPECT_NEAR(all.w, alone.w, 1e-8);
}

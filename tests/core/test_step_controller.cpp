// The step-size controller (core/step_controller.hpp, docs/adaptive.md): acceptance at an
// error norm of 1, the optimal factor safety * err^(-1/(p+1)), bounded growth and shrink, no
// growth right after a rejection or above the Newton target, dt_min / dt_max.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "traverse/core/step_controller.hpp"

namespace traverse {
namespace {

StepControlParameters params() {
  StepControlParameters p;
  p.relative = 1e-3;
  p.dt_min = 1e-6;
  p.dt_max = 1.0;
  p.growth = 2.0;
  p.shrink = 0.2;
  p.safety = 0.9;
  p.newton_target = 6;
  p.order = 2;
  return p;
}

TEST(StepController, AcceptsWithinTheToleranceWithTheOptimalFactor) {
  StepController c(params());
  const StepDecision d = c.decide(0.01, 0.5, 3);
  EXPECT_TRUE(d.accept);
  EXPECT_NEAR(d.next_dt, 0.01 * 0.9 * std::pow(0.5, -1.0 / 3.0), 1e-15);
}

TEST(StepController, GrowthIsBoundedAndZeroErrorGrowsByTheBound) {
  StepController c(params());
  EXPECT_DOUBLE_EQ(c.decide(0.01, 1e-12, 3).next_dt, 0.02);
  EXPECT_DOUBLE_EQ(c.decide(0.01, 0.0, 3).next_dt, 0.02);
  EXPECT_DOUBLE_EQ(c.decide(0.8, 0.0, 3).next_dt, 1.0);  // dt_max
}

TEST(StepController, RejectsAboveTheToleranceAndShrinksWithinBounds) {
  StepController c(params());
  const StepDecision d = c.decide(0.01, 8.0, 3);
  EXPECT_FALSE(d.accept);
  EXPECT_NEAR(d.next_dt, 0.01 * 0.9 / 2.0, 1e-15);            // 0.9 * 8^(-1/3)
  EXPECT_DOUBLE_EQ(c.decide(0.01, 1e9, 3).next_dt, 0.01 * 0.2);  // the shrink bound
  EXPECT_DOUBLE_EQ(c.decide(0.01, std::numeric_limits<double>::quiet_NaN(), 3).next_dt, 0.01 * 0.2);
  EXPECT_FALSE(c.decide(0.01, std::numeric_limits<double>::infinity(), 3).accept);
  EXPECT_DOUBLE_EQ(c.decide(2e-6, 1e9, 3).next_dt, 1e-6);  // dt_min
}

TEST(StepController, NoGrowthRightAfterARejectionNorAboveTheNewtonTarget) {
  StepController c(params());
  EXPECT_FALSE(c.decide(0.01, 2.0, 3).accept);
  EXPECT_TRUE(c.after_rejection());
  const StepDecision d = c.decide(0.008, 1e-6, 3);
  EXPECT_TRUE(d.accept);
  EXPECT_DOUBLE_EQ(d.next_dt, 0.008);  // held
  EXPECT_FALSE(c.after_rejection());
  EXPECT_DOUBLE_EQ(c.decide(0.008, 1e-6, 3).next_dt, 0.016);  // grows again
  EXPECT_DOUBLE_EQ(c.decide(0.008, 1e-6, 7).next_dt, 0.008);  // 7 > newton_target
  EXPECT_LT(c.decide(0.008, 0.9, 7).next_dt, 0.008);          // it may still shrink
}

TEST(StepController, AFailedSolveAtLeastHalvesTheStep) {
  StepController c(params());
  EXPECT_DOUBLE_EQ(c.after_failure(0.01), 0.0025);  // max(shrink, 0.25)
  EXPECT_TRUE(c.after_rejection());
  StepControlParameters p = params();
  p.shrink = 0.9;
  EXPECT_DOUBLE_EQ(StepController(p).after_failure(0.01), 0.005);
}

TEST(StepController, TotalsRecordTheRange) {
  StepControlTotals t;
  t.record_accepted(0.01);
  t.record_accepted(0.001);
  t.record_accepted(0.1);
  EXPECT_EQ(t.accepted, 3);
  EXPECT_DOUBLE_EQ(t.smallest_dt, 0.001);
  EXPECT_DOUBLE_EQ(t.largest_dt, 0.1);
  EXPECT_NE(t.summary().find("3 steps accepted"), std::string::npos);
}

// Landing on a time the steps must reach (an output time, a node crossing): the proposed step,
// the remainder, or half of it rather than a sliver; a step shortened only to land does not
// shrink the next proposal.
TEST(StepController, LandingStep) {
  EXPECT_DOUBLE_EQ(StepController::landing_step(0.1, 1.0), 0.1);
  EXPECT_DOUBLE_EQ(StepController::landing_step(2.0, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(StepController::landing_step(1.0 - 1e-14, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(StepController::landing_step(0.7, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(StepController::landing_step(0.5, 1.0), 0.5);
  EXPECT_DOUBLE_EQ(StepController::after_landing(0.5, 0.7, 0.6), 0.7);  // shortened: keep the proposal
  EXPECT_DOUBLE_EQ(StepController::after_landing(0.5, 0.7, 0.9), 0.9);
  EXPECT_DOUBLE_EQ(StepController::after_landing(0.1, 0.1, 0.05), 0.05);  // not shortened: the controller's
}

}  // namespace
}  // namespace traverse

// The shared time grid (traverse/core/time_grid.hpp): step counts without overflow, the join
// of a rounding remainder, the 2^32 limit, and step lengths that do not drift.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "traverse/core/time_grid.hpp"

using traverse::grid_step_count;
using traverse::kMaxGridSteps;
using traverse::make_time_grid;

TEST(TimeGrid, CountsWholeStepsAndJoinsARoundingRemainder) {
  EXPECT_EQ(grid_step_count(1.0, 0.25, 1e-6), 4.0);
  EXPECT_EQ(grid_step_count(1.0, 0.3, 1e-6), 4.0);            // 3.33 steps: the last one shortened
  EXPECT_EQ(grid_step_count(1.0 + 1e-9, 0.25, 1e-6), 4.0);    // 4.000000004: joins the last step
  EXPECT_EQ(grid_step_count(1.0 + 1e-5, 0.25, 1e-6), 5.0);    // 4.00004: a step of its own
  EXPECT_EQ(grid_step_count(0.1, 1.0, 1e-6), 1.0);            // dt longer than the run: one step
  EXPECT_EQ(grid_step_count(1e-300, 1e300, 1e-6), 1.0);
}

TEST(TimeGrid, HugeOrInvalidCountsAreNotConverted) {
  // A count that does not fit a long stays a double (it was static_cast<long> before: UB).
  const double huge = grid_step_count(0.275, 1e-300, 1e-6);
  EXPECT_GT(huge, 1e299);
  EXPECT_FALSE(make_time_grid(0.0, 0.275, 1e-300, 1e-6).ok);
  EXPECT_TRUE(std::isinf(grid_step_count(1e300, 1e-300, 1e-6)));
  EXPECT_FALSE(make_time_grid(0.0, 1e300, 1e-300, 1e-6).ok);
  for (double bad : {0.0, -1.0, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_TRUE(std::isnan(grid_step_count(bad, 1.0, 1e-6))) << bad;
    EXPECT_TRUE(std::isnan(grid_step_count(1.0, bad, 1e-6))) << bad;
    EXPECT_FALSE(make_time_grid(0.0, 1.0, bad, 1e-6).ok) << bad;
  }
  // The limit itself is accepted, one more step is not.
  EXPECT_TRUE(make_time_grid(0.0, kMaxGridSteps, 1.0, 1e-6).ok);
  EXPECT_EQ(make_time_grid(0.0, kMaxGridSteps, 1.0, 1e-6).grid.steps, 4294967296L);
  EXPECT_FALSE(make_time_grid(0.0, kMaxGridSteps + 1.0, 1.0, 1e-6).ok);
}

TEST(TimeGrid, StepLengthsStayWithin1e6OfDtUpToTheLimit) {
  // Random dt and end times with up to 2^32 steps: every step (sampled at the start, around
  // 2^k and at the end, where the rounding of k dt is largest) has the length dt to 1e-6, and
  // the last one is positive and at most dt (1 + 1e-6).
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> mant(1.0, 10.0), expo(-12.0, 9.0), frac(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 400; ++trial) {
    const double dt = mant(rng) * std::pow(10.0, expo(rng));
    const double steps = std::floor(std::pow(2.0, 32.0 * frac(rng)));
    const double t_end = (steps - 1.0 + std::max(1e-3, frac(rng))) * dt;
    const auto r = make_time_grid(0.0, t_end, dt, 1e-6);
    ASSERT_TRUE(r.ok) << dt << " " << t_end;
    const auto& g = r.grid;
    ASSERT_GE(g.steps, 1);
    ASSERT_LE(static_cast<double>(g.steps), kMaxGridSteps);
    EXPECT_EQ(g.time(g.steps), t_end);
    std::vector<long> ks = {1, 2, g.steps - 1, g.steps};
    for (long p = 2; p < g.steps; p *= 2) ks.insert(ks.end(), {p - 1, p, p + 1});
    for (long k : ks) {
      if (k < 1 || k > g.steps) continue;
      const double h = g.time(k) - g.time(k - 1);
      if (k == g.steps) {
        EXPECT_GT(h, 0.0) << "last step of " << g.steps << ", dt = " << dt;
        EXPECT_LE(h, dt * (1.0 + 1e-6)) << "last step of " << g.steps << ", dt = " << dt;
      } else {
        worst = std::max(worst, std::abs(h - dt) / dt);
        EXPECT_LE(std::abs(h - dt), 1e-6 * dt) << "step " << k << " of " << g.steps << ", dt = " << dt;
      }
    }
  }
  std::cout << "  largest |h - dt| / dt over the sampled steps: " << worst << "\n";
}

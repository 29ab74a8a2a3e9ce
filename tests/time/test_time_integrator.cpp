// The time integrator (time/time_integrator.hpp) on y' = lambda y with the trapezoidal rule:
// where the steps end (the grid, the output times, the kinks), what the observer is told,
// and the adaptive steps' accuracy against the closed form e^(lambda t).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "traverse/time/time_integrator.hpp"

namespace {

using namespace traverse;

/// y' = lambda y, the trapezoidal rule (second order); adaptive attempts by step doubling.
class Decay : public time::SteppedModel {
 public:
  explicit Decay(double lambda) : lambda_(lambda) {}
  double time() const override { return t_; }
  void step(double h) override {
    if (fail_fixed_at_ >= 0 && static_cast<int>(ends.size()) == fail_fixed_at_)
      throw time::StepFailed("no convergence");
    y_ *= factor(h);
    t_ += h;
    ends.push_back(t_);
  }
  time::Attempt attempt(double h) override {
    time::Attempt a;
    ++attempts;
    h_ = h;
    if (h > fail_above_) {
      a.why = "too long";
      return a;
    }
    const double full = y_ * factor(h), half = y_ * factor(0.5 * h) * factor(0.5 * h);
    y_new_ = half;
    a.converged = true;
    a.error = std::abs(half - full) / 3.0 / (tolerance * std::max(std::abs(half), 1e-3));
    return a;
  }
  std::vector<double> accept() override {
    y_ = y_new_;
    t_ += h_;
    ends.push_back(t_);
    return {0.5 * h_, 0.5 * h_};
  }
  void reject() override { ++rejections; }
  double next_kink(double t) const override {
    for (double k : kinks)
      if (k > t) return k;
    return HUGE_VAL;
  }
  bool ended() const override { return end_at_ > 0.0 && t_ >= end_at_; }
  double y() const { return y_; }

  std::vector<double> ends, kinks;
  double tolerance = 1e-6, fail_above_ = HUGE_VAL, end_at_ = 0.0;
  int fail_fixed_at_ = -1;  ///< the step (0-based) whose fixed step throws
  long attempts = 0, rejections = 0;

 private:
  double factor(double h) const { return (1.0 + 0.5 * lambda_ * h) / (1.0 - 0.5 * lambda_ * h); }
  double lambda_, t_ = 0.0, y_ = 1.0, y_new_ = 0.0, h_ = 0.0;
};

/// Records what the integrator tells; a failure or an interrupt throws.
struct Recorder : time::Observer {
  explicit Recorder(const time::SteppedModel& m) : model(m) {}
  void output() override { outputs.push_back(model.time()); }
  void store(long step) override { stored.push_back(step); }
  bool store_due() override { return true; }
  int interrupt_requested() override { return ++asked == interrupt_at ? 15 : 0; }
  void progress(double, long step, double, const StepControlTotals*) override { last_progress = step; }
  [[noreturn]] void interrupted(int sig, long step, const std::string& where) override {
    signal = sig;
    at_step = step;
    this->where = where;
    throw std::runtime_error("interrupted");
  }
  [[noreturn]] void failed(const std::string& where, const std::string& why, long step,
                           const time::StepFailed* cause) override {
    this->where = where;
    this->why = why;
    at_step = step;
    had_cause = cause != nullptr;
    throw std::runtime_error("failed");
  }
  const time::SteppedModel& model;
  std::vector<double> outputs;
  std::vector<long> stored;
  long asked = 0, interrupt_at = -1, at_step = -1, last_progress = -1;
  int signal = 0;
  bool had_cause = false;
  std::string where, why;
};

time::Schedule schedule(double dt, double end, long every, bool adaptive = false) {
  time::Schedule s;
  s.grid = make_time_grid(0.0, end, dt, 1e-9).grid;
  s.every = every;
  s.adaptive = adaptive;
  s.control.relative = 1.0;  // the model weighs its error by its own tolerance
  s.control.dt_min = 1e-9;
  s.control.order = 2;
  return s;
}

TEST(TimeIntegrator, FixedStepsEndOnTheGridAndWriteEveryNthStepAndTheLast) {
  Decay m(-1.0);
  Recorder r(m);
  time::TimeIntegrator(schedule(0.1, 1.0, 3), m, r).run();
  ASSERT_EQ(m.ends.size(), 10u);
  const TimeGrid g = make_time_grid(0.0, 1.0, 0.1, 1e-9).grid;
  for (long i = 1; i <= 10; ++i) EXPECT_DOUBLE_EQ(m.ends[static_cast<size_t>(i - 1)], g.time(i));
  EXPECT_EQ(r.outputs, (std::vector<double>{g.time(3), g.time(6), g.time(9), g.time(10)}));
  EXPECT_EQ(r.stored, (std::vector<long>{3, 6, 9, 10}));
  EXPECT_EQ(r.last_progress, 10);
  EXPECT_EQ(r.asked, 9);  // after each step but the last
  // The trapezoidal rule's global error: e^-1 (dt^2 / 12) to leading order.
  EXPECT_NEAR(m.y(), std::exp(-1.0), 1.1 * std::exp(-1.0) * 0.01 / 12.0);
}

TEST(TimeIntegrator, FixedStepsSplitAtKinksWhenAsked) {
  for (const bool split : {false, true}) {
    Decay m(-1.0);
    m.kinks = {0.25, 0.55, 0.6};  // 0.6 lies on the grid: no extra step
    Recorder r(m);
    time::Schedule s = schedule(0.1, 1.0, 5);
    s.split_at_kinks = split;
    time::TimeIntegrator(s, m, r).run();
    EXPECT_EQ(m.ends.size(), split ? 12u : 10u);
    EXPECT_EQ(std::count(m.ends.begin(), m.ends.end(), 0.25), split ? 1 : 0);
    EXPECT_EQ(std::count(m.ends.begin(), m.ends.end(), 0.55), split ? 1 : 0);
    ASSERT_EQ(r.outputs.size(), 2u);  // grid steps 5 and 10 only
    EXPECT_NEAR(r.outputs[0], 0.5, 1e-15);
  }
}

TEST(TimeIntegrator, AdaptiveStepsLandOnOutputTimesAndKinksWithinTheTolerance) {
  std::vector<double> errors;
  for (const double tol : {1e-7, 1e-9}) {  // steps set by the tolerance, not by the landing
    Decay m(-1.0);
    m.tolerance = tol;
    m.kinks = {0.123, 0.777};
    Recorder r(m);
    time::TimeIntegrator ti(schedule(0.1, 1.0, 2, true), m, r);
    ti.run();
    ASSERT_EQ(r.outputs.size(), 5u);
    for (size_t k = 0; k < 5; ++k) EXPECT_NEAR(r.outputs[k], 0.2 * double(k + 1), 1e-12);
    for (const double kink : m.kinks)
      EXPECT_TRUE(std::any_of(m.ends.begin(), m.ends.end(), [&](double t) { return std::abs(t - kink) < 1e-12; }));
    EXPECT_EQ(ti.totals().accepted, 2 * static_cast<long>(m.ends.size()));  // two half steps each
    EXPECT_EQ(ti.last_step(), ti.totals().accepted);
    errors.push_back(std::abs(m.y() - std::exp(-1.0)));
    // Each step's local error is within tol |y|: the global error within their sum.
    EXPECT_LT(errors.back(), tol * static_cast<double>(m.ends.size()));
  }
  // Second order: the step grows as tol^(1/3) and the global error shrinks as tol^(2/3).
  const double order = std::log(errors[0] / errors[1]) / std::log(100.0);
  EXPECT_NEAR(order, 2.0 / 3.0, 0.1);
}

TEST(TimeIntegrator, AdaptiveStepsRetryRejectedAndFailedAttemptsShorter) {
  Decay m(-5.0);
  m.tolerance = 1e-8;
  m.fail_above_ = 0.2;  // the first step (0.5) fails, then the error decides
  Recorder r(m);
  time::TimeIntegrator ti(schedule(0.5, 1.0, 1, true), m, r);
  ti.run();
  EXPECT_GE(ti.totals().failed, 1);
  EXPECT_GE(ti.totals().rejected, 1);
  EXPECT_EQ(m.rejections, ti.totals().rejected);
  EXPECT_EQ(m.attempts, ti.totals().failed + ti.totals().rejected + static_cast<long>(m.ends.size()));
  EXPECT_NEAR(m.y(), std::exp(-5.0), 1e-8 * static_cast<double>(m.ends.size()));
}

TEST(TimeIntegrator, AdaptiveRunGivesUpAtDtMinAndSaysWhy) {
  Decay m(-1.0);
  m.fail_above_ = 0.0;  // every attempt fails
  Recorder r(m);
  time::Schedule s = schedule(0.1, 1.0, 1, true);
  s.control.dt_min = 1e-3;
  EXPECT_THROW(time::TimeIntegrator(s, m, r).run(), std::runtime_error);
  EXPECT_NE(r.where.find("time.adaptive"), std::string::npos) << r.where;
  EXPECT_NE(r.why.find("too long at the smallest step, time.adaptive.dt_min = 0.001"), std::string::npos) << r.why;
  EXPECT_FALSE(r.had_cause);
  EXPECT_EQ(r.at_step, 0);
}

TEST(TimeIntegrator, FixedStepFailureNamesTheStepAndKeepsTheOneBefore) {
  Decay m(-1.0);
  m.fail_fixed_at_ = 3;  // the fourth step
  Recorder r(m);
  EXPECT_THROW(time::TimeIntegrator(schedule(0.1, 1.0, 1), m, r).run(), std::runtime_error);
  EXPECT_EQ(r.where, "time step 4 of 10");
  EXPECT_EQ(r.why, "no convergence");
  EXPECT_EQ(r.at_step, 3);
  EXPECT_TRUE(r.had_cause);
}

TEST(TimeIntegrator, AnEventEndsTheRunWithAnOutput) {
  Decay m(-1.0);
  m.end_at_ = 0.35;
  Recorder r(m);
  time::TimeIntegrator ti(schedule(0.1, 1.0, 10), m, r);
  ti.run();
  EXPECT_EQ(m.ends.size(), 4u);
  ASSERT_EQ(r.outputs.size(), 1u);
  EXPECT_NEAR(r.outputs[0], 0.4, 1e-15);
  EXPECT_EQ(ti.last_step(), 4);
}

TEST(TimeIntegrator, AnInterruptStopsAfterTheStepItFollows) {
  Decay m(-1.0);
  Recorder r(m);
  r.interrupt_at = 5;
  EXPECT_THROW(time::TimeIntegrator(schedule(0.1, 1.0, 1), m, r).run(), std::runtime_error);
  EXPECT_EQ(r.signal, 15);
  EXPECT_EQ(r.at_step, 5);
  EXPECT_EQ(r.where, "time step 5 of 10");
  EXPECT_EQ(m.ends.size(), 5u);
}

TEST(TimeIntegrator, ARestartContinuesFromItsStepAndControllerState) {
  // Fixed: the steps after the restart's are those of the whole run.
  Decay whole(-1.0), second(-1.0);
  Recorder rw(whole), rs(second);
  time::TimeIntegrator(schedule(0.1, 1.0, 1), whole, rw).run();
  for (int i = 0; i < 4; ++i) second.step(make_time_grid(0.0, 1.0, 0.1, 1e-9).grid.time(i + 1) - second.time());
  time::TimeIntegrator(schedule(0.1, 1.0, 1), second, rs).run(5);
  EXPECT_EQ(second.ends, whole.ends);
  EXPECT_EQ(second.y(), whole.y());
  // Adaptive: the controller's state round trip.
  Decay a(-1.0);
  Recorder ra(a);
  time::TimeIntegrator ti(schedule(0.1, 1.0, 1, true), a, ra);
  time::ControllerState c;
  c.next_dt = 0.0123;
  c.totals.accepted = 7;
  c.after_rejection = true;
  ti.restore(c);
  EXPECT_EQ(ti.controller_state().next_dt, 0.0123);
  EXPECT_EQ(ti.controller_state().totals.accepted, 7);
  EXPECT_TRUE(ti.controller_state().after_rejection);
}

TEST(TimeIntegrator, CallbackObserverThrowsRunFailedWithWhereAndWhy) {
  Decay m(-1.0);
  m.fail_fixed_at_ = 0;
  int outputs = 0;
  time::CallbackObserver calls([&] { ++outputs; });
  try {
    time::TimeIntegrator(schedule(0.1, 1.0, 1), m, calls).run();
    ADD_FAILURE() << "no RunFailed";
  } catch (const time::RunFailed& e) {
    EXPECT_STREQ(e.what(), "time step 1 of 10: no convergence");
  }
  EXPECT_EQ(outputs, 0);
}

}  // namespace

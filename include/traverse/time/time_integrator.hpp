#pragma once
// The one time loop of every model (docs/developer.md, "Time integration"): fixed steps on
// the grid of time.dt, or adaptive steps whose length the error estimate decides
// (time.adaptive). The steps land on the output times (every output.every steps of the grid,
// and time.end) and, adaptive, on the times where the model's loads have a kink. The
// integrator decides when to step, to write, to store a restart point, to look for an
// interrupt and to give up; the model takes the steps and the observer does the writing.
// Trilinos-free and MPI-free: a model on several ranks reduces its own error estimate.
#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "traverse/core/step_controller.hpp"
#include "traverse/core/time_grid.hpp"

namespace traverse::time {

/// A step the model could not take; the model's state is that before the step.
class StepFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One adaptive attempt: the step taken (kept until accept or reject) and its error estimate.
struct Attempt {
  bool converged = false;  ///< false: the solve failed, the state is as before, `why` says why
  double error = 0.0;      ///< the weighted error estimate (the step is within the tolerance at <= 1)
  int newton = 0;          ///< Newton iterations per solve: the controller's second signal
  std::string estimate = "the error estimate";  ///< what `error` is, for messages
  std::string why;
};

/// What the integrator steps.
class SteppedModel {
 public:
  virtual ~SteppedModel() = default;
  virtual double time() const = 0;
  /// Fixed steps: one step of length h; throws StepFailed (state as before the step).
  virtual void step(double h) = 0;
  /// Adaptive steps: an attempt of length h, then accept() or reject().
  virtual Attempt attempt(double h) = 0;
  /// The attempt becomes the state; the lengths of the steps it made (two for step doubling).
  /// May throw StepFailed (work after the step, e.g. locating an event, failed; the state is
  /// that before the attempt).
  virtual std::vector<double> accept() = 0;
  /// Back to the state before the attempt.
  virtual void reject() = 0;
  /// The first time after t at which the loads have a kink the adaptive steps land on (+inf: none).
  virtual double next_kink(double /*t*/) const { return HUGE_VAL; }
  /// Whether an event (the model's, e.g. a mass leaving the structure) ended the run.
  virtual bool ended() const { return false; }
};

/// What the integrator asks of the run around it (the output file, the console, the signals).
class Observer {
 public:
  virtual ~Observer() = default;
  /// An output time is reached (or the run ended by an event): write the outputs.
  virtual void output() = 0;
  /// Store a restart point of the current state as that of `step` (the step count so far).
  virtual void store(long step) = 0;
  /// Whether the restart interval has passed since the last point (collective).
  virtual bool store_due() = 0;
  /// A requested stop (a signal number), or 0 (collective).
  virtual int interrupt_requested() = 0;
  /// After each step: t, steps so far, and with adaptive steps the next step and the counters.
  virtual void progress(double t, long step, double next_dt, const StepControlTotals* totals) = 0;
  /// Stop on signal `sig`, the current state that of `step`; `where` e.g. "time step 12 of 100".
  [[noreturn]] virtual void interrupted(int sig, long step, const std::string& where) = 0;
  /// Give up at `where` (e.g. "time step 12 of 100"): `why` as the user reads it, the current
  /// state that of `step`; `cause` the model's exception (nullptr when the integrator gave up
  /// by itself, e.g. at dt_min).
  [[noreturn]] virtual void failed(const std::string& where, const std::string& why, long step,
                                   const StepFailed* cause) = 0;
};

/// The adaptive controller's state between two steps: what a restart point keeps.
struct ControllerState {
  double next_dt = 0.0;  ///< [s] the step proposed next
  StepControlTotals totals;
  bool after_rejection = false;
};

/// The steps of a run.
struct Schedule {
  TimeGrid grid;      ///< time.dt, time.end (adaptive: the first step and the output spacing)
  long every = 1;     ///< output.every: an output every this many grid steps, and at the end
  bool adaptive = false;
  StepControlParameters control;  ///< time.adaptive
  /// Fixed steps: a grid step with a kink of the loads inside is taken as two steps that meet
  /// there (adaptive steps always land on the kinks).
  bool split_at_kinks = false;
  /// What a run that fails at time.adaptive.dt_min may try.
  std::string dt_min_hint = "try a larger time.adaptive.tolerance or dt_min";
};

/// A run given up (thrown by CallbackObserver): where and why.
class RunFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The observer of a run inside a program (a test, a library user): `output` at each output
/// time, no restart points, no signals; a failure throws RunFailed ("where: why").
class CallbackObserver : public Observer {
 public:
  explicit CallbackObserver(std::function<void()> output) : output_(std::move(output)) {}
  void output() override {
    if (output_) output_();
  }
  void store(long) override {}
  bool store_due() override { return false; }
  int interrupt_requested() override { return 0; }
  void progress(double, long, double, const StepControlTotals*) override {}
  [[noreturn]] void interrupted(int, long, const std::string& where) override {
    throw std::logic_error("CallbackObserver: no interrupt at " + where);
  }
  [[noreturn]] void failed(const std::string& where, const std::string& why, long, const StepFailed*) override {
    throw RunFailed(where + ": " + why);
  }

 private:
  std::function<void()> output_;
};

/// What interrupt_requested answers for a stop that no signal asked for (a step hook's).
inline constexpr int kStopRequested = 1000;

/// An observer that passes everything on to `inner` and, after every `every`-th step (the step
/// count progress() gets), asks `proceed(step)`: false stops the run there as a signal does
/// (interrupt_requested answers kStopRequested, and the run ends through inner.interrupted).
/// `proceed` must answer alike on every rank (the inner interrupt check is then skipped alike).
class StepHookObserver : public Observer {
 public:
  StepHookObserver(Observer& inner, long every, std::function<bool(long)> proceed)
      : inner_(inner), every_(std::max(1L, every)), proceed_(std::move(proceed)) {}
  /// This observer when `hooked`, else the inner one (a run without a step hook skips it).
  Observer& chosen(bool hooked) { return hooked ? static_cast<Observer&>(*this) : inner_; }
  void output() override { inner_.output(); }
  void store(long step) override { inner_.store(step); }
  bool store_due() override { return inner_.store_due(); }
  int interrupt_requested() override { return stop_ ? kStopRequested : inner_.interrupt_requested(); }
  void progress(double t, long step, double next_dt, const StepControlTotals* totals) override {
    inner_.progress(t, step, next_dt, totals);
    if (step % every_ == 0 && !proceed_(step)) stop_ = true;
  }
  // (The inner observer's do not return either; the throws tell the compiler.)
  [[noreturn]] void interrupted(int sig, long step, const std::string& where) override {
    inner_.interrupted(sig, step, where);
    throw std::logic_error("StepHookObserver: the run went on after the interrupt at " + where);
  }
  [[noreturn]] void failed(const std::string& where, const std::string& why, long step,
                           const StepFailed* cause) override {
    inner_.failed(where, why, step, cause);
    throw RunFailed(where + ": " + why);
  }

 private:
  Observer& inner_;
  long every_;
  std::function<bool(long)> proceed_;
  bool stop_ = false;
};

/// The first of the sorted times `sorted` after t (+inf: none): a model's next_kink from a
/// list of its kinks.
inline double next_after(const std::vector<double>& sorted, double t) {
  const auto next = std::upper_bound(sorted.begin(), sorted.end(), t);
  return next == sorted.end() ? HUGE_VAL : *next;
}

/// Runs `model` from its time to the end with a CallbackObserver (`output` at each output
/// time); the adaptive counters of the run.
StepControlTotals run_with_callback(const Schedule& schedule, SteppedModel& model, std::function<void()> output);

class TimeIntegrator {
 public:
  TimeIntegrator(const Schedule& schedule, SteppedModel& model, Observer& observer);
  /// Steps from the model's time to the end (or an event). Fixed steps start with grid step
  /// `first_step` (a restart's next one).
  void run(long first_step = 1);

  /// The steps taken so far (fixed: the grid index; adaptive: the accepted steps).
  long last_step() const { return last_step_; }
  /// Adaptive steps: the controller's state, for the summary and a restart point.
  const StepControlTotals& totals() const { return totals_; }
  ControllerState controller_state() const { return {next_dt_, totals_, controller_.after_rejection()}; }
  void restore(const ControllerState& c);

 private:
  void run_fixed(long first_step);
  void run_adaptive();
  bool adaptive_step(double h);
  /// A failed or rejected attempt of h: the next try (next_dt_), or the end of the run at dt_min.
  void retry_smaller(double h, double next, const std::string& why);
  double output_time(long k) const;
  Schedule s_;
  SteppedModel& model_;
  Observer& obs_;
  StepController controller_;
  StepControlTotals totals_;
  double next_dt_;
  long last_step_ = 0;
};

}  // namespace traverse::time

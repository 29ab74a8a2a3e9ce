#include "traverse/time/time_integrator.hpp"

#include <algorithm>
#include <sstream>

namespace traverse::time {

StepControlTotals run_with_callback(const Schedule& schedule, SteppedModel& model, std::function<void()> output) {
  CallbackObserver calls(std::move(output));
  TimeIntegrator integrator(schedule, model, calls);
  integrator.run();
  return integrator.totals();
}

TimeIntegrator::TimeIntegrator(const Schedule& schedule, SteppedModel& model, Observer& observer)
    : s_(schedule), model_(model), obs_(observer), controller_(schedule.control),
      next_dt_(schedule.adaptive ? controller_.clamp(schedule.grid.dt) : schedule.grid.dt) {}

void TimeIntegrator::restore(const ControllerState& c) {
  next_dt_ = c.next_dt;
  totals_ = c.totals;
  controller_.set_after_rejection(c.after_rejection);
}

void TimeIntegrator::run(long first_step) {
  if (s_.adaptive)
    run_adaptive();
  else
    run_fixed(first_step);
}

double TimeIntegrator::output_time(long k) const { return s_.grid.time(std::min(k * s_.every, s_.grid.steps)); }

void TimeIntegrator::run_fixed(long first_step) {
  const long n = s_.grid.steps;
  const double tol = 1e-9 * s_.grid.dt;
  last_step_ = first_step - 1;
  for (long i = first_step; i <= n && !model_.ended(); ++i) {
    // Step i ends at the grid time i dt (t_end for the last): computed from i, not accumulated,
    // so the model's time stays on the grid (core/time_grid.hpp bounds the rounding of i dt).
    // Where for the messages, made only when one is written.
    auto where = [&] { return "time step " + std::to_string(i) + " of " + std::to_string(n); };
    const double target = s_.grid.time(i);
    do {
      const double now = model_.time();
      const double kink = s_.split_at_kinks ? model_.next_kink(now + tol) : HUGE_VAL;
      const double h = (kink < target - tol ? kink : target) - now;
      if (!(h > 0.0))
        throw std::logic_error("time loop: " + where() + " has length " + std::to_string(h) + " s (t = " +
                               std::to_string(now) + " s)");
      try {
        model_.step(h);
      } catch (const StepFailed& e) {
        obs_.failed(where(), e.what(), i - 1, &e);
      }
    } while (s_.split_at_kinks && model_.time() < target - tol && !model_.ended());
    last_step_ = i;
    if (i % s_.every == 0 || i == n || model_.ended()) {
      obs_.output();
      if (obs_.store_due()) obs_.store(i);
    }
    obs_.progress(model_.time(), i, 0.0, nullptr);
    if (const int sig = i < n && !model_.ended() ? obs_.interrupt_requested() : 0) obs_.interrupted(sig, i, where());
  }
}

// The steps land on the output times of the fixed grid (so outputs compare point for point
// with a fixed-step run) and on the model's kinks before them; a step that would leave less
// than itself is split in two (StepController::landing_step).
void TimeIntegrator::run_adaptive() {
  const long outputs = (s_.grid.steps + s_.every - 1) / s_.every;
  last_step_ = totals_.accepted;
  long k = 1;  // the next output time: the first one after the current time
  // (A restart point at an output time may lie a rounding below it: the landing tolerance.)
  while (k <= outputs && output_time(k) - model_.time() <= 1e-9 * s_.grid.dt) ++k;
  while (k <= outputs && !model_.ended()) {
    const double t_out = output_time(k), now = model_.time();
    const double kink = model_.next_kink(now + 1e-9 * next_dt_);
    const double target = kink < t_out - 1e-9 * next_dt_ ? kink : t_out;
    const double proposed = next_dt_, h = StepController::landing_step(proposed, target - now);
    if (!adaptive_step(h)) continue;
    next_dt_ = StepController::after_landing(h, proposed, next_dt_);
    last_step_ = totals_.accepted;
    const bool landed = std::abs(t_out - model_.time()) <= 1e-9 * h;
    if (landed) ++k;
    if (landed || model_.ended()) {
      obs_.output();
      if (obs_.store_due()) obs_.store(last_step_);
    }
    obs_.progress(model_.time(), last_step_, next_dt_, &totals_);
    if (const int sig = k <= outputs && !model_.ended() ? obs_.interrupt_requested() : 0)
      obs_.interrupted(sig, last_step_, "adaptive step " + std::to_string(last_step_));
  }
}

bool TimeIntegrator::adaptive_step(double h) {
  auto where = [&] { return "adaptive step " + std::to_string(last_step_ + 1); };
  Attempt a;
  try {
    a = model_.attempt(h);
  } catch (const StepFailed& e) {
    obs_.failed(where(), e.what(), last_step_, &e);
  }
  if (!a.converged) {
    ++totals_.failed;
    retry_smaller(h, controller_.after_failure(h), a.why);
    return false;
  }
  const StepDecision d = controller_.decide(h, a.error, a.newton);
  if (!d.accept) {
    model_.reject();
    ++totals_.rejected;
    std::ostringstream os;
    os << a.estimate << " is " << a.error << " times the tolerance";
    retry_smaller(h, d.next_dt, os.str());
    return false;
  }
  std::vector<double> lengths;
  try {
    lengths = model_.accept();
  } catch (const StepFailed& e) {
    obs_.failed(where(), e.what(), last_step_, &e);
  }
  for (const double length : lengths) totals_.record_accepted(length);
  next_dt_ = d.next_dt;
  return true;
}

void TimeIntegrator::retry_smaller(double h, double next, const std::string& why) {
  const double dt_min = controller_.parameters().dt_min;
  if (h <= dt_min * (1.0 + 1e-12)) {
    std::ostringstream where, os;
    where.precision(12);
    where << "adaptive time stepping (time.adaptive) at t = " << model_.time() << " s";
    os << why << " at the smallest step, time.adaptive.dt_min = " << dt_min << " s; " << s_.dt_min_hint;
    obs_.failed(where.str(), os.str(), last_step_, nullptr);
  }
  next_dt_ = std::min(next, h);
}

}  // namespace traverse::time

#pragma once
// Step-size control by a local error estimate (docs/adaptive.md): the elementary controller
// of Hairer, Norsett & Wanner (I.II.4), with bounded growth and shrink, a smallest and a
// largest step, no growth right after a rejection, and the Newton iteration count as a second
// signal. Shared by the rod's generalised-alpha step and the beam's integrators; it holds no
// model and no solver, only the numbers that decide the next step.
#include <algorithm>
#include <string>

namespace traverse {

/// The user's controls (scene section time.adaptive).
struct StepControlParameters {
  double relative = 1e-3;   ///< local error per step, relative (the error norm is 1 there): see tolerance_scale
  double dt_min = 0.0;      ///< [s] smallest step: a step that must be shorter fails the run
  double dt_max = 0.0;      ///< [s] largest step (0: none)
  double growth = 2.0;      ///< largest factor between successive steps (> 1)
  double shrink = 0.2;      ///< smallest factor after a rejection (in (0, 1))
  double safety = 0.9;      ///< factor on the optimal step (in (0, 1])
  int newton_target = 6;    ///< above this many Newton iterations the step does not grow
  int order = 2;            ///< order p of the scheme: the local error is O(dt^(p+1))
};

/// The tolerance a user gives is the relative error asked of the run; the local error allowed
/// per step is that tolerance times this factor, (tol / 1e-3)^(1/p) for a scheme of order p
/// (tolerance proportionality, docs/adaptive.md). The global error of a smooth run goes like
/// the local target^(p/(p+1)), so with the factor it falls in proportion to the tolerance;
/// at 1e-3 the local target is the tolerance itself.
double tolerance_scale(double tolerance, int order);

/// What the controller decided about one attempted step.
struct StepDecision {
  bool accept = false;
  double next_dt = 0.0;  ///< [s] the step to try next (after acceptance: the next step)
};

class StepController {
 public:
  explicit StepController(const StepControlParameters& p) : p_(p) {}
  /// The step of length dt [s] has the weighted error norm `error` (<= 1: within the
  /// tolerance; NaN or inf count as far above) after `newton_iterations` iterations.
  StepDecision decide(double dt, double error, int newton_iterations);
  /// The step of length dt did not converge: the step to try instead (dt shrink-fold, at least
  /// halved).
  double after_failure(double dt);
  /// dt clamped to [dt_min, dt_max].
  double clamp(double dt) const;
  /// The step to take towards a time `remaining` [s] ahead that the steps must land on: the
  /// proposed step, or the remainder when it would reach or pass it, or half the remainder
  /// when it would leave less than itself (no sliver step).
  static double landing_step(double proposed, double remaining);
  /// The step to propose after an accepted step h that was `proposed` before landing and for
  /// which the controller proposes `next`: a step shortened only to land does not shrink the next.
  static double after_landing(double h, double proposed, double next) {
    return h < proposed ? std::max(next, proposed) : next;
  }
  const StepControlParameters& parameters() const { return p_; }
  /// Whether the last decision was a rejection (or a failure): the next accepted step may not grow.
  bool after_rejection() const { return rejected_last_; }
  void set_after_rejection(bool r) { rejected_last_ = r; }

 private:
  StepControlParameters p_;
  bool rejected_last_ = false;
};

/// Counters of an adaptive run, for its summary.
struct StepControlTotals {
  long accepted = 0;
  long rejected = 0;         ///< error above the tolerance
  long failed = 0;           ///< Newton did not converge
  double smallest_dt = 0.0;  ///< [s] of the accepted steps (0 before the first)
  double largest_dt = 0.0;   ///< [s] of the accepted steps
  void record_accepted(double dt);
  /// e.g. "412 steps accepted, 9 rejected (error), 1 failed (Newton); dt 1.2e-05 .. 0.0625 s".
  std::string summary() const;
};

}  // namespace traverse

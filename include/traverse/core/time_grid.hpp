#pragma once
// The uniform time grid of a run: t_k = t_start + k dt for k < steps, t_steps = t_end (the last
// step shortened). Shared by the beam's integrator and the rod's time loop so that the step
// count a run reports is the one it takes, computed without overflow (docs/reliability.md,
// "Limits").
#include <algorithm>
#include <cmath>
#include <limits>

namespace traverse {

/// The most steps a grid may have: 2^32. Times are doubles, so t_k = k dt carries a rounding
/// of up to ulp(t_end) / 2; with at most 2^32 steps that is below 2^-21 dt, so every step has
/// the length dt to within 1e-6 and the last one is longer than zero. Beyond it the grid
/// cannot be represented faithfully (and the count would no longer fit 32-bit counters).
constexpr double kMaxGridSteps = 4294967296.0;

/// The number of steps of length dt that cover `span`, as a double so that it cannot
/// overflow: ceil(span / dt - join), at least 1. A remainder below `join` dt is rounding of dt
/// or of the end time and joins the last step. NaN when span or dt is not a positive finite
/// number; +inf or a huge value when dt is tiny against span (callers compare it with
/// kMaxGridSteps before converting it to an integer).
inline double grid_step_count(double span, double dt, double join) {
  if (!(span > 0.0) || !(dt > 0.0) || !std::isfinite(span) || !std::isfinite(dt))
    return std::numeric_limits<double>::quiet_NaN();
  return std::max(1.0, std::ceil(span / dt - join));
}

/// A grid whose step count passed the check above (steps <= kMaxGridSteps).
struct TimeGrid {
  double t_start = 0.0, t_end = 0.0, dt = 0.0;
  long steps = 0;
  /// The time at the end of step k (1 <= k <= steps): t_start + k dt, t_end for the last.
  /// Computed from k, never accumulated, so the grid does not drift.
  double time(long k) const { return k >= steps ? t_end : t_start + static_cast<double>(k) * dt; }
};

/// The grid of `steps` = grid_step_count(t_end - t_start, dt, join); `ok` is false (and the
/// grid empty) when that count is not a number or exceeds kMaxGridSteps.
struct TimeGridResult {
  TimeGrid grid;
  double steps = 0.0;  ///< the count as computed (may be NaN or huge when !ok)
  bool ok = false;
};
inline TimeGridResult make_time_grid(double t_start, double t_end, double dt, double join) {
  TimeGridResult r;
  r.steps = grid_step_count(t_end - t_start, dt, join);
  r.ok = r.steps <= kMaxGridSteps;  // false for NaN
  if (r.ok) r.grid = TimeGrid{t_start, t_end, dt, static_cast<long>(r.steps)};
  return r;
}

}  // namespace traverse

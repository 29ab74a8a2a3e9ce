#pragma once
// The step controller's parameters from a scene's time.adaptive (docs/adaptive.md), for the
// rod and the beam runners.
#include <cstdio>
#include <string>

#include "traverse/core/step_controller.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

/// dt_min defaults to 1e-6 time.dt; `order` is the scheme's (2 for the rod).
inline StepControlParameters step_control_parameters(const scene::AdaptiveSpec& a, double dt, int order = 2) {
  StepControlParameters p;
  p.relative = a.tolerance;
  p.dt_min = a.dt_min > 0.0 ? a.dt_min : 1e-6 * dt;
  p.dt_max = a.dt_max;
  p.growth = a.growth;
  p.shrink = a.shrink;
  p.safety = a.safety;
  p.newton_target = a.newton_target;
  p.order = order;
  return p;
}

/// The counters of an adaptive run as root attributes of its output (docs/output.md):
/// `steps_accepted`, `steps_rejected` (error above the tolerance), `steps_failed` (Newton),
/// `dt_smallest` and `dt_largest` [s] of the accepted steps (17 digits).
inline void write_adaptive_totals(output::Writer& w, const StepControlTotals& t) {
  w.set_attribute("steps_accepted", std::to_string(t.accepted));
  w.set_attribute("steps_rejected", std::to_string(t.rejected));
  w.set_attribute("steps_failed", std::to_string(t.failed));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", t.smallest_dt);
  w.set_attribute("dt_smallest", buf);
  std::snprintf(buf, sizeof buf, "%.17g", t.largest_dt);
  w.set_attribute("dt_largest", buf);
}

}  // namespace traverse::app

#pragma once
// The step controller's parameters from a scene's time.adaptive (docs/adaptive.md), for the
// rod and the beam runners.
#include "traverse/core/step_controller.hpp"
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

}  // namespace traverse::app

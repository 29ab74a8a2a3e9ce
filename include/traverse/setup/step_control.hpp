#pragma once
// The time integrator's schedule and the rod's error weights from a scene's time and
// time.adaptive (docs/adaptive.md), for the rod and the beam runners.
#include <mpi.h>

#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "traverse/core/step_controller.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/rod/rod_model.hpp"
#include "traverse/rod/time_error.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/solver/rod_error_estimate.hpp"
#include "traverse/solver/rod_stepper.hpp"
#include "traverse/time/time_integrator.hpp"

namespace traverse::setup {

/// The order of the rod's time scheme (generalised alpha).
inline constexpr int kRodOrder = 2;

/// dt_min defaults to 1e-6 time.dt; `order` is the scheme's.
inline StepControlParameters step_control_parameters(const scene::AdaptiveSpec& a, double dt, int order = kRodOrder) {
  StepControlParameters p;
  p.relative = a.tolerance * tolerance_scale(a.tolerance, order);
  p.dt_min = a.dt_min > 0.0 ? a.dt_min : 1e-6 * dt;
  p.dt_max = a.dt_max;
  p.growth = a.growth;
  p.shrink = a.shrink;
  p.safety = a.safety;
  p.newton_target = a.newton_target;
  p.order = order;
  return p;
}

/// The steps of a rod run on `grid`: every output.every steps, adaptive with time.adaptive.
inline time::Schedule rod_schedule(const scene::Scene& sc, const TimeGrid& grid) {
  time::Schedule s{grid, sc.output.every, sc.time.adaptive.enabled, step_control_parameters(sc.time.adaptive, grid.dt)};
  s.dt_min_hint += ", or scheme.rho_inf < 1";
  return s;
}

/// The rod's error weights (rod/time_error.hpp): the tolerances and controlled groups of
/// time.adaptive scaled for the rod's second-order scheme (tolerance_scale), the position
/// floor from the rod's length.
inline rod::ErrorWeights error_weights(const scene::AdaptiveSpec& a, double length) {
  rod::ErrorWeights w;
  const double f = tolerance_scale(a.tolerance, kRodOrder);
  w.relative = a.tolerance * f;
  for (int g = 0; g < rod::kErrorGroups; ++g) w.absolute[g] = a.absolute[g] * f;
  w.floor = rod::scale_floors(length);
  w.controlled = a.controlled;
  return w;
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

/// The work of a rod run as root attributes of its output (docs/output.md): `time_steps` and
/// `newton_iterations` (a restarted run without a coupled mass counts from its restart), and
/// with a coupled mass `coupling_iterations` (`coupling` >= 0).
inline void write_solve_totals(output::Writer& w, long time_steps, long newton, long coupling = -1) {
  w.set_attribute("time_steps", std::to_string(time_steps));
  w.set_attribute("newton_iterations", std::to_string(newton));
  if (coupling >= 0) w.set_attribute("coupling_iterations", std::to_string(coupling));
}

/// The first time after t at which one of the prescribed moving loads (not a coupled mass)
/// enters the rod or reaches one of its nodes (the multiples of ds in [0, length]): there the
/// hat weights that share its force between the nodes have a kink in time. +inf if none.
double next_node_crossing(const std::vector<scene::MovingLoadSpec>& loads, double t, double ds, double length);

/// Values per node of a rod run's restart point: the node, and with time.adaptive the error
/// estimate's two earlier levels.
std::size_t rod_restart_components(const scene::Scene& sc);

/// The adaptive steps' error estimate of a rod run: started at the stepper's current level, or
/// restored from the restart point `point` (not null) with the controller's state into
/// `controller`. Collective.
std::unique_ptr<solver::RodErrorEstimate> rod_error_estimate(const scene::Scene& sc, const rod::RodModel& model,
                                                             const solver::RodStepper& st,
                                                             const output::RestartPoint* point, MPI_Comm comm,
                                                             std::optional<time::ControllerState>& controller);

}  // namespace traverse::setup

#pragma once
// The hanging cable of the reference scenes for the rod tests: L along k, clamped at s = 0,
// sliding along k at s = L, gravity g along -j; its static form with a point weight where a
// moving load starts, and its dynamic model (gravity and ends; loads added by each test).
#include "traverse/rod/rod_kernels.hpp"
#include "reference_statics.hpp"
#include "traverse/rod/static_load_steps.hpp"

namespace traverse::testing {

inline rod::StaticModel hanging_cable_statics(const rod::RodProperties& props, int cells, double L, double g,
                                              double weight, double s0) {
  rod::StaticModel sm;
  sm.props = props;
  sm.num_cells = cells;
  sm.length = L;
  sm.left.type = rod::EndCondition::Type::clamped;
  sm.right.type = rod::EndCondition::Type::sliding;
  sm.right.axis = Vec3::UnitZ();
  sm.right.position = Vec3(0, 0, L);
  sm.gravity = Vec3(0, -g, 0);
  sm.point_forces.push_back({Vec3(0, -weight, 0), s0});
  return sm;
}

inline rod::RodModel hanging_cable_model(const rod::RodProperties& props, int cells, double L, double g) {
  rod::RodModel m;
  m.props = props;
  m.num_cells = cells;
  m.length = L;
  m.left = rod::EndCondition::make_clamped();
  m.right = rod::EndCondition::make_sliding(Vec3::UnitZ());
  m.loads.gravity = Vec3(0, -g, 0);
  return m;
}

/// The static equilibrium of `sm` (load steps from the straight state) as the dynamic state
/// at rest; `converged` says whether the static solve converged.
inline rod::RodState static_start(const rod::StaticModel& sm, bool& converged) {
  auto nodes = rod::straight_static_state(sm);
  converged = rod::serial_load_steps(sm, nodes).converged;
  return rod::dynamic_state_from_static(sm, nodes);
}

/// A mass M moving from s = 0 at constant speed v (inertia: its inertia terms, else its weight only).
inline rod::MovingMass uniform_mass(double M, double v, bool inertia) {
  rod::MovingMass mm;
  mm.mass = M;
  mm.sigma = [v](double t) { return v * t; };
  mm.speed = [v](double) { return v; };
  mm.accel = [](double) { return 0.0; };
  mm.inertia = inertia;
  return mm;
}

}  // namespace traverse::testing

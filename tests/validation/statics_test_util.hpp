#pragma once
// Shared set-ups of the statics tests: the scene rod in standard configurations.
#include <cmath>

#include "traverse/rod/static_problem.hpp"

namespace traverse::statics_test {

/// Straight rod along +k from the origin: left end pinned about i, right end a roller
/// (pin i, sliding along k) loaded by a compressive force P = end_load.
inline rod::StaticProblem pinned_roller(int cells, double length = 1.0) {
  rod::StaticProblem p;
  p.base.props = rod::RodProperties::scene_rod();
  p.base.num_cells = cells;
  p.base.length = length;
  p.base.left.type = rod::EndCondition::Type::pinned;
  p.base.left.axis = Vec3::UnitX();
  p.base.right.type = rod::EndCondition::Type::roller;
  p.base.right.axis = Vec3::UnitX();
  p.base.right.slide_axis = Vec3::UnitZ();
  p.base.right.position = Vec3(0.0, 0.0, length);
  p.end_load_direction = -Vec3::UnitZ();
  p.end_position_axis = Vec3::UnitZ();
  p.value(rod::StaticParameter::end_position) = length;
  return p;
}

inline double bending_stiffness(const rod::StaticProblem& p) { return p.base.props.K(0); }

}  // namespace traverse::statics_test

#include "traverse/rod/static_problem.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace traverse::rod {

namespace {
const char* const kNames[num_static_parameters] = {"end_load", "end_position", "gravity_factor",
                                                   "load_position", "load_magnitude"};
const char* const kUnits[num_static_parameters] = {"N", "m", "1", "m", "N"};
}  // namespace

std::string parameter_name(StaticParameter p) {
  const int i = static_cast<int>(p);
  if (i < 0 || i >= num_static_parameters) throw std::logic_error("parameter_name: unknown parameter");
  return kNames[i];
}

std::string parameter_unit(StaticParameter p) {
  const int i = static_cast<int>(p);
  if (i < 0 || i >= num_static_parameters) throw std::logic_error("parameter_unit: unknown parameter");
  return kUnits[i];
}

StaticParameter parameter_from_name(const std::string& name) {
  for (int i = 0; i < num_static_parameters; ++i)
    if (name == kNames[i]) return static_cast<StaticParameter>(i);
  std::string valid;
  for (int i = 0; i < num_static_parameters; ++i) valid += std::string(i ? ", " : "") + kNames[i];
  throw std::invalid_argument("unknown continuation parameter '" + name + "' (expected one of " + valid + ")");
}

StaticModel StaticProblem::model() const { return model(values); }

StaticModel StaticProblem::model(const std::array<double, num_static_parameters>& v) const {
  StaticModel m = base;
  auto val = [&](StaticParameter p) { return v[static_cast<size_t>(p)]; };
  m.gravity = val(StaticParameter::gravity_factor) * gravity;
  StaticEnd& e = m.right;
  using T = EndCondition::Type;
  const double P = val(StaticParameter::end_load);
  switch (e.type) {
    case T::free:
      e.end_force = P * end_load_direction;
      break;
    case T::sliding:
      e.axial_force = P * end_load_direction.dot(e.axis.normalized());
      break;
    case T::roller:
      e.axial_force = P * end_load_direction.dot(e.slide_axis.normalized());
      break;
    case T::clamped:
    case T::pinned:
      break;
    default:
      throw std::invalid_argument("StaticProblem: the right end type has no static form");
  }
  if (e.type != T::free) {
    const Vec3 a = end_position_axis.normalized();
    e.position += (val(StaticParameter::end_position) - a.dot(e.position)) * a;
  }
  if (has_point_load)
    m.point_forces.push_back({val(StaticParameter::load_magnitude) * load_direction,
                              val(StaticParameter::load_position)});
  return m;
}

Vec3 position_at(const StaticModel& m, const std::vector<StaticNode>& nodes, double s) {
  const double ds = m.ds();
  const int N = m.num_cells;
  const double q = std::clamp(s / ds, 0.0, static_cast<double>(N));
  const int j = std::min(static_cast<int>(std::floor(q)), N - 1);
  const double w = q - j;
  return (1.0 - w) * nodes[static_cast<size_t>(j)].x.segment<3>(svar::r) +
         w * nodes[static_cast<size_t>(j + 1)].x.segment<3>(svar::r);
}

StaticProbe probe_end_compression(const Vec3& axis, std::string name) {
  const Vec3 a = axis.normalized();
  return {std::move(name), "N", [a](const StaticModel&, const std::vector<StaticNode>& n) {
            const StaticNode& e = n.back();
            return -(e.frame().transpose() * e.x.segment<3>(svar::n)).dot(a);
          }};
}

StaticProbe probe_position(double s, int c, std::string name) {
  if (c < 0 || c > 2) throw std::invalid_argument("probe_position: component must be 0, 1 or 2");
  return {std::move(name), "m", [s, c](const StaticModel& m, const std::vector<StaticNode>& n) {
            return position_at(m, n, s)(c);
          }};
}

StaticProbe probe_end_distance(std::string name) {
  return {std::move(name), "m", [](const StaticModel&, const std::vector<StaticNode>& n) {
            return (n.back().x.segment<3>(svar::r) - n.front().x.segment<3>(svar::r)).z();
          }};
}

}  // namespace traverse::rod

#include "traverse/rod/static_problem.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "traverse/core/so3.hpp"

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
  if (!set_end_load(e, val(StaticParameter::end_load), end_load_direction))
    throw std::invalid_argument("StaticProblem: the right end type has no static form");
  if (end_holds_position(e)) {
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

namespace {

// d (share F) / dp of `node` (0..N) for the load magnitude (the share) or the load position
// (F times the share's slope, point_load_slope).
double load_share_derivative(const StaticProblem& pr, const std::array<double, num_static_parameters>& v,
                             StaticParameter ip, int node) {
  const StaticModel& m = pr.base;
  const double sigma = v[static_cast<size_t>(StaticParameter::load_position)];
  if (ip == StaticParameter::load_position)
    return v[static_cast<size_t>(StaticParameter::load_magnitude)] * point_load_slope(sigma, node, m.num_cells, m.ds());
  return point_load_weights(sigma, m.num_cells, m.ds()).share(node);
}

}  // namespace

Vec12 static_cell_dfdp(const StaticProblem& pr, const std::array<double, num_static_parameters>& v,
                       StaticParameter ip, int j, const StaticNode& prev, const StaticNode& self) {
  Vec12 d = Vec12::Zero();
  const StaticModel& m = pr.base;
  const double ds = m.ds();
  const StaticNode* nd[2] = {&prev, &self};
  switch (ip) {
    case StaticParameter::gravity_factor:  // force rows: -1/2 (R_{j-1} + R_j) rhoA g
      for (int q = 0; q < 2; ++q) d.head<3>() -= 0.5 * (nd[q]->frame() * (m.props.rhoA * pr.gravity));
      return d;
    case StaticParameter::load_magnitude:
    case StaticParameter::load_position: {  // force rows: -1/2 w_k / ds R_k F
      if (!pr.has_point_load) return d;
      for (int q = 0; q < 2; ++q) {
        const int node = j - 1 + q;
        if (node == 0 || node == m.num_cells) continue;  // an end node's share acts in the end's rows
        const double w = load_share_derivative(pr, v, ip, node);  // d (share F) / dp
        if (w != 0.0) d.head<3>() -= 0.5 * w / ds * (nd[q]->frame() * pr.load_direction);
      }
      return d;
    }
    case StaticParameter::end_load:
    case StaticParameter::end_position: return d;
    default: throw std::logic_error("static_cell_dfdp: unknown parameter");
  }
}

Vec6 static_end_dfdp(const StaticProblem& pr, const std::array<double, num_static_parameters>& v,
                     StaticParameter ip, const StaticNode& node, bool right) {
  Vec6 d = Vec6::Zero();
  if (ip == StaticParameter::load_magnitude || ip == StaticParameter::load_position) {
    // The rows read n - sign R F_end (static_end_rows), F_end the load's end share.
    const double w = pr.has_point_load ? load_share_derivative(pr, v, ip, right ? pr.base.num_cells : 0) : 0.0;
    if (w == 0.0) return d;
    const StaticModel m = pr.model(v);
    LocalBlock b;
    b.residual = VecX::Zero(6);
    b.jac.assign(1, MatX::Zero(6, 12));
    static_end_rows(m, right ? m.right : m.left, node, right ? 1.0 : -1.0, b);
    return -(right ? 1.0 : -1.0) * w * (b.jac[0].block<6, 3>(0, svar::n) * (node.frame() * pr.load_direction));
  }
  if (!right) return d;
  const StaticEnd& e = pr.base.right;
  if (ip == StaticParameter::end_load)  // the end's external force P * end_load_direction
    d = end_load_derivative(e, node, pr.end_load_direction);
  else if (ip == StaticParameter::end_position)  // rows b . (r - position)
    d = end_position_derivative(e, pr.end_position_axis.normalized());
  return d;
}

StaticProblem pinned_roller_problem(const RodProperties& props, int num_cells, double length, double g) {
  StaticProblem pr;
  pr.base.props = props;
  pr.base.num_cells = num_cells;
  pr.base.length = length;
  pr.base.left.type = EndCondition::Type::pinned;
  pr.base.left.axis = Vec3::UnitX();
  pr.base.right.type = EndCondition::Type::roller;
  pr.base.right.axis = Vec3::UnitX();
  pr.base.right.slide_axis = Vec3::UnitZ();
  pr.base.right.position = Vec3(0.0, 0.0, length);
  pr.gravity = Vec3(0.0, -g, 0.0);
  pr.end_load_direction = -Vec3::UnitZ();
  pr.end_position_axis = Vec3::UnitZ();
  pr.value(StaticParameter::end_position) = length;
  return pr;
}

StaticProblem pinned_arch_problem(StaticProblem formed, double dz) {
  formed.base.right.type = EndCondition::Type::pinned;
  formed.value(StaticParameter::end_load) = 0.0;
  formed.value(StaticParameter::end_position) = dz;
  formed.value(StaticParameter::gravity_factor) = 0.0;
  return formed;
}

double chord_cosine(const std::vector<StaticNode>& a, const std::vector<StaticNode>& b, const std::vector<Vec12>& mode) {
  double dot = 0.0, nm = 0.0, nt = 0.0;
  for (size_t j = 0; j < mode.size(); ++j)
    for (int first : {svar::r, svar::kappa, svar::n})
      for (int c = first; c < first + 3; ++c) {
        const double t = b[j].x(c) - a[j].x(c), f = mode[j](c);
        dot += t * f;
        nm += f * f;
        nt += t * t;
      }
  return (nm > 0.0 && nt > 0.0) ? std::abs(dot) / std::sqrt(nm * nt) : 0.0;
}

std::vector<Vec12> normalised_mode(const std::vector<StaticNode>& base, std::vector<StaticNode> nodes) {
  for (size_t j = 0; j < nodes.size(); ++j)
    nodes[j].x.segment<3>(svar::theta) =
        so3::left_jacobian(-base[j].x.segment<3>(svar::theta)) * nodes[j].x.segment<3>(svar::theta);
  double scale = 0.0;
  for (const auto& n : nodes) scale = std::max(scale, n.x.segment<3>(svar::r).cwiseAbs().maxCoeff());
  if (!(scale > 0.0)) scale = 1.0;
  double big = 0.0;
  for (const auto& n : nodes)
    for (int c = 0; c < 3; ++c)
      if (std::abs(n.x(c)) > std::abs(big) * (1.0 + 1e-9)) big = n.x(c);
  if (big < 0.0) scale = -scale;
  std::vector<Vec12> out;
  for (const auto& n : nodes) out.push_back(n.x / scale);
  return out;
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

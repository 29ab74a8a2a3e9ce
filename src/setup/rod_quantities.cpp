#include "traverse/setup/rod_quantities.hpp"

#include <stdexcept>

namespace traverse::setup {

using scene::Field;
using scene::Quantity;

NodeView node_view(const rod::RodNode& node, const Vec3& r) {
  NodeView v;
  v.R = node.R;
  v.r = r;
  v.u = node.y.segment<3>(rod::var::u);
  v.omega = node.y.segment<3>(rod::var::omega);
  v.kappa = node.y.segment<3>(rod::var::kappa);
  v.n = node.y.segment<3>(rod::var::n);
  v.kappa_t = node.yt.segment<3>(rod::var::kappa);
  v.strain_rate = node.yt.segment<3>(rod::var::n);
  return v;
}

NodeView node_view(const rod::StaticNode& node) {
  NodeView v;
  v.R = node.frame();
  v.r = node.x.segment<3>(rod::svar::r);
  v.kappa = node.x.segment<3>(rod::svar::kappa);
  v.n = node.x.segment<3>(rod::svar::n);
  return v;
}

const std::string& quantity_unit(Quantity q) {
  static const std::vector<std::string> units{"m", "m/s", "rad/s", "1/m", "N", "N m", "1", "1", "1", "1"};
  return units.at(static_cast<std::size_t>(q));
}

Vec3 quantity_value(Quantity q, const NodeView& node, const rod::RodProperties& props, scene::Frame frame) {
  Vec3 v;
  switch (q) {
    case Quantity::position: return node.r;
    case Quantity::d1: return node.R.row(0).transpose();
    case Quantity::d2: return node.R.row(1).transpose();
    case Quantity::d3: return node.R.row(2).transpose();
    case Quantity::u: v = node.u; break;
    case Quantity::omega: v = node.omega; break;
    case Quantity::kappa: v = node.kappa; break;
    case Quantity::n: v = node.n; break;
    case Quantity::m:
      v = props.moment(node.kappa);
      if (props.B_bt != Vec3::Zero()) v += props.B_bt.cwiseProduct(node.kappa_t);  // the viscous part
      break;
    case Quantity::v: v = props.compliant() ? props.strain(node.n, node.strain_rate) : Vec3(Vec3::UnitZ()); break;
    default: throw std::logic_error("quantity_value: unknown quantity");
  }
  return frame == scene::Frame::fixed ? Vec3(node.R.transpose() * v) : v;
}

RodFieldInfo rod_field_info(Field f) {
  const std::vector<std::string> d123{"1", "2", "3"};
  switch (f) {
    case Field::u: return {3, "m/s", "velocity, body components", d123};
    case Field::omega: return {3, "rad/s", "spin, body components", d123};
    case Field::kappa: return {3, "1/m", "curvature and twist, body components", d123};
    case Field::n: return {3, "N", "contact force, body components", d123};
    case Field::m: return {3, "N m", "contact moment K (kappa - kappa0) (+ B_bt kappa_t), body components", d123};
    case Field::v:
      return {3, "1", "strain dr/ds, body components: shears v1, v2 and stretch v3 (e3 when inextensible)", d123};
    case Field::stretch: return {1, "1", "stretch |dr/ds| of the centreline (1 when inextensible)", {}};
    case Field::axial_force: return {1, "N", "contact force along the tangent, n . v / |v| (tension > 0)", {}};
    case Field::r: return {3, "m", "centreline, fixed components", {"x", "y", "z"}, true};
    case Field::R:
      return {9, "1", "orientation: rows d1, d2, d3 in fixed components",
              {"d1x", "d1y", "d1z", "d2x", "d2y", "d2z", "d3x", "d3y", "d3z"}};
    default: throw std::logic_error("rod_field_info: not a rod field: " + scene::name_of(f));
  }
}

Quantity field_quantity(Field f) {
  switch (f) {
    case Field::u: return Quantity::u;
    case Field::omega: return Quantity::omega;
    case Field::kappa: return Quantity::kappa;
    case Field::n: return Quantity::n;
    case Field::m: return Quantity::m;
    case Field::v: return Quantity::v;
    case Field::r: return Quantity::position;
    default: throw std::logic_error("field_quantity: no single quantity for field " + scene::name_of(f));
  }
}

void field_values(Field f, const NodeView& node, const rod::RodProperties& props, double* out) {
  switch (f) {
    case Field::R:
      for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c) out[3 * i + c] = node.R(i, c);
      return;
    case Field::stretch: out[0] = quantity_value(Quantity::v, node, props, scene::Frame::body).norm(); return;
    case Field::axial_force: {
      const Vec3 v = quantity_value(Quantity::v, node, props, scene::Frame::body);
      out[0] = node.n.dot(v) / v.norm();
      return;
    }
    default: {
      const Vec3 v = quantity_value(field_quantity(f), node, props, scene::Frame::body);
      std::copy(v.data(), v.data() + 3, out);
    }
  }
}

void declare_rod_probes(output::Writer& w, const std::vector<scene::OutputProbeSpec>& probes) {
  const std::vector<std::string> xyz{"x", "y", "z"}, d123{"1", "2", "3"};
  for (const auto& pr : probes) {
    const bool fixed = pr.frame == scene::Frame::fixed;
    w.add_probe({pr.name, 3, quantity_unit(pr.quantity),
                 scene::name_of(pr.quantity) + " at s = " + scene::format_number(pr.at) + " m, " +
                     (fixed ? "fixed-frame components (i, j, k)" : "body components (d1, d2, d3)"),
                 fixed ? xyz : d123});
  }
}

}  // namespace traverse::setup

#pragma once
// The rod's output quantities in one table: what a probe or a field of a rod run measures,
// its unit, and its value at a node. Dynamic runs (probes and fields) and continuation runs
// (continuation probes) both read it.
#include <string>
#include <vector>

#include "traverse/core/types.hpp"
#include "traverse/rod/rod_properties.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/rod/static_kernels.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::setup {

/// The values a quantity is computed from at one node. Static nodes have u = omega = 0.
struct NodeView {
  Mat3 R = Mat3::Identity();  ///< rows d1, d2, d3 in fixed components
  Vec3 r = Vec3::Zero();      ///< centreline [m] (when known)
  Vec3 u = Vec3::Zero(), omega = Vec3::Zero(), kappa = Vec3::Zero(), n = Vec3::Zero();  ///< body components
  /// The rates the viscosities and the strain read: kappa_t and the strain rate v_t (the
  /// histories' kappa and n slots; zero at rest and for static nodes).
  Vec3 kappa_t = Vec3::Zero(), strain_rate = Vec3::Zero();
};
NodeView node_view(const rod::RodNode& node, const Vec3& r);
NodeView node_view(const rod::StaticNode& node);

/// Unit of a quantity ("m", "m/s", "rad/s", "1/m", "N", "N m", "1").
const std::string& quantity_unit(scene::Quantity q);

/// The quantity at a node: directors and the position in fixed components; the others in
/// body components, or fixed (R^T v) when `frame` is fixed.
Vec3 quantity_value(scene::Quantity q, const NodeView& node, const rod::RodProperties& props, scene::Frame frame);

/// The quantity at arclength s, linear between the nodes around it (rod::locate_on_nodes);
/// `node(j)` gives the view of node j.
template <class NodeAt>
Vec3 quantity_at(scene::Quantity q, double s, double ds, int num_cells, const rod::RodProperties& props,
                 scene::Frame frame, const NodeAt& node) {
  const rod::NodeInterpolation loc = rod::locate_on_nodes(s, ds, num_cells);
  return (1.0 - loc.xi) * quantity_value(q, node(loc.j), props, frame) +
         loc.xi * quantity_value(q, node(loc.j + 1), props, frame);
}

/// Declares the scene's rod probes (3 components each, body or fixed frame) in `w`.
void declare_rod_probes(output::Writer& w, const std::vector<scene::OutputProbeSpec>& probes);

/// A field of a rod run: how it is declared in the output file.
struct RodFieldInfo {
  std::size_t components = 3;
  std::string units, description;
  std::vector<std::string> component_names;
  bool geometry = false;  ///< the node positions of the sidecar
};
RodFieldInfo rod_field_info(scene::Field f);

/// The quantity a rod field holds at every node (r: position, R, stretch, axial_force: none, the
/// others theirs).
scene::Quantity field_quantity(scene::Field f);

/// A rod field's rod_field_info(f).components values at a node into `out`: R's rows, the
/// stretch |v|, the axial force n . v / |v|, the others their quantity in body components.
void field_values(scene::Field f, const NodeView& node, const rod::RodProperties& props, double* out);

}  // namespace traverse::setup

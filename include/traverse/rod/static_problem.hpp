#pragma once
// The static problem with its continuation parameters (docs/statics.md): a base
// StaticModel plus five scalar parameters that set the end load, the right end's position
// along an axis, the gravity factor, and the position and magnitude of one point force.
// Also the scalar probes of a static state used by continuation runs. No Trilinos here.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "traverse/rod/static_kernels.hpp"

namespace traverse::rod {

/// The continuation parameters, in the order of the parameter vector.
enum class StaticParameter {
  end_load = 0,    ///< P [N]: external force on the right end = P * end_load_direction
  end_position,    ///< [m]: the right end's position component along end_position_axis
  gravity_factor,  ///< [-]: gravity = factor * StaticProblem::gravity
  load_position,   ///< sigma [m]: arclength of the point force
  load_magnitude,  ///< F [N]: point force = F * load_direction
};
inline constexpr int num_static_parameters = 5;

/// "end_load", "end_position", "gravity_factor", "load_position", "load_magnitude".
std::string parameter_name(StaticParameter p);
/// Inverse of parameter_name; throws std::invalid_argument naming the valid names.
StaticParameter parameter_from_name(const std::string& name);
/// SI unit of a parameter ("N", "m", "1").
std::string parameter_unit(StaticParameter p);

struct StaticProblem {
  /// Geometry, section, end types, frames and fixed positions; gravity, point forces and the
  /// fields set by parameters are overwritten by model().
  StaticModel base;
  Vec3 gravity = Vec3(0.0, -9.8, 0.0);          ///< gravity at factor 1 [m/s^2], fixed frame
  /// Direction of the right end's external load: a free end gets end_force = P * d; a
  /// sliding or roller end gets axial_force = P * (d . e) along its sliding axis e.
  Vec3 end_load_direction = -Vec3::UnitZ();     ///< default: compression of a rod along +k
  Vec3 end_position_axis = Vec3::UnitZ();       ///< unit axis of the end_position parameter
  bool has_point_load = false;                  ///< whether the point force exists
  Vec3 load_direction = -Vec3::UnitY();         ///< unit direction of the point force
  std::array<double, num_static_parameters> values{};  ///< current parameter values

  double value(StaticParameter p) const { return values[static_cast<size_t>(p)]; }
  double& value(StaticParameter p) { return values[static_cast<size_t>(p)]; }
  /// The point force `force` [N] (fixed frame) at `position` [m]: its direction, magnitude and
  /// position (no point force when it is zero).
  void set_point_load(const Vec3& force, double position) {
    const double F = force.norm();
    has_point_load = F > 0.0;
    if (has_point_load) load_direction = force / F;
    value(StaticParameter::load_magnitude) = F;
    value(StaticParameter::load_position) = position;
  }
  /// The base model with the parameters applied (see StaticParameter).
  StaticModel model() const;
  /// The same with `vals` in place of `values`.
  StaticModel model(const std::array<double, num_static_parameters>& vals) const;
};

/// dF/dp: the derivative of the static residual with respect to parameter `ip` at the
/// parameter values `v`, analytic. F is affine in the end load, the end position, the
/// gravity factor and the load magnitude, and piecewise linear in the load position (the
/// weights are kinked at the nodes: on an interior node the mean of the two cells' slopes, as
/// a central difference gives it).
/// Cell j's 12 rows (rows 6 + 12 (j - 1) ...) and an end's 6 rows (left: rows 0 ..., right:
/// rows 12 N + 6 ...; the left end's depend only on the point load, through its end share).
Vec12 static_cell_dfdp(const StaticProblem& pr, const std::array<double, num_static_parameters>& v,
                       StaticParameter ip, int j, const StaticNode& prev, const StaticNode& self);
Vec6 static_end_dfdp(const StaticProblem& pr, const std::array<double, num_static_parameters>& v,
                     StaticParameter ip, const StaticNode& node, bool right);

/// The hinged rod of the arch scenes before forming: length L along k, pinned at s = 0 and on
/// a roller at s = L (pin axes i, sliding along k), compressed by the end load along -k,
/// gravity g [m/s^2] along -j at factor 1; end_position starts at L.
StaticProblem pinned_roller_problem(const RodProperties& props, int num_cells, double length, double g);

/// The formed arch: the problem `formed` with its right end pinned at the end-to-end distance
/// dz [m] along k, no end load and gravity factor 0 (raised afterwards).
StaticProblem pinned_arch_problem(StaticProblem formed, double dz);

/// |cos| of the angle between the chord b - a of two static states and a mode (per node 12
/// components in the static layout), on the frame-independent unknowns r, kappa and n: about 1
/// when the mode lies along the branch (a fold), about 0 when orthogonal to it (a pitchfork).
double chord_cosine(const std::vector<StaticNode>& a, const std::vector<StaticNode>& b, const std::vector<Vec12>& mode);

/// A small-vibration mode of the static state `base` (per node 12 components in the static
/// layout, rotation increments relative to each node's Rbar) in the coordinates of the rebased
/// state (theta = 0: dtheta' = -D(theta) dtheta, so3::left_jacobian(-theta) dtheta), scaled to
/// max |r| = 1 with its largest displacement component positive (a deterministic sign).
std::vector<Vec12> normalised_mode(const std::vector<StaticNode>& base, std::vector<StaticNode> mode);

/// A scalar measured on a static state (gathered on every rank).
struct StaticProbe {
  std::string name;  ///< e.g. "end_compression"
  std::string unit;  ///< e.g. "N"
  std::function<double(const StaticModel&, const std::vector<StaticNode>&)> eval;
};

/// -n(L) . axis: the compressive force carried at the right end along `axis` (fixed frame) [N].
StaticProbe probe_end_compression(const Vec3& axis = Vec3::UnitZ(), std::string name = "end_compression");
/// Component `c` (0 = x/i, 1 = y/j, 2 = z/k) of r(s), linear between nodes [m].
StaticProbe probe_position(double s, int c, std::string name);
/// (r(L) - r(0)) . k: the end-to-end distance along k [m].
StaticProbe probe_end_distance(std::string name = "end_distance");

/// r(s) interpolated linearly between nodes [m].
Vec3 position_at(const StaticModel& m, const std::vector<StaticNode>& nodes, double s);

}  // namespace traverse::rod

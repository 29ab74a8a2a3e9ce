#pragma once
// Static form of the rod discretisation (docs/statics.md): u = omega = 0, no time
// derivatives; the frame and the centreline along s become unknowns. Per node
// x = (r, theta, kappa, n): centreline r [m] (fixed components), rotation increment theta
// [rad] with R = exp(-hat(theta)) Rbar about a reference frame Rbar carried with the node,
// curvature kappa [1/m] and contact force n [N] (body components). 12 unknowns per node, the
// same count, row layout and block-tridiagonal coupling as the dynamic box scheme:
//   rows [0, 6): left end; 6 + 12 (j-1) + (0..11): cell (j-1, j); last 6: right end.
// Cell rows (the dynamic box-scheme rows at rest, plus the frame and centreline):
//   0-2   -(n_j - n_{j-1})/ds + avg(-kappa x n - R f) - point forces         (force balance)
//         (a point force's share of an end node acts in that end's rows instead)
//   3-5   -K (kappa_j - kappa_{j-1})/ds + avg(-kappa x m - v x n - R l)      (moment balance)
//   6-8   (log(R_j R_{j-1}^T) + ds avg(kappa)) / ds                           (frame follows kappa)
//   9-11  (r_j - r_{j-1})/ds - avg(R^T v)                                      (centreline, trapezoidal)
// with the strain v = e3 + C n of a rod that strains (RodProperties::C), e3 for the inextensible rod.
// avg() is the cell average (value at j-1 + value at j)/2: the frame relation is the midpoint
// exponential of state_from_curvature and the centreline the trapezoidal rule, both second order.
#include <vector>

#include "traverse/rod/end_condition.hpp"
#include "traverse/rod/rod_kernels.hpp"

namespace traverse::rod {

/// Index of each vector unknown inside the static node block.
namespace svar {
inline constexpr int r = 0;      ///< centreline [m], fixed components
inline constexpr int theta = 3;  ///< rotation increment [rad], R = exp(-hat(theta)) Rbar
inline constexpr int kappa = 6;  ///< curvature [1/m], body components
inline constexpr int n = 9;      ///< contact force [N], body components
}  // namespace svar

/// An end condition read statically: the same types as the dynamic ones, with the end's
/// position and frame fixed where the dynamic condition fixes the velocity and spin.
///   clamped:  r = position (3), log(R frame^T) = 0 (3)
///   pinned:   r = position (3), log(frame^T R) parallel to the pin axis a (2), m . (R a) = 0 (1)
///   sliding:  r - position perpendicular to e is 0 (2), log(R frame^T) = 0 (3),
///             external force along e = axial_force (1)
///   free:     external force = end_force (3), m = 0 (3)
///   roller:   r - position perpendicular to slide_axis e is 0 (2), external force along e =
///             axial_force (1), log(frame^T R) parallel to the pin axis a (2), m . (R a) = 0 (1)
/// External forces act on the rod at that end: n(L) = F at the right end, n(0) = -F at the left.
/// The scene's parameters (EndSpec) are read as in EndCondition: `axis` the pin axis (pinned,
/// roller) or sliding axis (sliding), `slide_axis` the roller's sliding axis e, `axial_force`
/// the external force along the sliding axis [N] (sliding, roller).
struct StaticEnd : EndSpec {
  Vec3 position = Vec3::Zero();    ///< [m]
  Mat3 frame = Mat3::Identity();   ///< fixed -> body at the end
  Vec3 end_force = Vec3::Zero();   ///< free: external force, fixed frame [N]
};

/// The static reading of a scene end at `position` (the type EndCondition::static_type
/// gives, the frame the identity).
StaticEnd static_end(const EndSpec& spec, const Vec3& position);

/// A point force at a fixed arclength (statics).
struct StaticPointForce {
  Vec3 force = Vec3::Zero();  ///< fixed frame [N]
  double sigma = 0.0;         ///< [m]
};

struct StaticModel {
  RodProperties props;
  int num_cells = 1;
  double length = 1.0;
  StaticEnd left, right;
  Vec3 gravity = Vec3::Zero();                 ///< fixed frame [m/s^2]
  std::vector<StaticPointForce> point_forces;  ///< shared by the nodes as PointLoadWeights
  double ds() const { return length / num_cells; }
  Eigen::Index num_unknowns() const { return 12 * static_cast<Eigen::Index>(num_cells + 1); }
};

/// One node: unknowns and the reference frame they are measured from.
struct StaticNode {
  Vec12 x = Vec12::Zero();
  Mat3 Rbar = Mat3::Identity();
  /// R = exp(-hat(theta)) Rbar.
  Mat3 frame() const;
  /// Folds theta into Rbar (theta = 0 afterwards; the frame is unchanged).
  void rebase();
};

/// The left perturbation D of R = exp(-hat(theta)) Rbar: dR = hat(D dtheta) R.
Mat3 frame_perturbation(const Vec3& theta);

/// The 6 rows of an end (the static rows of its type's table entry, end_condition.cpp) into
/// b (rows 0..5, Jacobian b.jac[0]); `sign` of external forces: +1 right end, -1 left end.
void static_end_rows(const StaticModel& m, const StaticEnd& c, const StaticNode& node, double sign, LocalBlock& b);

/// The point forces' shares of end node 0 (left) or N (right), fixed frame [N]
/// (PointLoadWeights): the end rows read n - sign R F, so a free, sliding or roller end
/// carries it and a held position absorbs it.
Vec3 static_end_point_force(const StaticModel& m, bool right);

/// The end load P along `direction` (fixed frame) of a continuation on this end, set in e
/// (free: the end force; sliding, roller: the force along the sliding axis; clamped, pinned:
/// none). False for a type without a static form (prescribed).
bool set_end_load(StaticEnd& e, double P, const Vec3& direction);
/// d(rows)/dP of that load at `node`.
Vec6 end_load_derivative(const StaticEnd& e, const StaticNode& node, const Vec3& direction);
/// Whether the end's rows hold its position (in full or across its sliding axis): a
/// continuation of the end position moves it (not free).
bool end_holds_position(const StaticEnd& e);
/// d(rows)/dp of the end position p along the unit `axis` (position += (p - axis . position) axis).
Vec6 end_position_derivative(const StaticEnd& e, const Vec3& axis);

/// Cell (j-1, j): 12 rows at 6 + 12 (j-1), Jacobian blocks for nodes j-1 and j.
LocalBlock static_cell_block(const StaticModel& m, int j, const StaticNode& prev, const StaticNode& self);
/// The inertia of small vibrations about a static state in the rows of cell (j-1, j): the
/// dynamic rows are (static rows) + M_s x'' with, in the force rows, rhoA (R_a r''_a +
/// R_b r''_b)/2 (body acceleration u' = R r'') and, in the moment rows, rhoI (omega'_a +
/// omega'_b)/2 with omega = -D theta' (= theta' at theta = 0). Other rows carry no inertia.
/// Same row and column layout as static_cell_block; the residual is zero.
LocalBlock static_mass_block(const StaticModel& m, int j, const StaticNode& prev, const StaticNode& self);

/// End rows: left at rows 0..5 (node 0), right at rows 12 N + 6 .. (node N).
LocalBlock static_left_block(const StaticModel& m, const StaticNode& node);
LocalBlock static_right_block(const StaticModel& m, const StaticNode& node);

/// Straight rod along Rbar^T e3 from r0, at rest and unloaded (kappa = 0, n = 0).
std::vector<StaticNode> straight_static_state(const StaticModel& m, const Vec3& r0 = Vec3::Zero(),
                                              const Mat3& R0 = Mat3::Identity());

/// Nodes first .. first + count - 1 of that state (one rank's piece).
std::vector<StaticNode> straight_static_nodes(const StaticModel& m, int first, int count, const Vec3& r0 = Vec3::Zero(),
                                              const Mat3& R0 = Mat3::Identity());

/// The dynamic state at rest with the same frames, curvature and force (u = omega = 0,
/// yt = 0; ys by centred differences, one-sided second order at the ends).
RodState dynamic_state_from_static(const StaticModel& m, const std::vector<StaticNode>& nodes);
/// The same for nodes from .. from + count - 1 of the rod, from static nodes first ..
/// first + nodes.size() - 1 that hold their neighbours (two more at the rod's ends).
std::vector<RodNode> dynamic_nodes_from_static(const StaticModel& m, const std::vector<StaticNode>& nodes, int first,
                                               int from, int count);

}  // namespace traverse::rod

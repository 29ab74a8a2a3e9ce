#pragma once
// State of a discretised rod at one time level: per node the 12 unknowns
// y = (u, omega, kappa, n) in body components, the orientation R and the histories yt, ys.
#include <functional>
#include <string>
#include <vector>

#include "traverse/core/types.hpp"
#include "traverse/rod/alpha_parameters.hpp"
#include "traverse/rod/rod_properties.hpp"

namespace traverse::rod {

/// Index of the first entry of each vector unknown inside y (and inside yt, ys).
namespace var {
inline constexpr int u = 0;      ///< velocity [m/s]
inline constexpr int omega = 3;  ///< spin [rad/s]
inline constexpr int kappa = 6;  ///< curvature/twist [1/m]
inline constexpr int n = 9;      ///< contact force [N]
}  // namespace var

/// One node at one time level.
struct RodNode {
  /// A node whose members are all about to be assigned (no zeroing first).
  struct NoInit {};
  RodNode() = default;
  explicit RodNode(NoInit) : y(), R(), yt(), ys(), yv(), yg(), kst() {}

  Vec12 y = Vec12::Zero();    ///< (u, omega, kappa, n), body components
  Mat3 R = Mat3::Identity();  ///< fixed -> body components; rows are d1, d2, d3 (fixed comps)
  Vec12 yt = Vec12::Zero();   ///< time-derivative history (generalised-alpha), zero at rest
  Vec12 ys = Vec12::Zero();   ///< space-derivative history (used only when ys is carried)
  /// (y - y of the level before) / dt of the step that made this level: the slope of the next
  /// step's Newton initial guess y + dt yv (StepAssembly::initial_guess); zero at a start.
  Vec12 yv = Vec12::Zero();
  /// The slope of the next step's guess with 'Initial Guess: auto', y + dt yg: each entry of
  /// yv where the secant guess predicted that entry's change in the step that made this level
  /// to within half of the change, else zero (advance_node); zero at a start, and everywhere
  /// after a step that Newton solved only from the old level (solver::RodStepper::attempt).
  Vec12 yg = Vec12::Zero();
  /// The time-derivative history (generalised alpha) of the carried kappa_s, which the bending
  /// and torsion viscosity reads with rho_inf_space < 1 ((B kappa_t)_s = B (kappa_s)_t); zero
  /// otherwise.
  Vec3 kst = Vec3::Zero();
};

/// A node as plain numbers (restart points, gathers over ranks): y (12), R row-major (9),
/// yt (12), ys (12), yv (12), yg (12), kst (3).
inline constexpr std::size_t kPackedNodeValues = 72;
void pack_node(const RodNode& nd, double* o);
RodNode unpack_node(const double* o);

/// Nodes j = 0..N at spacing ds = L / N, at time t.
struct RodState {
  double t = 0.0;  ///< [s]
  double ds = 0.0; ///< [m]
  std::vector<RodNode> nodes;
  int num_cells() const { return static_cast<int>(nodes.size()) - 1; }
};

/// Straight rod at rest, d3 = R0^T e3 the tangent (R0 = I: along k), kappa = kappa0 = 0
/// assumed, n = 0, all histories zero.
RodState straight_rest_state(int num_cells, double length, const Mat3& R0 = Mat3::Identity());

/// Rod at rest whose curvature is kappa(s) (body components): R follows dR/ds = -hat(kappa) R
/// from R(0) = R0 with the midpoint exponential R_j = exp(-hat(ds (kappa_{j-1}+kappa_j)/2)) R_{j-1}
/// (second order). u = omega = 0, n = 0 (set n yourself if the state must be in equilibrium),
/// yt = 0; ys = d y / ds by centred differences (one-sided second order at the ends) so that a
/// carried-ys run starts from a consistent spatial history.
RodState state_from_curvature(int num_cells, double length,
                              const std::function<Vec3(double)>& kappa,
                              const Mat3& R0 = Mat3::Identity());

/// Discrete energy (kinetic + bending/torsion) [J], the quantity the centred box scheme
/// conserves exactly for the linearised rod: sum over cells of
/// ds * (1/2 rhoA |ub|^2 + 1/2 wb . rhoI wb + 1/2 (kb - kappa0) . K (kb - kappa0)) with
/// ub, wb, kb the cell averages (y(j-1) + y(j)) / 2.
double discrete_energy(const RodState& state, const RodProperties& props);

/// Same energy, trapezoidal rule over the nodes (for output; not exactly conserved).
double nodal_energy(const RodState& state, const RodProperties& props);
/// Both energies include, for a rod that strains, the strain energy 1/2 d . C^-1 d of the
/// strain deviation d = v - e3 (strain_deviation; cell averages in discrete_energy) over the
/// directions it strains in.

/// The strain deviation v - e3 = C n - tau v_t of a node (v_t: the n slot of yt), zero for the
/// inextensible rod.
Vec3 strain_deviation(const RodNode& node, const RodProperties& props);

/// The Kelvin-Voigt dissipation rate over the step from old_state to state [W]: sum over cells
/// of ds (vb . B_se vb + kb . B_bt kb), vb and kb the cell averages of the secant rates
/// (d_new - d_old) / dt of the strain deviation and of kappa. With discrete_energy, the
/// centred box scheme's balance for the linearised rod: E(state) - E(old_state) = -dt times it
/// (plus the work of the loads and the ends).
double discrete_dissipation(const RodState& old_state, const RodState& state, const RodProperties& props);

/// Centreline at the nodes from r(0) = r0 by the trapezoidal rule on dr/ds = R^T e3
/// (second order). Fixed components [m].
std::vector<Vec3> centreline_in_space(const RodState& state, const Vec3& r0 = Vec3::Zero());

/// The tangent dr/ds = R^T e3 of a node (its director d3, fixed components).
inline Vec3 tangent(const RodNode& node) { return node.R.row(2).transpose(); }
/// The tangent dr/ds = R^T v of a node of the rod `props` describes, v its strain
/// (RodProperties::strain of the node's n and of the strain rate in the n slot of yt): d3 for the
/// inextensible rod, stretched and sheared for one that strains (fixed components).
inline Vec3 tangent(const RodNode& node, const RodProperties& props) {
  if (!props.compliant()) return tangent(node);
  return node.R.transpose() * props.strain(node.y.segment<3>(var::n), node.yt.segment<3>(var::n));
}

/// The same rule along consecutive nodes given by their tangents, from r = r_first at the
/// first of them: r_k = r_{k-1} + ds/2 (t_{k-1} + t_k). centreline_in_space is this from r0
/// at node 0 (the same sums in the same order).
std::vector<Vec3> centreline_from(const std::vector<Vec3>& tangents, double ds, const Vec3& r_first);

/// The centreline of a rod held in pieces (each rank its nodes) without the whole state in
/// one place: each piece's summary (centreline_piece), the summaries of all pieces merged
/// (centreline_starts) give each piece the position of its first node, from which
/// centreline_from integrates its own nodes.
struct CentrelinePiece {
  int first = 0;  ///< global index of the piece's first node
  int count = 0;  ///< nodes in the piece (0: empty)
  Vec3 first_tangent = Vec3::Zero();  ///< tangent at the piece's first node
  Vec3 last_tangent = Vec3::Zero();   ///< tangent at its last node
  /// The trapezoidal rule along the piece from `origin` to its last node [m]: the piece that
  /// holds node 0 starts from r0 (this is then r at its last node, by the sums of
  /// centreline_in_space), the others from zero (their span r(last) - r(first)).
  Vec3 end = Vec3::Zero();
};
/// The summary of nodes first .. first + tangents.size() - 1 given by their tangents;
/// `origin`: r0 for the piece that holds node 0, zero for the others.
CentrelinePiece centreline_piece(const std::vector<Vec3>& tangents, int first, double ds, const Vec3& origin);
/// r at the first node of each piece, in the order given, from r(0) = r0: the end of the
/// first piece and the spans of the later ones before it in node order, plus the trapezoid
/// of each cell between two pieces (the tangents at its ends). Two pieces give the sums of
/// centreline_in_space; more differ from them by rounding. The non-empty pieces must tile
/// the nodes 0 .. N without gaps or overlaps (std::invalid_argument otherwise); an empty
/// piece's start is unspecified.
std::vector<Vec3> centreline_starts(const std::vector<CentrelinePiece>& pieces, double ds, const Vec3& r0);

/// Where arclength s lies on nodes 0..N at spacing ds: between nodes j and j + 1, xi the
/// linear-interpolation weight of node j + 1 (s clamped to the rod).
struct NodeInterpolation {
  int j = 0;
  double xi = 0.0;
};
NodeInterpolation locate_on_nodes(double s, double ds, int num_cells);

/// A point output of a rod run at arclength s: the position r(s) (it needs the centreline)
/// or a quantity of the nodes around s (u, omega, kappa, n, m, d1, d2, d3).
struct PointOutput {
  double s = 0.0;
  bool position = false;
};

/// What a rod run's outputs read from the state at an output step (the centreline
/// is reconstructed only for outputs that need it, and never from a gathered state).
struct OutputNeeds {
  /// r(s) at the nodes: a "position" point output or the field "r" (each rank integrates its
  /// own nodes from the start centreline_starts gives it).
  bool centreline = false;
  /// The nodes the point outputs read (j and j + 1 of each), sorted, no repeats (with the
  /// centreline too: a position probe reads r at these two nodes); the fields read only each
  /// rank's own nodes.
  std::vector<int> nodes;
};
/// `centreline_field`: the fields include r.
OutputNeeds output_needs(int num_cells, double ds, const std::vector<PointOutput>& points, bool centreline_field);

/// Velocity of a node in fixed components, R^T u [m/s].
inline Vec3 fixed_velocity(const RodNode& node) { return node.R.transpose() * node.y.segment<3>(var::u); }

/// One trapezoidal step of dr/dt = v over h [s]: r + h/2 (v_old + v_new) (second order) [m].
inline Vec3 trapezoidal_step(const Vec3& r, const Vec3& v_old, const Vec3& v_new, double h) {
  return r + 0.5 * h * (v_old + v_new);
}

/// Advance nodal positions over one step by the trapezoidal rule on dr/dt = R^T u:
/// r_new = r_old + dt/2 (R_old^T u_old + R_new^T u_new) (second order). Fixed components [m].
std::vector<Vec3> advance_centreline_in_time(const std::vector<Vec3>& r_old,
                                             const RodState& old_state,
                                             const RodState& new_state);

/// The rod held whole on every rank, per node [bytes]: the initial state or restart point
/// (RodNode), the packed nodes of a gather, the centreline (measured as
/// solver::time_step_bytes_per_node is).
constexpr double kReplicatedBytesPerNode = 800.0;

}  // namespace traverse::rod

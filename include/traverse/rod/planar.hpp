#pragma once
// Planar fast path: when a rod problem is symmetric under the reflection through a
// fixed plane, the out-of-plane unknowns stay exactly zero and the step's Jacobian splits into
// an in-plane and an out-of-plane block, so the step can be solved with the in-plane half of
// the unknowns and rows only. This header detects the symmetry and maps kernel blocks (12 or 24
// unknowns per node, RodModel layout) to the planar layout (6 or 12 per node). Eigen only.
//
// Parity. Under the reflection x -> P x, P = I - 2 n n^T (n the plane's unit normal), a state
// whose body axis d_a (a = 0 or 1) is n at every node maps to the state with the frame
// (d_a, P d_b, P d3): in body components polar vectors (u, n, the momentum and
// inextensibility rows) change the sign of component a, axial vectors (omega, kappa, m, the
// angular-momentum and compatibility rows) change the sign of the two components other than
// a. The even ("in-plane") components of y = (u, omega, kappa, n) are therefore
//   a = 0 (normal d1): u2, u3, omega1, kappa1, n2, n3   (indices 1, 2, 3, 6, 10, 11)
//   a = 1 (normal d2): u1, u3, omega2, kappa2, n1, n3   (indices 0, 2, 4, 7, 9, 11)
// and the cell rows split the same way (same indices). Each end's 6 rows split 3 + 3,
// depending on the condition and its axes (found by probing the end rows, see check_planar).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "traverse/rod/rod_kernels.hpp"
#include "traverse/rod/rod_model.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/rod/static_kernels.hpp"

namespace traverse::rod {

/// The reflection symmetry of one rod problem.
struct PlanarSymmetry {
  Vec3 normal = Vec3::UnitX();  ///< unit normal of the plane, fixed components
  int axis = 0;                 ///< body axis equal to the normal at every node: 0 (d1) or 1 (d2)
  std::array<int, 3> left_rows{{0, 0, 0}};   ///< the in-plane rows among the left end's 6
  std::array<int, 3> right_rows{{0, 0, 0}};  ///< the in-plane rows among the right end's 6
  /// One line, e.g. "plane normal (1, 0, 0) = d1".
  std::string describe() const;
};

/// Result of check_planar.
struct PlanarCheck {
  bool planar = false;
  PlanarSymmetry symmetry;  ///< valid when planar
  std::string reason;       ///< why the problem is not planar (empty when planar)
};

/// Indices in y = (u, omega, kappa, n) of the 6 in-plane components for normal axis a.
std::array<int, 6> in_plane_components(int axis);

/// Whether `model` with the state `state` is reflection-symmetric about a plane whose
/// normal is a body axis d1 or d2 (tried in this order; d_a must be the same fixed vector at
/// every node). Checks, with relative tolerance `tol`:
///  * the intrinsic curvature kappa0 has only its component a;
///  * every node: d_a = normal, the out-of-plane components of y, yt and ys are zero
///    (relative to the largest entry of each);
///  * gravity and every point force vector lie in the plane; `point_force_vectors` holds the
///    (constant) fixed-frame vector of each entry of model.loads.point_forces (the functions
///    themselves are not inspected); moving masses need only gravity in the plane;
///    distributed loads given as functions (f_fixed, l_fixed) are not checked and make the
///    problem non-planar;
///  * each end's 6 rows split into 3 in-plane rows (no out-of-plane unknown enters them) and
///    3 out-of-plane rows (no in-plane unknown enters them and they vanish at symmetric
///    states): probed with end_condition_rows at random symmetric states at the state's time
///    and 3 later times (a prescribed motion is assumed to keep its direction).
/// The reason names what failed for each candidate axis.
PlanarCheck check_planar(const RodModel& model, const RodState& state,
                         const std::vector<Vec3>& point_force_vectors, double tol = 1e-12);

/// What check_planar needs of the state's nodes, for each candidate normal axis a (d1, d2):
/// the first node whose d_a differs from node 0's (-1: none) and by how much; for y, yt and
/// ys the largest out-of-plane entry, the first node holding it and the largest entry. Plain
/// numbers, so that the pieces of a distributed state can be summed up where they are and
/// merged (in node order) wherever they are needed.
struct PlanarStateSummary {
  long first_node = 0;  ///< of the nodes summed up
  std::array<long, 2> frame_node{{-1, -1}};
  std::array<double, 2> frame_dev{};
  std::array<std::array<double, 3>, 2> odd{}, all{};
  std::array<std::array<long, 3>, 2> odd_node{};
};
/// The summary of the nodes first_node .. of `piece`, R0 the frame of the rod's node 0.
PlanarStateSummary summarize_planarity(const RodState& piece, int first_node, const Mat3& R0);
/// Adds the summary of the nodes after `into`'s to `into`.
void merge(PlanarStateSummary& into, const PlanarStateSummary& later);
/// check_planar from the merged summary of the whole state, its end nodes and its time.
PlanarCheck check_planar(const RodModel& model, const PlanarStateSummary& summary, const RodNode& left_end,
                         const RodNode& right_end, double t, const std::vector<Vec3>& point_force_vectors,
                         double tol = 1e-12);

/// The planar layout of a RodModel and the maps between it and the full one.
///
/// Unknowns: node j owns [q j, q (j+1)), q = 6 (box scheme) or 12 (carried ys: the 6
/// in-plane components of y, then those of ys).
/// Rows, box scheme (6 (N+1)): [3 left-end rows, 6 per cell j = 1..N, 3 right-end rows];
/// carried ys (12 (N+1)): [3 left-end rows, 6 collocation rows, 12 per cell (6 PDE, 6
/// recursion), 3 right-end rows]. As in the full layout, row r belongs to node r / q and the
/// rows of node k come from the end blocks and cells k, k + 1 (nodes k-1..k+1 only).
class PlanarReduction {
 public:
  PlanarReduction(const RodModel& model, const PlanarSymmetry& symmetry);

  const PlanarSymmetry& symmetry() const { return sym_; }
  int unknowns_per_node() const { return q_; }      ///< q: 6 or 12
  int full_unknowns_per_node() const { return p_; }  ///< p: 12 or 24
  Eigen::Index num_rows() const { return static_cast<Eigen::Index>(q_) * (num_cells_ + 1); }
  /// Positions in a full node block (size p) of the q planar unknowns, in planar order.
  const std::vector<int>& kept_unknowns() const { return cols_; }

  /// Full node block (y, and ys when carried) -> its q in-plane entries.
  VecX restrict_unknowns(const VecX& full) const;
  /// q in-plane entries -> full node block with zeros in the out-of-plane entries.
  void embed(const double* planar, VecX& full) const;

  /// The in-plane rows and columns of a kernel block (left_block, cell_block or right_block
  /// of the same model) with global indices of the planar layout. Returns the largest
  /// |residual| of the dropped (out-of-plane) rows: zero to round-off when the symmetry holds.
  double restrict_block(const LocalBlock& full, LocalBlock& out) const;

  /// The in-plane cell kernel (6 unknowns of y per node, 6 x 6 blocks): the flux, its Jacobian
  /// and the frame's rotation about the plane normal are formed for the in-plane components
  /// only, and the cell's rows come from the same cell scheme as the 3D kernel's
  /// (cell_scheme.hpp). At a symmetric state it equals restrict_block(cell_block(...)) to
  /// round-off. What a node needs at the old level is formed once per step (old_node) and at
  /// the new level once per Newton iteration (new_levels), shared by the node's two cells.
  struct OldNode {
    Vec6 y, yt, ys;          ///< in-plane components of the old level's y, yt, ys
    double kst = 0.0;        ///< the old level's rate of the carried kappa_s about the normal
    Vec6 F;                  ///< in-plane components of the old-level flux
    Eigen::Vector2d fb;      ///< the rod's weight per length rho A g in old body components (in-plane)
    double fb_normal = 0.0;  ///< its component along the normal (zero when the problem is planar)
  };
  struct NewLevels {
    Vec6 yt, F;                         ///< at the new level
    Eigen::Matrix<double, 6, 6> dF;     ///< dF/dy_new, the frame's rotation included
  };
  OldNode old_node(const RodModel& model, const StepTimes& step, int j, const RodNode& old) const;
  /// From the node's q planar unknowns (y's in-plane components, then ys's when carried).
  void new_levels(const RodModel& model, const StepTimes& step, const OldNode& old, const double* x_new,
                  NewLevels& out) const;
  /// Cell j's q rows (planar layout) without point loads: x_prev/x_this the nodes' q planar
  /// unknowns. Use add_loads for a cell that loads_touch_cell. Returns the largest |residual|
  /// of the cell's dropped rows: at an embedded planar state only the momentum row along the
  /// normal can be nonzero, by the weight's component along it (the frame's normal axis does
  /// not turn), so that row is all it computes.
  /// `jacobian` false: the residual alone (the same bits), the Jacobian blocks left zero.
  double cell_block_into(LocalBlock& out, const RodModel& model, const StepTimes& step, int j, const OldNode& op,
                       const OldNode& oc, const double* x_prev, const double* x_this, const NewLevels& lp,
                       const NewLevels& lc, bool jacobian = true) const;
  /// Adds the in-plane rows and columns of a cell's load_block (full layout) to its planar cell
  /// block; returns the largest |residual| of the load's out-of-plane rows.
  double add_loads(LocalBlock& cell, const LocalBlock& loads) const;

 private:
  PlanarSymmetry sym_;
  int num_cells_ = 1;
  bool carried_ = false;
  int p_ = 12, q_ = 6;
  Eigen::Index full_left_row_ = 0, full_right_row_ = 0;
  std::vector<int> cols_;                               ///< kept entries of a node block
  std::vector<int> left_keep_, cell_keep_, right_keep_;  ///< kept local rows per block kind
  std::vector<int> left_drop_, cell_drop_, right_drop_;  ///< the others
  Eigen::Matrix<double, 6, 6> Mm6_, Kk6_;  ///< the in-plane rows and columns of the model's Mm and Kk
  double sigma_ = 1.0;  ///< e_a x v = sigma J v for in-plane polar v, J (v_b, v_3) = (-v_3, v_b)
  /// A rod that strains: the strain rate's slots of L.yt (the n slots), the strain v = (v_b, v_3)
  /// and dv/dn (diagonal) at the new level of a node whose in-plane force is n.
  void strain_levels(const RodModel& model, const StepTimes& step, const OldNode& o, const Eigen::Vector2d& n,
                     NewLevels& L, Eigen::Vector2d& v, Eigen::Vector2d& dv) const;
  /// The bending viscosity's -(B kappa_t)_s about the normal in a cell's spin row (box scheme:
  /// the nodes' kappa rates differenced; carried ys: the carried kappa_s's rates averaged).
  void add_bending_viscosity(LocalBlock& b, const RodModel& model, const StepTimes& step, const OldNode& op,
                             const OldNode& oc, const double* xp, const double* xc, const NewLevels& lp,
                             const NewLevels& lc) const;
};

/// The same symmetry for a static problem (static_kernels.hpp) started from the straight state
/// with frame R0 = I (straight_static_nodes), about the plane normal to d_axis = e_axis. The
/// static unknowns (r, theta, kappa, n) and cell rows (force, moment, frame, centreline) have
/// the parities of the dynamic ones (r and n polar as u and n; theta and kappa axial as omega
/// and kappa), so in_plane_components(axis) gives the in-plane unknowns of a node and rows of a
/// cell again; each end's 6 rows are split 3 + 3 by probing static_end_rows at random symmetric
/// nodes. A Newton update of the in-plane system keeps a symmetric state symmetric.
struct StaticPlanarSplit {
  int axis = 0;                              ///< 0 (normal d1 = i) or 1 (normal d2 = j)
  std::array<int, 3> left_rows{{0, 0, 0}};   ///< the in-plane rows among the left end's 6
  std::array<int, 3> right_rows{{0, 0, 0}};  ///< the in-plane rows among the right end's 6
};
/// The split about d1, else about d2, when the intrinsic curvature has only the normal's
/// component, gravity and the point forces lie in the plane (relative tolerance `tol`) and
/// both ends split; none otherwise.
std::optional<StaticPlanarSplit> static_planar_split(const StaticModel& m, double tol = 1e-12);
/// The in-plane rows and columns of a static block of m (static_left_block, static_cell_block,
/// static_right_block) in the planar layout, 6 unknowns per node (in_plane_components order)
/// and rows [3 left-end rows, 6 per cell, 3 right-end rows], as PlanarReduction's box-scheme
/// layout. Returns the largest |residual| of the dropped rows (zero at a symmetric state).
double restrict_static_block(const StaticModel& m, const StaticPlanarSplit& split, const LocalBlock& full,
                             LocalBlock& out);

}  // namespace traverse::rod

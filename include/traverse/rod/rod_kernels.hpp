#pragma once
// Residual and exact Jacobian kernels of the generalised-alpha space-time scheme for the
// rod, designed for distributed assembly: every block needs only the old-level states and
// new-level unknowns of the (at most two) nodes it touches, and carries global indices.
#include <vector>

#include "traverse/rod/rod_model.hpp"
#include "traverse/rod/rod_state.hpp"

namespace traverse::rod {

/// The time step from level i-1 (t_old) to level i (t_old + dt).
struct StepTimes {
  double t_old = 0.0;  ///< [s]
  double dt = 0.0;     ///< [s]
  double t_new() const { return t_old + dt; }
};

/// Residual rows and dense Jacobian blocks with respect to the new-level unknowns of the
/// nodes it touches. Global row = row + local row; global column of jac[k](r, c) is
/// cols[k] + c. jac[k] has residual.size() rows and unknowns_per_node() columns.
struct LocalBlock {
  Eigen::Index row = 0;
  VecX residual;
  std::vector<Eigen::Index> cols;
  std::vector<MatX> jac;
};

/// The orientation and time derivative at the new level implied by the new unknowns:
/// R = exp(-hat(dt omega_c)) R_old with omega_c = (omega_new + omega_old) / 2,
/// yt = (y_new - y_old) / (gt dt) - (1 - gt)/gt yt_old, and G = left_jacobian(-dt omega_c) dt/2
/// so that d(R v)/d omega_new = hat(R v) G for any fixed v.
struct NewLevelNode {
  Mat3 R;
  Mat3 G;
  Vec12 yt;
};
/// `with_G` false: G is left zero (a new level that no Jacobian needs, as a converged step's).
NewLevelNode new_level_node(const RodNode& old_node, const Vec12& y_new, double dt,
                            const AlphaParameters& alpha, bool with_G = true);
/// The same for the model's rod: for a rod that strains (RodProperties::compliant) the n slot of
/// yt holds the strain rate v_t instead of n's (docs/rod.md, "Extensible and shearable rods"):
/// the Kelvin-Voigt law n = C^-1 (v - e3) + B_se v_t with v_t from the same recursion, solved
/// for v at the new level. The inextensible rod's yt is new_level_node's above.
NewLevelNode new_level_node(const RodModel& model, const RodNode& old_node, const Vec12& y_new, double dt,
                            bool with_G = true);

/// The strain rate v_t of a node at the new level from its new contact force n_new [N]: the
/// Kelvin-Voigt law n = C^-1 (v - e3) + B_se v_t with v_t = (v_new - v_old)/(gt dt) -
/// (1 - gt)/gt v_t,old (the scheme's recursion), solved for v_new componentwise; v_old from the
/// old level's n_old and v_t,old. Without viscosity v_t = C (n_new - n_old)/(gt dt) - (1 - gt)/gt v_t,old.
Vec3 strain_rate(const RodProperties& p, const Vec3& n_old, const Vec3& vt_old, const Vec3& n_new, double dt,
                 const AlphaParameters& alpha);
/// The effective compliance dv_new/dn_new = C / (1 + tau c) of the new level [1/N], c = 1/(gt dt)
/// the sensitivity of a new-level rate to the new value (tau: the retardation times).
Vec3 effective_compliance(const RodProperties& p, double c);

/// Flux F(y, R, s, t) of Mm y_t + Kk y_s + F = 0 at one node and level, including gravity
/// and the distributed fixed-frame loads (not point loads, which enter cells only), and its
/// Jacobian with respect to y at fixed R (dF_dy) and with respect to the fixed-frame load
/// vectors' rotation: dF/d omega_new = dF_dy(omega cols) + dR_rows * G, where dR_rows
/// (12x3) = [-hat(f_body); -hat(l_body); 0; 0].
/// Without fixed-frame loads (RodLoads::has_frame_loads() false: no gravity, f_fixed or
/// l_fixed) dF_dRrot is zero, frame_loads is false and the kernels skip its products.
struct NodeFlux {
  Vec12 F;
  Mat12 dF_dy;
  Eigen::Matrix<double, 12, 3> dF_dRrot;
  bool frame_loads = true;  ///< whether the load terms R f, R l (and dF_dRrot) were formed
  bool has_jacobian = true;  ///< false: only F was formed (dF_dy, dF_dRrot not set)
};
/// The flux also reads the node's time-derivative history yt at its level (the strain rate v_t
/// in the n slot of a rod that strains, kappa_t for the bending viscosity) and c = d yt / d y,
/// 1/(gt dt) at the new level (what dF_dy includes of yt's dependence on y). The strain is
/// v = e3 + C n - tau v_t (RodProperties::strain) in the couple rows (- v x n) and the
/// compatibility rows (- omega x v); m = K (kappa - kappa0) + B_bt kappa_t.
/// `jacobian` false: only F (the old level's flux, which no Jacobian needs).
NodeFlux node_flux(const RodModel& model, const Vec12& y, const Vec12& yt, double c, const Mat3& R, double s,
                   double t, bool jacobian = true);
/// node_flux with yt = 0: a rod without viscosity, or one at rest.
NodeFlux node_flux(const RodModel& model, const Vec12& y, const Mat3& R, double s, double t, bool jacobian = true);

/// Mm y and Kk y of the first-order form (docs/rod.md).
Vec12 apply_Mm(const RodProperties& p, const Vec12& y);
Vec12 apply_Kk(const RodProperties& p, const Vec12& y);

/// Cell (j-1, j), j = 1..N: the 12 PDE rows (and, with carried ys, the 12 recursion rows),
/// including point forces and moving masses (load_block below). old_*/new_* are the old
/// node states and new unknown blocks (size unknowns_per_node()) of nodes j-1 and j.
LocalBlock cell_block(const RodModel& model, const StepTimes& step, int j,
                      const RodNode& old_prev, const RodNode& old_this,
                      const VecX& new_prev, const VecX& new_this);

/// What a cell needs from one of its nodes, computed once per node and shared by the node's
/// two cells (cell_block_into): the new-level orientation/history and the fluxes at the new
/// and the old level (the old-level flux does not change during a step's Newton iterations).
struct NodeLevels {
  NewLevelNode nn;  ///< new_level_node(old, y_new, dt, alpha)
  NodeFlux F_new;   ///< node_flux(y_new, nn.R, s_j, t_new)
  NodeFlux F_old;   ///< node_flux(old.y, old.R, s_j, t_old)
};
/// F_old of node j (s_j = j ds) at t_old: F only (has_jacobian false).
NodeFlux old_level_flux(const RodModel& model, const StepTimes& step, int j, const RodNode& old_node);
/// nn and F_new of node j from its new unknown block; leaves out.F_old alone. `jacobian`
/// false: without nn.G and F_new's Jacobian (for cell_block_into's residual alone; the same
/// residual bits).
void new_level_quantities(const RodModel& model, const StepTimes& step, int j, const RodNode& old_node,
                          const VecX& new_node, NodeLevels& out, bool jacobian = true);
/// cell_block with the nodes' quantities precomputed (as above, for nodes j-1 and j), written
/// into `out` reusing its storage. Identical arithmetic, so identical bits: cell_block is
/// this function with the NodeLevels computed on the spot. `loads_touch`: loads_touch_cell(model,
/// step, j), which depends only on the step (StepAssembly finds it once per step). `jacobian`
/// false: the residual alone (the same bits), the Jacobian blocks left zero.
void cell_block_into(LocalBlock& out, const RodModel& model, const StepTimes& step, int j,
                     const RodNode& old_prev, const RodNode& old_this, const VecX& new_prev,
                     const VecX& new_this, const NodeLevels& prev, const NodeLevels& cur, bool loads_touch,
                     bool jacobian = true);

/// The residual rows of cell (j-1, j) without the point loads, written into r (12 rows, or 24
/// with carried ys: the recursion rows): Mm A_t + Kk A_s + A_F with the generalised-alpha
/// averages of the node levels (cell_scheme.hpp, which the planar cell evaluates on its
/// in-plane components), and the bending and torsion viscosity. Mm, Kk: Mm_matrix and
/// Kk_matrix of the model's properties.
void cell_residual_into(VecX& r, const RodModel& model, const StepTimes& step, const Mat12& Mm, const Mat12& Kk,
                        const RodNode& old_prev, const RodNode& old_this, const VecX& new_prev, const VecX& new_this,
                        const NodeLevels& prev, const NodeLevels& cur);

/// Whether a point force or moving mass acts on cell j at either level of the step (when not,
/// load_block is zero).
bool loads_touch_cell(const RodModel& model, const StepTimes& step, int j);
/// The cells c0 <= j <= c1 for which loads_touch_cell holds, in increasing order, found from
/// the loads' positions (each load's cells at both levels and those between, with their
/// neighbours, checked by loads_touch_cell) instead of by visiting every cell.
std::vector<int> cells_touched_by_loads(const RodModel& model, const StepTimes& step, int c0, int c1);

/// Only the point-force and moving-mass contributions to the 12 PDE rows of cell j (the
/// load kernel; already included in cell_block).
LocalBlock load_block(const RodModel& model, const StepTimes& step, int j,
                      const RodNode& old_prev, const RodNode& old_this,
                      const VecX& new_prev, const VecX& new_this);

/// Left end: its 6 condition rows (rows 0..5) and, with carried ys, the PDE collocated at
/// node 0 (rows 6..17). Right end: its 6 condition rows at right_row().
LocalBlock left_block(const RodModel& model, const StepTimes& step, const RodNode& old_node,
                      const VecX& new_node);
LocalBlock right_block(const RodModel& model, const StepTimes& step, const RodNode& old_node,
                       const VecX& new_node);

/// Every block owned by nodes first_node..last_node (see RodModel): the caller passes old
/// states and new unknowns for nodes offset .. offset + size - 1, which must include
/// max(first_node - 1, 0) .. last_node (one ghost node on the left; a ghost on the right is
/// allowed and ignored).
std::vector<LocalBlock> assemble_nodes(const RodModel& model, const StepTimes& step,
                                       int first_node, int last_node, int offset,
                                       const std::vector<RodNode>& old_nodes,
                                       const std::vector<VecX>& new_unknowns);

/// Unknown block of a node (y, and ys when carried) - the natural Newton initial guess.
VecX node_unknowns(const RodModel& model, const RodNode& node);

/// The new-level node implied by converged unknowns (y, ys, R, yt updated; yv the step's
/// secant (y_new - y_old) / dt; yg the entries of yv whose change in this step the old node's
/// secant predicted to within half of it, |d - dt yv_old| < |d| / 2 with d = y_new - y_old,
/// zero elsewhere).
RodNode advance_node(const RodModel& model, const RodNode& old_node, const VecX& new_unknowns,
                     double dt);


}  // namespace traverse::rod

#include "traverse/rod/rod_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "traverse/core/so3.hpp"
#include "traverse/rod/cell_scheme.hpp"

namespace traverse::rod {

using so3::hat;

Vec3 effective_compliance(const RodProperties& p, double c) {
  return p.C.cwiseQuotient((Vec3::Ones() + c * p.retardation()));
}

Vec3 strain_rate(const RodProperties& p, const Vec3& n_old, const Vec3& vt_old, const Vec3& n_new, double dt,
                 const AlphaParameters& alpha) {
  // In the deviations v - e3 (the strain itself would lose the digits of C n against 1).
  const double gdt = alpha.gt * dt, hist = (1.0 - alpha.gt) / alpha.gt;
  const Vec3 tau = p.retardation();
  const Vec3 d_old = p.C.cwiseProduct(n_old) - tau.cwiseProduct(vt_old);
  const Vec3 d_new =
      (p.C.cwiseProduct(n_new) + tau.cwiseProduct(d_old / gdt + hist * vt_old)).cwiseQuotient(Vec3::Ones() + tau / gdt);
  return (d_new - d_old) / gdt - hist * vt_old;
}

namespace {

const Vec3 e3 = Vec3::UnitZ();

/// Mm of Mm y_t: the compliance row -v_t of a rod that strains reads the n slot of y_t, which
/// then holds the strain rate v_t (strain_rate); for the inextensible rod it is zero.
Mat12 Mm_matrix(const RodProperties& p) {
  Vec12 d;
  d << Vec3::Constant(p.rhoA), p.rhoI, Vec3::Ones(), Vec3::Zero();
  Mat12 M = d.asDiagonal();
  if (p.compliant()) M.block<3, 3>(9, var::n) = -Mat3::Identity();
  return M;
}

/// Mm as the Jacobian of Mm y_t with respect to y_new, divided by dy_t/dy = c = 1/(gt dt): the
/// strain rate's slot depends on n_new through the effective compliance.
Mat12 Mm_jacobian(const RodProperties& p, double c) {
  Mat12 M = Mm_matrix(p);
  if (p.compliant()) M.block<3, 3>(9, var::n) = -Mat3(effective_compliance(p, c).asDiagonal());
  return M;
}

/// The time-derivative history of a node's carried kappa_s at the new level (generalised
/// alpha, as y_t from y): (ys_new - ys_old) / (gt dt) - (1 - gt) / gt kst_old, kappa slots.
Vec3 carried_kappa_rate(const RodModel& model, const RodNode& old_node, const VecX& new_node, double dt) {
  const AlphaParameters& a = model.alpha;
  return (new_node.tail<12>().segment<3>(var::kappa) - old_node.ys.segment<3>(var::kappa)) / (a.gt * dt) -
         (1.0 - a.gt) / a.gt * old_node.kst;
}

/// The viscous part of the bending moment's derivative, -(B_bt kappa_t)_s, in the angular
/// momentum rows of cell (j-1, j), averaged in time like Kk y_s. Box scheme in s: the kappa
/// slots of y_t differenced between the nodes. Carried ys: (B kappa_t)_s = B (kappa_s)_t, the
/// rates of the carried kappa_s averaged with the cell's spatial weights, as Kk ys is.
Vec3 bending_viscosity(const RodModel& model, double dt, const RodNode& old_prev, const RodNode& old_this,
                       const VecX& new_prev, const VecX& new_this, const NodeLevels& prev, const NodeLevels& cur) {
  const AlphaParameters& a = model.alpha;
  Vec3 A;
  if (model.carries_ys()) {
    const Vec3 kp = carried_kappa_rate(model, old_prev, new_prev, dt), kc = carried_kappa_rate(model, old_this, new_this, dt);
    A = (1.0 - a.bt) * ((1.0 - a.bs) * kc + a.bs * kp) + a.bt * ((1.0 - a.bs) * old_this.kst + a.bs * old_prev.kst);
  } else {
    const Vec3 d_new = cur.nn.yt.segment<3>(var::kappa) - prev.nn.yt.segment<3>(var::kappa);
    const Vec3 d_old = old_this.yt.segment<3>(var::kappa) - old_prev.yt.segment<3>(var::kappa);
    A = ((1.0 - a.bt) * d_new + a.bt * d_old) / model.ds();
  }
  return -model.props.B_bt.cwiseProduct(A);
}

/// Its Jacobian with respect to node j-1 (Jp) and j (Jc): their kappa (box scheme) or their
/// carried kappa_s (columns 12 + kappa).
void add_bending_viscosity_jacobian(MatX& Jp, MatX& Jc, const RodModel& model, double dt) {
  const AlphaParameters& a = model.alpha;
  const Mat3 B = Mat3(model.props.B_bt.asDiagonal()) * ((1.0 - a.bt) / (a.gt * dt));
  if (model.carries_ys()) {
    Jc.block<3, 3>(3, 12 + var::kappa) -= (1.0 - a.bs) * B;
    Jp.block<3, 3>(3, 12 + var::kappa) -= a.bs * B;
  } else {
    Jc.block<3, 3>(3, var::kappa) -= B / model.ds();
    Jp.block<3, 3>(3, var::kappa) += B / model.ds();
  }
}

Mat12 Kk_matrix(const RodProperties& p) {
  Mat12 k = Mat12::Zero();
  k.block<3, 3>(0, var::n) = -Mat3::Identity();
  k.block<3, 3>(3, var::kappa) = -Mat3(p.K.asDiagonal());
  k.block<3, 3>(6, var::omega) = -Mat3::Identity();
  k.block<3, 3>(9, var::u) = Mat3::Identity();
  return k;
}

/// Jacobian of the flux with respect to the new-level y, R's dependence on omega included.
Mat12 new_level_flux_jacobian(const NodeFlux& f, const Mat3& G) {
  if (!f.has_jacobian) throw std::logic_error("rod kernels: the Jacobian of a flux formed without it");
  Mat12 J = f.dF_dy;
  if (f.frame_loads) J.block<12, 3>(0, var::omega) += f.dF_dRrot * G;  // else dF_dRrot = 0
  return J;
}

/// The fixed-frame force [N] the point loads and the masses' weights put on end node `node`
/// (0 or N) at time t: their end shares (PointLoadWeights), which the end's rows take.
Vec3 end_point_force(const RodModel& model, int node, double t) {
  const auto& loads = model.loads;
  const int N = model.num_cells;
  const double ds = model.ds();
  auto share = [&](double sigma) { return point_load_weights(sigma, N, ds).share(node); };
  Vec3 F = Vec3::Zero();
  for (const PointForce& P : loads.point_forces)
    if (const double w = share(P.sigma(t)); w != 0.0) F += w * P.force_fixed(t);
  if (loads.has_gravity())
    for (const MovingMass& M : loads.masses)
      if (const double w = share(M.sigma(t)); w != 0.0) F += w * (M.mass - M.carried) * loads.gravity;
  return F;
}

/// The inertia -M p'' of a moving mass, the part that cell j's rows receive (momentum rows
/// 0..2, angular-momentum rows 3..5; residual and the Jacobian blocks of nodes j-1, j).
///
/// Momentum form over the cell's space-time box (the box's rows are its equations integrated
/// over [s_{j-1}, s_j] x [t_{i-1}, t_i], divided by ds dt). The mass's momentum per unit mass
/// is p' = U + v r_s in fixed components (U = R^T u, r_s = R^T v_strain: d3 = R^T e3 for the
/// inextensible rod, R^T (e3 + C n - tau v_t) for one that strains), taken bilinear in the box
/// from its four corners. The mass is carried as a line mass of density M / (2 ds) on
/// [sigma - ds, sigma + ds] moving with it (line_mass_part). While sigma runs along a segment
/// a -> b of its path (mass_path_in_cell: sigma in cell j - 1, j or j + 1), the line mass's
/// part [l, r] in cell j has momentum Pi = M / (2 ds) (r - l) p'((l + r) / 2) (exact for p'
/// linear in s), and it exerts on the cell the impulse (Reynolds transport: the part's ends
/// at sigma -+ ds move with the mass, the cell's ends are fixed)
///
///     I = Pi(b) - Pi(a) + M / (2 ds) v (t_b - t_a) [p'(s_j) - p'(s_{j-1})]
///
/// where a cell end counts only while it lies inside the line mass (right end: sigma in cell
/// j or j + 1; left end: sigma in cell j - 1 or j), p' at the ends at the segment's
/// mid-time. I / (ds dt), in body components with the frame at the part's centroid at
/// mid-time, enters the momentum rows, with the couple about s_{j-1} + bs ds that puts it
/// at that centroid.
///
/// Why a line mass: the box scheme has an undamped odd-even (checkerboard) mode, and a load
/// excites it unless neighbouring cells share it the way the scheme's average shares a nodal
/// force. A point mass's impulse sits in the one box it crosses; at dt = ds / v the mass
/// crosses one box per step, all of the same parity, and pumps the mode coherently (a
/// growing node-to-node sawtooth in n behind it). The line mass's shares of the cells are
/// the hat weights of a point load at sigma (1/4, 1/2, 1/4 in cells k-1, k, k+1 when sigma
/// is mid-cell k), whose alternating sum vanishes. They and the parts' centroids move
/// continuously with sigma; each cell reads only its own corners (interpolation, no
/// extrapolation) and only p', which is C^2 across the mass (the kinks of U and of v d3
/// cancel in it), along the part's path and at its fixed ends; a constant p' exerts
/// nothing; the parts' momenta add up to the line mass's integral of the interpolated p',
/// so the impulses telescope; and the line mass differs from the point mass by O(ds^2). The
/// part beyond the rod's ends is dropped (the rod's ends are fixed cell ends).
void add_mass_momentum(LocalBlock& b, const RodModel& model, const StepTimes& step, int j, const MovingMass& M,
                       const RodNode* const old[2], const Vec12 yn[2], const NewLevelNode nn[2]) {
  const int N = model.num_cells;
  const double ds = model.ds(), dt = step.dt;
  const double sigma_old = M.sigma(step.t_old), sigma_new = M.sigma(step.t_new());
  const double s0 = (j - 1) * ds, s1 = j * ds;  // the cell's ends
  const double rho = M.mass / (2.0 * ds);        // the line mass's density
  // The inertia tensor's shape (fixed frame): I, or I - (carried / mass) a a^T
  const Mat3 inertia_shape =
      Mat3::Identity() - (M.carried != 0.0 ? M.carried / M.mass : 0.0) * M.carried_axis * M.carried_axis.transpose();
  // Corner c = 2 q + lev: node j-1+q, lev 0 = new level (unknowns), 1 = old level.
  // The centreline's tangent r_s in body components at the corners (the strain v), and its
  // sensitivity to the new level's n (the effective compliance, rod_kernels.hpp).
  const RodProperties& p = model.props;
  const bool strains = p.compliant();
  Vec3 V[4];
  for (int q = 0; q < 2; ++q) {
    V[2 * q] = strains ? p.strain(yn[q].segment<3>(var::n), nn[q].yt.segment<3>(var::n)) : e3;
    V[2 * q + 1] = strains ? p.strain(old[q]->y.segment<3>(var::n), old[q]->yt.segment<3>(var::n)) : e3;
  }
  const Vec3 dv_dn = strains ? effective_compliance(p, 1.0 / (model.alpha.gt * dt)) : Vec3::Zero();
  Vec3 U[4], D[4];
  const Mat3* R[4];
  for (int q = 0; q < 2; ++q) {
    R[2 * q] = &nn[q].R;
    R[2 * q + 1] = &old[q]->R;
    U[2 * q] = nn[q].R.transpose() * yn[q].segment<3>(var::u);
    U[2 * q + 1] = old[q]->R.transpose() * old[q]->y.segment<3>(var::u);
    D[2 * q] = nn[q].R.transpose() * V[2 * q];
    D[2 * q + 1] = old[q]->R.transpose() * V[2 * q + 1];
  }
  // Bilinear weights of the corners at (s, tau), tau = (t - t_old) / dt, s in the cell.
  auto corner_weights = [&](double s, double tau, double w[4]) {
    const double xi = std::clamp((s - s0) / ds, 0.0, 1.0);
    w[0] = (1.0 - xi) * tau;
    w[1] = (1.0 - xi) * (1.0 - tau);
    w[2] = xi * tau;
    w[3] = xi * (1.0 - tau);
  };
  const Mat3 he3 = hat(e3);
  for (int cell = std::max(1, j - 1); cell <= std::min(N, j + 1); ++cell) {
    const MassPathSegment seg = mass_path_in_cell(sigma_old, sigma_new, cell, N, ds);
    if (!seg.valid) continue;
    // The part [l, r] of the line mass in cell j at a point of the segment (sigma in `cell`).
    double la = s0, ra = s0, lb = s0, rb = s0, lm = s0, rm = s0;
    const bool in_a = line_mass_part(seg.s_a, j, N, ds, la, ra);
    const bool in_b = line_mass_part(seg.s_b, j, N, ds, lb, rb);
    const bool in_m = line_mass_part(0.5 * (seg.s_a + seg.s_b), j, N, ds, lm, rm);
    if (!in_a && !in_b && !in_m) continue;
    if (!in_a) la = ra = cell < j ? s0 : s1;  // an empty part at the cell's end facing sigma
    if (!in_b) lb = rb = cell < j ? s0 : s1;
    if (!in_m) lm = rm = cell < j ? s0 : s1;
    const bool left_inside = cell <= j, right_inside = cell >= j;  // cell ends inside it
    const double tau_m = 0.5 * (seg.tau_a + seg.tau_b), dtau = seg.tau_b - seg.tau_a;
    const double va = M.speed(step.t_old + seg.tau_a * dt), vb = M.speed(step.t_old + seg.tau_b * dt);
    const double vm = M.speed(step.t_old + tau_m * dt);
    // I = sum_c aU[c] U[c] + aD[c] D[c]: `coef` times p' at (s, tau) with speed v, summed.
    double aU[4] = {0.0, 0.0, 0.0, 0.0}, aD[4] = {0.0, 0.0, 0.0, 0.0};
    auto add = [&](double coef, double s, double tau, double v) {
      double w[4];
      corner_weights(s, tau, w);
      for (int c = 0; c < 4; ++c) {
        aU[c] += coef * w[c];
        aD[c] += coef * w[c] * v;
      }
    };
    add(rho * (rb - lb), 0.5 * (lb + rb), seg.tau_b, vb);   // Pi(b)
    add(-rho * (ra - la), 0.5 * (la + ra), seg.tau_a, va);  // -Pi(a)
    const double flux = rho * vm * dtau * dt;                // momentum carried through the ends
    if (right_inside) add(flux, s1, tau_m, vm);
    if (left_inside) add(-flux, s0, tau_m, vm);
    const double xm = 0.5 * (lm + rm);  // the part's centroid at mid-time
    double wm[4];
    corner_weights(xm, tau_m, wm);
    Vec3 dP = Vec3::Zero();  // I, fixed components
    Mat3 Rm = Mat3::Zero();  // frame at the centroid
    for (int c = 0; c < 4; ++c) {
      dP += aU[c] * U[c] + aD[c] * D[c];
      Rm += wm[c] * *R[c];
    }
    if (M.carried != 0.0) dP = inertia_shape * dP;
    const Vec3 J = Rm * dP;  // I in body components
    const double C = 1.0 / (ds * dt);
    const double arm = xm - (s0 + model.alpha.bs * ds);
    b.residual.head<3>() += C * J;
    b.residual.segment<3>(3) += (C * arm) * e3.cross(J);
    // Jacobian: the new-level corners (c = 0, 2) depend on the unknowns, through u and through
    // R_new(omega_new): d(R^T x)/d omega_new = -R^T hat(x) G (x a body vector) and
    // d(R y)/d omega_new = hat(R y) G (y a fixed vector).
    for (int q = 0; q < 2; ++q) {
      const int c = 2 * q;
      const Mat3& Rn = nn[q].R;
      const Mat3& G = nn[q].G;
      const Vec3 x = aU[c] * yn[q].segment<3>(var::u) + aD[c] * V[c];
      const Mat3 RPR = Rm * inertia_shape * Rn.transpose();
      const Mat3 dJ_du = aU[c] * RPR;
      const Mat3 dJ_dw = -RPR * hat(x) * G + wm[c] * hat(Vec3(Rn * dP)) * G;
      b.jac[q].block<3, 3>(0, var::u) += C * dJ_du;
      b.jac[q].block<3, 3>(0, var::omega) += C * dJ_dw;
      b.jac[q].block<3, 3>(3, var::u) += (C * arm) * he3 * dJ_du;
      b.jac[q].block<3, 3>(3, var::omega) += (C * arm) * he3 * dJ_dw;
      if (strains) {
        const Mat3 dJ_dn = aD[c] * RPR * dv_dn.asDiagonal();
        b.jac[q].block<3, 3>(0, var::n) += C * dJ_dn;
        b.jac[q].block<3, 3>(3, var::n) += (C * arm) * he3 * dJ_dn;
      }
    }
  }
}

LocalBlock make_block(Eigen::Index row, int rows, int p, std::vector<Eigen::Index> cols) {
  LocalBlock b;
  b.row = row;
  b.residual = VecX::Zero(rows);
  b.cols = std::move(cols);
  b.jac.assign(b.cols.size(), MatX::Zero(rows, p));
  return b;
}

/// make_block's result in place, reusing b's storage when the sizes match (no allocation).
void prepare_block(LocalBlock& b, Eigen::Index row, int rows, int p, Eigen::Index col0, Eigen::Index col1) {
  b.row = row;
  b.residual.setZero(rows);
  b.cols.resize(2);
  b.cols[0] = col0;
  b.cols[1] = col1;
  b.jac.resize(2);
  for (MatX& J : b.jac) J.setZero(rows, p);
}

}  // namespace

bool loads_touch_cell(const RodModel& model, const StepTimes& step, int j) {
  const auto& loads = model.loads;
  if (loads.point_forces.empty() && loads.masses.empty()) return false;
  const int N = model.num_cells;
  const double ds = model.ds();
  const double tl0[2] = {step.t_new(), step.t_old};
  auto touches = [&](const PointLoadWeights& W) { return W.at(j - 1) != 0.0 || W.at(j) != 0.0; };
  bool any = false;
  for (const PointForce& P : loads.point_forces)
    for (int lev = 0; lev < 2 && !any; ++lev) any = touches(point_load_weights(P.sigma(tl0[lev]), N, ds));
  for (const MovingMass& M : loads.masses) {
    for (int lev = 0; lev < 2 && !any; ++lev) any = touches(point_load_weights(M.sigma(tl0[lev]), N, ds));
    // The inertia: the mass's path through cells j-1, j, j+1 (its line mass reaches cell j).
    for (int c = std::max(1, j - 1); c <= std::min(N, j + 1) && !any && M.inertia; ++c)
      any = mass_path_in_cell(M.sigma(step.t_old), M.sigma(step.t_new()), c, N, ds).valid;
  }
  return any;
}

std::vector<int> cells_touched_by_loads(const RodModel& model, const StepTimes& step, int c0, int c1) {
  const auto& loads = model.loads;
  std::vector<int> out;
  c0 = std::max(c0, 1);
  c1 = std::min(c1, model.num_cells);
  if (c0 > c1 || (loads.point_forces.empty() && loads.masses.empty())) return out;
  // A load at sigma weighs on the nodes of the cell holding it (point_load_weights), so it
  // reaches that cell and its two neighbours; a mass's inertia reaches the cells of its path
  // and their neighbours. Candidates a cell wider on each side, then the exact test.
  std::vector<std::pair<int, int>> ranges;
  const double ds = model.ds(), cells = model.num_cells;
  auto add = [&](double a, double b) {
    const double lo = std::clamp(std::floor(std::min(a, b) / ds) - 2.0, 0.0, cells + 1.0);
    const double hi = std::clamp(std::ceil(std::max(a, b) / ds) + 2.0, 0.0, cells + 1.0);
    if (std::isfinite(lo) && std::isfinite(hi)) ranges.emplace_back(static_cast<int>(lo), static_cast<int>(hi));
    else ranges.emplace_back(0, model.num_cells + 1);  // no position: every cell is a candidate
  };
  for (const PointForce& P : loads.point_forces) add(P.sigma(step.t_old), P.sigma(step.t_new()));
  for (const MovingMass& M : loads.masses) add(M.sigma(step.t_old), M.sigma(step.t_new()));
  std::sort(ranges.begin(), ranges.end());
  int next = c0;  // the first cell not yet checked
  for (const auto& [lo, hi] : ranges) {
    const int to = std::min(hi, c1);
    for (int j = std::max(lo, next); j <= to; ++j)
      if (loads_touch_cell(model, step, j)) out.push_back(j);
    next = std::max(next, to + 1);
  }
  return out;
}

namespace {

void check_unknowns(const RodModel& model, const VecX& x) {
  if (x.size() != model.unknowns_per_node())
    throw std::invalid_argument("rod kernels: node unknown block has the wrong size");
}

}  // namespace

Vec12 apply_Mm(const RodProperties& p, const Vec12& y) { return Mm_matrix(p) * y; }
Vec12 apply_Kk(const RodProperties& p, const Vec12& y) { return Kk_matrix(p) * y; }

NewLevelNode new_level_node(const RodNode& old_node, const Vec12& y_new, double dt,
                            const AlphaParameters& alpha, bool with_G) {
  NewLevelNode n;
  const Vec3 x = -0.5 * dt * (y_new.segment<3>(var::omega) + old_node.y.segment<3>(var::omega));
  n.R = so3::exp(x) * old_node.R;
  n.G = with_G ? Mat3(so3::left_jacobian(x) * (0.5 * dt)) : Mat3::Zero();
  n.yt = (y_new - old_node.y) / (alpha.gt * dt) - (1.0 - alpha.gt) / alpha.gt * old_node.yt;
  return n;
}

NewLevelNode new_level_node(const RodModel& model, const RodNode& old_node, const Vec12& y_new, double dt,
                            bool with_G) {
  NewLevelNode n = new_level_node(old_node, y_new, dt, model.alpha, with_G);
  if (model.props.compliant())
    n.yt.segment<3>(var::n) = strain_rate(model.props, old_node.y.segment<3>(var::n), old_node.yt.segment<3>(var::n),
                                          y_new.segment<3>(var::n), dt, model.alpha);
  return n;
}

NodeFlux node_flux(const RodModel& model, const Vec12& y, const Mat3& R, double s, double t, bool jacobian) {
  return node_flux(model, y, Vec12::Zero(), 0.0, R, s, t, jacobian);
}

NodeFlux node_flux(const RodModel& model, const Vec12& y, const Vec12& yt, double c, const Mat3& R, double s, double t,
                   bool jacobian) {
  const RodProperties& p = model.props;
  const Vec3 u = y.segment<3>(var::u), w = y.segment<3>(var::omega);
  const Vec3 k = y.segment<3>(var::kappa), n = y.segment<3>(var::n);
  // The contact moment (with the bending and torsion viscosity when there is one) and its
  // sensitivity to kappa; the strain v (e3 for the inextensible rod) and its sensitivity to n.
  Vec3 m = p.K.cwiseProduct(k - p.kappa0), dm_dk = p.K;
  if (p.B_bt != Vec3::Zero()) {
    m += p.B_bt.cwiseProduct(yt.segment<3>(var::kappa));
    dm_dk += c * p.B_bt;
  }
  const bool compliant = p.compliant();
  const Vec3 v = compliant ? p.strain(n, yt.segment<3>(var::n)) : e3;
  NodeFlux out;
  // Fixed-frame loads in body components; a scene without gravity and distributed loads
  // skips them (fb = lb = 0 exactly, no products with R).
  out.frame_loads = model.loads.has_frame_loads();
  Vec3 fb = Vec3::Zero(), lb = Vec3::Zero();
  if (out.frame_loads) {
    Vec3 f_fixed = p.rhoA * model.loads.gravity;
    if (model.loads.f_fixed) f_fixed += model.loads.f_fixed(s, t);
    Vec3 l_fixed = Vec3::Zero();
    if (model.loads.l_fixed) l_fixed = model.loads.l_fixed(s, t);
    fb = R * f_fixed;
    lb = R * l_fixed;
  }
  const Vec3 Iw = p.rhoI.cwiseProduct(w);

  out.F.segment<3>(0) = -k.cross(n) + p.rhoA * w.cross(u) - fb;
  out.F.segment<3>(3) = -k.cross(m) - v.cross(n) + w.cross(Iw) - lb;
  out.F.segment<3>(6) = -k.cross(w);
  out.F.segment<3>(9) = k.cross(u) - w.cross(v);
  out.has_jacobian = jacobian;
  if (!jacobian) return out;

  Mat12& J = out.dF_dy;
  J.setZero();
  J.block<3, 3>(0, var::u) = p.rhoA * hat(w);
  J.block<3, 3>(0, var::omega) = -p.rhoA * hat(u);
  J.block<3, 3>(0, var::kappa) = hat(n);
  J.block<3, 3>(0, var::n) = -hat(k);
  J.block<3, 3>(3, var::omega) = hat(w) * p.rhoI.asDiagonal() - hat(Iw);
  J.block<3, 3>(3, var::kappa) = -hat(k) * dm_dk.asDiagonal() + hat(m);
  J.block<3, 3>(3, var::n) = -hat(v);
  J.block<3, 3>(6, var::omega) = -hat(k);
  J.block<3, 3>(6, var::kappa) = hat(w);
  J.block<3, 3>(9, var::u) = hat(k);
  J.block<3, 3>(9, var::omega) = hat(v);
  J.block<3, 3>(9, var::kappa) = -hat(u);
  if (compliant) {  // v = e3 + C n - tau v_t depends on n (at the new level through v_t too)
    const Mat3 dv_dn = effective_compliance(p, c).asDiagonal();
    J.block<3, 3>(3, var::n) += hat(n) * dv_dn;
    J.block<3, 3>(9, var::n) = -hat(w) * dv_dn;
  }

  out.dF_dRrot.setZero();
  if (out.frame_loads) {
    out.dF_dRrot.block<3, 3>(0, 0) = -hat(fb);
    out.dF_dRrot.block<3, 3>(3, 0) = -hat(lb);
  }
  return out;
}

LocalBlock load_block(const RodModel& model, const StepTimes& step, int j,
                      const RodNode& old_prev, const RodNode& old_this, const VecX& new_prev,
                      const VecX& new_this) {
  check_unknowns(model, new_prev);
  check_unknowns(model, new_this);
  const int p = model.unknowns_per_node();
  LocalBlock b = make_block(model.cell_row(j), 12, p, {model.node_col(j - 1), model.node_col(j)});
  const auto& loads = model.loads;
  if (loads.point_forces.empty() && loads.masses.empty()) return b;

  const AlphaParameters& a = model.alpha;
  const int N = model.num_cells;
  const double ds = model.ds(), dt = step.dt;
  // Speed: a load touches at most two cells, so most cells get nothing; return the zero
  // block before the (costly) new-level frames are built. Same weights as below, so the
  // result is identical.
  if (!loads_touch_cell(model, step, j)) return b;
  const Vec12 yn[2] = {new_prev.head<12>(), new_this.head<12>()};
  const RodNode* old[2] = {&old_prev, &old_this};
  // (the model's: for a rod that strains the n slot of yt is the strain rate the masses read)
  const NewLevelNode nn[2] = {new_level_node(model, old_prev, yn[0], dt), new_level_node(model, old_this, yn[1], dt)};
  const int node[2] = {j - 1, j};
  const double sw_b[2] = {a.bs, 1.0 - a.bs};  // spatial weights of F in this cell
  // level 0 = new (t_i, weight 1 - bt), level 1 = old (t_{i-1}, weight bt)
  const double tw_b[2] = {1.0 - a.bt, a.bt};
  const double tl[2] = {step.t_new(), step.t_old};

  for (const PointForce& P : loads.point_forces) {
    for (int lev = 0; lev < 2; ++lev) {
      const PointLoadWeights W = point_load_weights(P.sigma(tl[lev]), N, ds);
      if (W.count == 0) continue;
      const Vec3 F = P.force_fixed(tl[lev]);
      for (int q = 0; q < 2; ++q) {
        const double w = W.at(node[q]);
        if (w == 0.0) continue;
        const double c = tw_b[lev] * sw_b[q] * w / ds;
        const Mat3& R = lev == 0 ? nn[q].R : old[q]->R;
        const Vec3 Fb = R * F;
        b.residual.head<3>() -= c * Fb;
        if (lev == 0) b.jac[q].block<3, 3>(0, var::omega) -= c * hat(Fb) * nn[q].G;
      }
    }
  }

  const bool gravity = loads.has_gravity();
  for (const MovingMass& M : loads.masses) {
    // The weight M g: a moving point force (the same arithmetic for a mass with or without
    // inertia). Without gravity there is none.
    if (gravity) {
      for (int lev = 0; lev < 2; ++lev) {
        const PointLoadWeights W = point_load_weights(M.sigma(tl[lev]), N, ds);
        if (W.count == 0) continue;
        for (int q = 0; q < 2; ++q) {
          const double w = W.at(node[q]);
          if (w == 0.0) continue;
          const double c = tw_b[lev] * sw_b[q] * w / ds * (M.mass - M.carried);
          const Mat3& R = lev == 0 ? nn[q].R : old[q]->R;
          const Vec3 Rg = R * loads.gravity;
          b.residual.head<3>() -= c * Rg;
          if (lev == 0) b.jac[q].block<3, 3>(0, var::omega) -= c * hat(Rg) * nn[q].G;
        }
      }
    }
    // The inertia -M p'': momentum form over the cell's space-time box, for a short line mass.
    if (M.inertia) add_mass_momentum(b, model, step, j, M, old, yn, nn);
  }
  return b;
}

NodeFlux old_level_flux(const RodModel& model, const StepTimes& step, int j, const RodNode& old_node) {
  return node_flux(model, old_node.y, old_node.yt, 0.0, old_node.R, j * model.ds(), step.t_old, false);
}

void new_level_quantities(const RodModel& model, const StepTimes& step, int j, const RodNode& old_node,
                          const VecX& new_node, NodeLevels& out, bool jacobian) {
  check_unknowns(model, new_node);
  const Vec12 y = new_node.head<12>();
  out.nn = new_level_node(model, old_node, y, step.dt, jacobian);
  out.F_new = node_flux(model, y, out.nn.yt, 1.0 / (model.alpha.gt * step.dt), out.nn.R, j * model.ds(), step.t_new(),
                        jacobian);
}

LocalBlock cell_block(const RodModel& model, const StepTimes& step, int j,
                      const RodNode& old_prev, const RodNode& old_this, const VecX& new_prev,
                      const VecX& new_this) {
  if (j < 1 || j > model.num_cells) throw std::out_of_range("cell_block: cell index");
  check_unknowns(model, new_prev);
  check_unknowns(model, new_this);
  NodeLevels lp, lc;
  lp.F_old = old_level_flux(model, step, j - 1, old_prev);
  lc.F_old = old_level_flux(model, step, j, old_this);
  new_level_quantities(model, step, j - 1, old_prev, new_prev, lp);
  new_level_quantities(model, step, j, old_this, new_this, lc);
  LocalBlock b;
  cell_block_into(b, model, step, j, old_prev, old_this, new_prev, new_this, lp, lc, loads_touch_cell(model, step, j));
  return b;
}

namespace {
/// A cell node's quantities for the cell scheme (cell_scheme.hpp).
CellNode<12> cell_node(const RodModel& model, const RodNode& old_node, const VecX& new_node, const NodeLevels& lv) {
  const bool carried = model.carries_ys();
  return CellNode<12>{old_node.y,         old_node.yt,      old_node.ys, lv.F_old.F,
                      new_node.head<12>(), carried ? new_node.tail<12>() : new_node.head<12>(),
                      lv.nn.yt,           lv.F_new.F};
}
}  // namespace

void cell_residual_into(VecX& r, const RodModel& model, const StepTimes& step, const Mat12& Mm, const Mat12& Kk,
                        const RodNode& old_prev, const RodNode& old_this, const VecX& new_prev, const VecX& new_this,
                        const NodeLevels& prev, const NodeLevels& cur) {
  cell_scheme_residual<12>(r, model.alpha, model.carries_ys(), model.ds(), Mm, Kk,
                           cell_node(model, old_prev, new_prev, prev), cell_node(model, old_this, new_this, cur));
  if (model.props.B_bt != Vec3::Zero())
    r.segment<3>(3) += bending_viscosity(model, step.dt, old_prev, old_this, new_prev, new_this, prev, cur);
}

void cell_block_into(LocalBlock& b, const RodModel& model, const StepTimes& step, int j,
                     const RodNode& old_prev, const RodNode& old_this, const VecX& new_prev,
                     const VecX& new_this, const NodeLevels& prev, const NodeLevels& cur, bool loads_touch,
                     bool jacobian) {
  if (j < 1 || j > model.num_cells) throw std::out_of_range("cell_block: cell index");
  check_unknowns(model, new_prev);
  check_unknowns(model, new_this);
  const RodProperties& P = model.props;
  const int p = model.unknowns_per_node();
  const Mat12 Mm = Mm_matrix(P), Kk = Kk_matrix(P);

  prepare_block(b, model.cell_row(j), model.cell_rows(), p, model.node_col(j - 1), model.node_col(j));
  cell_residual_into(b.residual, model, step, Mm, Kk, old_prev, old_this, new_prev, new_this, prev, cur);
  if (!jacobian) {
    if (loads_touch) b.residual.head<12>() += load_block(model, step, j, old_prev, old_this, new_prev, new_this).residual;
    return;
  }
  MatX& Jp = b.jac[0];
  MatX& Jc = b.jac[1];
  const Mat12 dFp = new_level_flux_jacobian(prev.F_new, prev.nn.G), dFc = new_level_flux_jacobian(cur.F_new, cur.nn.G);
  const Mat12 MmJ = P.compliant() ? Mm_jacobian(P, 1.0 / (model.alpha.gt * step.dt)) : Mm;
  cell_scheme_jacobian<12>(Jp, Jc, model.alpha, model.carries_ys(), model.ds(), step.dt, MmJ, Kk, dFp, dFc);
  if (P.B_bt != Vec3::Zero()) add_bending_viscosity_jacobian(Jp, Jc, model, step.dt);

  if (loads_touch) {  // else load_block is zero
    const LocalBlock lb = load_block(model, step, j, old_prev, old_this, new_prev, new_this);
    b.residual.head<12>() += lb.residual;
    Jp.topRows(12) += lb.jac[0];
    Jc.topRows(12) += lb.jac[1];
  }
}

namespace {
LocalBlock end_block(const RodModel& model, const StepTimes& step, const EndCondition& c,
                     Eigen::Index row, int node, const RodNode& old_node, const VecX& new_node,
                     bool collocate) {
  check_unknowns(model, new_node);
  const int p = model.unknowns_per_node();
  const AlphaParameters& a = model.alpha;
  LocalBlock b = make_block(row, collocate ? 18 : 6, p, {model.node_col(node)});
  const Vec12 y = new_node.head<12>();
  const NewLevelNode nn = new_level_node(model, old_node, y, step.dt);
  const double rate = 1.0 / (a.gt * step.dt);  // d y_t / d y_new
  Vec6 r;
  Eigen::Matrix<double, 6, 12> J;
  // The loads' end share F (fixed frame) acts on the end: the rows read the contact force
  // less the external one, n - sign R F (n(L) = F at the right end, n(0) = -F at the left),
  // so a free or sliding end carries it and a support's rows, which read no force, absorb it.
  const double sign = node == 0 ? -1.0 : 1.0;
  const Vec3 Fb = nn.R * end_point_force(model, node, step.t_new());
  Vec12 y_rows = y;
  y_rows.segment<3>(var::n) -= sign * Fb;
  end_condition_rows(c, model.props, step.t_new(), y_rows, nn.R, nn.G, r, J, nn.yt.segment<3>(var::kappa), rate);
  if (Fb != Vec3::Zero()) J.block<6, 3>(0, var::omega) -= sign * J.block<6, 3>(0, var::n) * hat(Fb) * nn.G;
  b.residual.head<6>() = r;
  b.jac[0].block<6, 12>(0, 0) = J;
  if (collocate) {
    // PDE collocated at the node (closes the carried-ys system); a point load's share of the
    // end node is in the end rows above.
    const RodProperties& P = model.props;
    const Mat12 Mm = Mm_matrix(P), Kk = Kk_matrix(P);
    const double s = node * model.ds();
    const NodeFlux Fo = node_flux(model, old_node.y, old_node.yt, 0.0, old_node.R, s, step.t_old, false);
    const NodeFlux Fn = node_flux(model, y, nn.yt, rate, nn.R, s, step.t_new());
    const Vec12 ys = new_node.tail<12>();
    b.residual.segment<12>(6) = Mm * ((1.0 - a.at) * nn.yt + a.at * old_node.yt) +
                                Kk * ((1.0 - a.bt) * ys + a.bt * old_node.ys) +
                                (1.0 - a.bt) * Fn.F + a.bt * Fo.F;
    b.jac[0].block<12, 12>(6, 0) = (1.0 - a.at) / (a.gt * step.dt) * (P.compliant() ? Mm_jacobian(P, rate) : Mm) +
                                   (1.0 - a.bt) * new_level_flux_jacobian(Fn, nn.G);
    b.jac[0].block<12, 12>(6, 12) = (1.0 - a.bt) * Kk;
    if (P.B_bt != Vec3::Zero()) {  // -(B kappa_t)_s = -B (kappa_s)_t
      b.residual.segment<3>(6 + 3) -= P.B_bt.cwiseProduct((1.0 - a.bt) * carried_kappa_rate(model, old_node, new_node, step.dt) +
                                                          a.bt * old_node.kst);
      b.jac[0].block<3, 3>(6 + 3, 12 + var::kappa) -= Mat3(P.B_bt.asDiagonal()) * ((1.0 - a.bt) * rate);
    }
  }
  return b;
}
}  // namespace

LocalBlock left_block(const RodModel& model, const StepTimes& step, const RodNode& old_node,
                      const VecX& new_node) {
  return end_block(model, step, model.left, model.left_row(), 0, old_node, new_node,
                   model.carries_ys());
}

LocalBlock right_block(const RodModel& model, const StepTimes& step, const RodNode& old_node,
                       const VecX& new_node) {
  return end_block(model, step, model.right, model.right_row(), model.num_cells, old_node,
                   new_node, false);
}

std::vector<LocalBlock> assemble_nodes(const RodModel& model, const StepTimes& step,
                                       int first_node, int last_node, int offset,
                                       const std::vector<RodNode>& old_nodes,
                                       const std::vector<VecX>& new_unknowns) {
  const int N = model.num_cells;
  if (first_node < 0 || last_node > N || first_node > last_node)
    throw std::out_of_range("assemble_nodes: node range");
  if (offset > std::max(first_node - 1, 0) ||
      offset + static_cast<int>(old_nodes.size()) <= last_node ||
      old_nodes.size() != new_unknowns.size())
    throw std::out_of_range("assemble_nodes: the arrays do not cover the range and its ghost");
  std::vector<LocalBlock> out;
  auto O = [&](int j) -> const RodNode& { return old_nodes[static_cast<size_t>(j - offset)]; };
  auto X = [&](int j) -> const VecX& { return new_unknowns[static_cast<size_t>(j - offset)]; };
  for (int j = first_node; j <= last_node; ++j) {
    if (j == 0) out.push_back(left_block(model, step, O(0), X(0)));
    if (j >= 1) out.push_back(cell_block(model, step, j, O(j - 1), O(j), X(j - 1), X(j)));
    if (j == N) out.push_back(right_block(model, step, O(N), X(N)));
  }
  return out;
}

VecX node_unknowns(const RodModel& model, const RodNode& node) {
  VecX x(model.unknowns_per_node());
  x.head<12>() = node.y;
  if (model.carries_ys()) x.tail<12>() = node.ys;
  return x;
}

RodNode advance_node(const RodModel& model, const RodNode& old_node, const VecX& new_unknowns,
                     double dt) {
  check_unknowns(model, new_unknowns);
  RodNode n{RodNode::NoInit{}};  // every member is assigned below
  n.y = new_unknowns.head<12>();
  const NewLevelNode nn = new_level_node(model, old_node, n.y, dt, false);
  n.R = nn.R;
  n.yt = nn.yt;
  n.yv = (n.y - old_node.y) / dt;
  // The entries the old node's secant predicted to within half of their change in this step
  // (smooth there) are extrapolated by the next step's blended guess; the others (a load's jump
  // passing, a velocity alternating from step to step) start from the old level.
  for (int i = 0; i < 12; ++i) {
    const double d = n.y(i) - old_node.y(i);
    n.yg(i) = std::abs(d - dt * old_node.yv(i)) < 0.5 * std::abs(d) ? n.yv(i) : 0.0;
  }
  n.ys = model.carries_ys() ? Vec12(new_unknowns.tail<12>()) : Vec12::Zero();
  n.kst = model.carries_ys() && model.props.B_bt != Vec3::Zero() ? carried_kappa_rate(model, old_node, new_unknowns, dt)
                                                                : Vec3::Zero();
  return n;
}

}  // namespace traverse::rod

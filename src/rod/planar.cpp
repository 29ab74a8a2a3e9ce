#include "traverse/rod/planar.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "traverse/core/so3.hpp"
#include "traverse/rod/cell_scheme.hpp"
#include "traverse/rod/end_condition.hpp"

namespace traverse::rod {

namespace {

/// Frames: d_a may differ from the normal by this much (absolute; R's entries are O(1)).
constexpr double kFrameTolerance = 1e-10;
/// End-row probe: an entry is "zero" below this fraction of the row's largest entry.
constexpr double kProbeTolerance = 1e-10;

std::string vec_text(const Vec3& v) {
  std::ostringstream os;
  os.precision(6);
  os << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return os.str();
}

/// Whether entry k of a 12-vector is in-plane for normal axis a.
std::array<bool, 12> even_mask(int axis) {
  std::array<bool, 12> m{};
  for (int c : in_plane_components(axis)) m[static_cast<size_t>(c)] = true;
  return m;
}

/// Largest |out-of-plane entry| and largest |entry| of a 12-vector.
void parity_norms(const Vec12& v, const std::array<bool, 12>& even, double& odd_max, double& all_max) {
  for (int k = 0; k < 12; ++k) {
    const double a = std::abs(v(k));
    all_max = std::max(all_max, a);
    if (!even[static_cast<size_t>(k)]) odd_max = std::max(odd_max, a);
  }
}

/// One probe of an end's 6 rows (residual r, Jacobian J at a symmetric state whose unknowns
/// are at most x_max): a row is in-plane (+1 in kind) when no out-of-plane unknown enters it,
/// out-of-plane (-1) when no in-plane unknown enters it and it is zero; it must be one of them
/// and agree with the earlier probes (`row`: the first that does not).
enum class RowProbe { ok, no_unknown, mixed };
RowProbe classify_end_rows(const Vec6& r, const Eigen::Matrix<double, 6, 12>& J, const std::array<bool, 12>& even,
                           double x_max, std::array<int, 6>& kind, int& row) {
  for (int i = 0; i < 6; ++i) {
    row = i;
    double je = 0.0, jo = 0.0;
    for (int k = 0; k < 12; ++k) {
      const double v = std::abs(J(i, k));
      if (even[static_cast<size_t>(k)]) je = std::max(je, v);
      else jo = std::max(jo, v);
    }
    const double jm = std::max(je, jo);
    if (!(jm > 0.0)) return RowProbe::no_unknown;
    int k = 0;
    if (jo <= kProbeTolerance * jm) k = +1;
    else if (je <= kProbeTolerance * jm && std::abs(r(i)) <= kProbeTolerance * std::max(1.0, jm * x_max))
      k = -1;
    if (k == 0 || (kind[static_cast<size_t>(i)] != 0 && kind[static_cast<size_t>(i)] != k)) return RowProbe::mixed;
    kind[static_cast<size_t>(i)] = k;
  }
  return RowProbe::ok;
}

/// The in-plane rows after the probes (the first 3 into rows); returns how many there are.
int in_plane_rows(const std::array<int, 6>& kind, std::array<int, 3>& rows) {
  int n_even = 0;
  for (int i = 0; i < 6; ++i)
    if (kind[static_cast<size_t>(i)] > 0) {
      if (n_even < 3) rows[static_cast<size_t>(n_even)] = i;
      ++n_even;
    }
  return n_even;
}

/// Splits one end's 6 rows into 3 in-plane and 3 out-of-plane rows by probing
/// end_condition_rows at random symmetric states; returns "" or what is wrong.
std::string split_end_rows(const EndCondition& c, const RodModel& model, const RodNode& node, int axis,
                           const Vec3& normal, double t0, const char* which, std::array<int, 3>& rows) {
  const std::array<int, 6> S = in_plane_components(axis);
  const std::array<bool, 12> even = even_mask(axis);
  std::mt19937 rng(12345u + static_cast<unsigned>(axis));
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  // +1 in-plane, -1 out-of-plane, 0 not classified yet.
  std::array<int, 6> kind{};
  const double times[4] = {t0, t0 + 0.37, t0 + 3.1, t0 + 29.0};
  for (double t : times) {
    RodNode old;
    old.R = node.R * so3::exp(U(rng) * normal).transpose();  // the frame turned about the normal
    Vec12 y = Vec12::Zero();
    for (int k : S) {
      old.y(k) = U(rng);
      old.yt(k) = U(rng);
      y(k) = U(rng);
    }
    const double dt = 0.01 + 0.1 * std::abs(U(rng));
    const NewLevelNode nn = new_level_node(old, y, dt, model.alpha);
    Vec6 r;
    Eigen::Matrix<double, 6, 12> J;
    end_condition_rows(c, model.props, t, y, nn.R, nn.G, r, J);
    int row = 0;
    const RowProbe p = classify_end_rows(r, J, even, y.cwiseAbs().maxCoeff(), kind, row);
    if (p == RowProbe::no_unknown)
      return std::string(which) + " end: row " + std::to_string(row) + " depends on no unknown";
    if (p == RowProbe::mixed)
      return std::string(which) + " end: its condition row " + std::to_string(row) +
             " mixes in-plane and out-of-plane components (or is not zero out of the plane) for the plane "
             "normal " + vec_text(normal);
  }
  const int n_even = in_plane_rows(kind, rows);
  if (n_even != 3)
    return std::string(which) + " end: " + std::to_string(n_even) +
           " of its 6 rows are in-plane (3 needed) for the plane normal " + vec_text(normal);
  return "";
}

/// The static counterpart of split_end_rows: static_end_rows at random symmetric nodes
/// (in-plane unknowns random, the reference frame turned about the normal); false when the
/// rows do not split 3 + 3.
bool split_static_end_rows(const StaticModel& m, const StaticEnd& c, double sign, int axis, std::array<int, 3>& rows) {
  const std::array<int, 6> S = in_plane_components(axis);
  const std::array<bool, 12> even = even_mask(axis);
  const Vec3 normal = Vec3::Unit(axis);
  std::mt19937 rng(54321u + static_cast<unsigned>(axis));
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::array<int, 6> kind{};  // +1 in-plane, -1 out-of-plane, 0 not classified yet
  for (int probe = 0; probe < 4; ++probe) {
    StaticNode node;
    node.Rbar = so3::exp(U(rng) * normal);
    for (int k : S) node.x(k) = U(rng);
    LocalBlock b;
    b.residual = VecX::Zero(6);
    b.cols = {0};
    b.jac = {MatX::Zero(6, 12)};
    static_end_rows(m, c, node, sign, b);
    int row = 0;
    if (classify_end_rows(Vec6(b.residual), Eigen::Matrix<double, 6, 12>(b.jac[0]), even, node.x.cwiseAbs().maxCoeff(),
                          kind, row) != RowProbe::ok)
      return false;
  }
  return in_plane_rows(kind, rows) == 3;
}

/// "" when the problem is symmetric about the plane normal to d_axis, else the reason.
std::string check_axis(const RodModel& model, const PlanarStateSummary& st, const RodNode& left_end,
                       const RodNode& right_end, double t, const std::vector<Vec3>& forces, double tol, int axis,
                       PlanarSymmetry& sym) {
  const size_t a = static_cast<size_t>(axis);
  const Vec3 normal = left_end.R.row(axis).transpose().normalized();
  // The frames: d_axis is the same fixed vector at every node.
  if (st.frame_node[a] >= 0) {
    std::ostringstream os;
    os << "the frame at node " << st.frame_node[a] << " is turned out of the plane normal to " << vec_text(normal)
       << " (|d" << axis + 1 << " - normal| = " << st.frame_dev[a] << ")";
    return os.str();
  }
  // Intrinsic curvature: only its component about the normal.
  const Vec3& k0 = model.props.kappa0;
  for (int c = 0; c < 3; ++c)
    if (c != axis && !(std::abs(k0(c)) <= tol * k0.cwiseAbs().maxCoeff()))
      return "the intrinsic curvature " + vec_text(k0) + " has a component out of the plane";
  // The state: out-of-plane components of y, yt, ys zero relative to each array's largest entry.
  const char* names[3] = {"y (u, omega, kappa, n)", "yt", "ys"};
  for (size_t k = 0; k < 3; ++k) {
    const double odd = st.odd[a][k], all = st.all[a][k];
    if (!(odd <= tol * all)) {
      std::ostringstream os;
      os << "the state's " << names[k] << " has out-of-plane components (largest " << odd << " at node "
         << st.odd_node[a][k] << ", relative " << odd / all << ")";
      return os.str();
    }
  }
  // Loads.
  const Vec3& g = model.loads.gravity;
  if (!(std::abs(g.dot(normal)) <= tol * g.norm())) return "gravity " + vec_text(g) + " is not in the plane";
  if (model.loads.f_fixed || model.loads.l_fixed)
    return "distributed loads given as functions (f_fixed, l_fixed) are not checked for planarity";
  if (forces.size() != model.loads.point_forces.size())
    return "the vectors of the point forces were not given (" + std::to_string(forces.size()) + " for " +
           std::to_string(model.loads.point_forces.size()) + " forces)";
  for (size_t i = 0; i < forces.size(); ++i)
    if (!(std::abs(forces[i].dot(normal)) <= tol * forces[i].norm()))
      return "point force " + std::to_string(i) + " " + vec_text(forces[i]) + " has a component " +
             vec_text(forces[i].dot(normal) * normal) + " out of the plane";
  // End conditions.
  sym.normal = normal;
  sym.axis = axis;
  if (std::string e = split_end_rows(model.left, model, left_end, axis, normal, t, "left", sym.left_rows);
      !e.empty())
    return e;
  if (std::string e = split_end_rows(model.right, model, right_end, axis, normal, t, "right", sym.right_rows);
      !e.empty())
    return e;
  return "";
}

}  // namespace

std::string PlanarSymmetry::describe() const {
  return "plane normal " + vec_text(normal) + " = d" + std::to_string(axis + 1);
}

std::array<int, 6> in_plane_components(int axis) {
  if (axis != 0 && axis != 1) throw std::invalid_argument("in_plane_components: axis must be 0 or 1");
  const int b = axis == 0 ? 1 : 0, c = 2;
  // polar (u, n): the two components other than a; axial (omega, kappa): component a.
  std::array<int, 6> s{{var::u + b, var::u + c, var::omega + axis, var::kappa + axis, var::n + b, var::n + c}};
  return s;
}

PlanarStateSummary summarize_planarity(const RodState& piece, int first_node, const Mat3& R0) {
  PlanarStateSummary out;
  out.first_node = first_node;
  for (size_t a = 0; a < 2; ++a) {
    const std::array<bool, 12> even = even_mask(static_cast<int>(a));
    const Vec3 normal = R0.row(static_cast<Eigen::Index>(a)).transpose().normalized();
    for (size_t j = 0; j < piece.nodes.size(); ++j) {
      const RodNode& nd = piece.nodes[j];
      const long node = first_node + static_cast<long>(j);
      const double dev = (nd.R.row(static_cast<Eigen::Index>(a)).transpose() - normal).cwiseAbs().maxCoeff();
      if (!(dev <= kFrameTolerance) && out.frame_node[a] < 0) {
        out.frame_node[a] = node;
        out.frame_dev[a] = dev;
      }
      for (size_t k = 0; k < 3; ++k) {
        const Vec12& v = k == 0 ? nd.y : k == 1 ? nd.yt : nd.ys;
        const double before = out.odd[a][k];
        parity_norms(v, even, out.odd[a][k], out.all[a][k]);
        if (out.odd[a][k] > before) out.odd_node[a][k] = node;
      }
    }
  }
  return out;
}

void merge(PlanarStateSummary& into, const PlanarStateSummary& later) {
  for (size_t a = 0; a < 2; ++a) {
    if (into.frame_node[a] < 0 && later.frame_node[a] >= 0) {
      into.frame_node[a] = later.frame_node[a];
      into.frame_dev[a] = later.frame_dev[a];
    }
    for (size_t k = 0; k < 3; ++k) {
      if (later.odd[a][k] > into.odd[a][k]) {
        into.odd[a][k] = later.odd[a][k];
        into.odd_node[a][k] = later.odd_node[a][k];
      }
      into.all[a][k] = std::max(into.all[a][k], later.all[a][k]);
    }
  }
}

PlanarCheck check_planar(const RodModel& model, const RodState& state, const std::vector<Vec3>& point_force_vectors,
                         double tol) {
  if (state.nodes.size() != static_cast<size_t>(model.num_cells) + 1) {
    PlanarCheck out;
    out.reason = "the state has " + std::to_string(state.nodes.size()) + " nodes, the model " +
                 std::to_string(model.num_cells + 1);
    return out;
  }
  return check_planar(model, summarize_planarity(state, 0, state.nodes.front().R), state.nodes.front(),
                      state.nodes.back(), state.t, point_force_vectors, tol);
}

PlanarCheck check_planar(const RodModel& model, const PlanarStateSummary& summary, const RodNode& left_end,
                         const RodNode& right_end, double t, const std::vector<Vec3>& point_force_vectors,
                         double tol) {
  PlanarCheck out;
  std::string reasons;
  for (int axis = 0; axis < 2; ++axis) {
    PlanarSymmetry sym;
    const std::string why = check_axis(model, summary, left_end, right_end, t, point_force_vectors, tol, axis, sym);
    if (why.empty()) {
      out.planar = true;
      out.symmetry = sym;
      out.reason.clear();
      return out;
    }
    reasons += std::string(reasons.empty() ? "" : "; ") + "about d" + std::to_string(axis + 1) + ": " + why;
  }
  out.reason = reasons;
  return out;
}

PlanarReduction::PlanarReduction(const RodModel& model, const PlanarSymmetry& symmetry)
    : sym_(symmetry), num_cells_(model.num_cells), carried_(model.carries_ys()) {
  p_ = model.unknowns_per_node();
  q_ = p_ / 2;
  full_left_row_ = model.left_row();
  full_right_row_ = model.right_row();
  const std::array<int, 6> S = in_plane_components(sym_.axis);
  for (int c : S) cols_.push_back(c);
  if (carried_)
    for (int c : S) cols_.push_back(12 + c);
  for (int r : sym_.left_rows) left_keep_.push_back(r);
  if (carried_)
    for (int c : S) left_keep_.push_back(6 + c);  // the PDE collocated at node 0
  cell_keep_ = cols_;                              // PDE rows like y, recursion rows like ys
  for (int r : sym_.right_rows) right_keep_.push_back(r);
  auto complement = [](const std::vector<int>& keep, int n) {
    std::vector<int> d;
    for (int i = 0; i < n; ++i)
      if (std::find(keep.begin(), keep.end(), i) == keep.end()) d.push_back(i);
    return d;
  };
  left_drop_ = complement(left_keep_, carried_ ? 18 : 6);
  cell_drop_ = complement(cell_keep_, model.cell_rows());
  right_drop_ = complement(right_keep_, 6);
  if (left_keep_.size() + left_drop_.size() != (carried_ ? 18u : 6u) || right_keep_.size() != 3 ||
      right_drop_.size() != 3)
    throw std::invalid_argument("PlanarReduction: the end rows must split 3 + 3");
  for (int c = 0; c < 6; ++c) {  // the in-plane rows and columns of Mm and Kk
    const Vec12 e = Vec12::Unit(S[static_cast<size_t>(c)]);
    const Vec12 Me = apply_Mm(model.props, e), Ke = apply_Kk(model.props, e);
    for (int r = 0; r < 6; ++r) {
      Mm6_(r, c) = Me(S[static_cast<size_t>(r)]);
      Kk6_(r, c) = Ke(S[static_cast<size_t>(r)]);
    }
  }
  sigma_ = sym_.axis == 0 ? 1.0 : -1.0;
  if (model.loads.f_fixed || model.loads.l_fixed)
    throw std::invalid_argument("PlanarReduction: distributed loads given as functions are not planar");
}

PlanarReduction::OldNode PlanarReduction::old_node(const RodModel& model, const StepTimes& step, int j,
                                                   const RodNode& old) const {
  const NodeFlux F = old_level_flux(model, step, j, old);
  OldNode o;
  for (int i = 0; i < 6; ++i) {
    const int c = cols_[static_cast<size_t>(i)];
    o.y(i) = old.y(c);
    o.yt(i) = old.yt(c);
    o.ys(i) = old.ys(c);
    o.F(i) = F.F(c);
  }
  o.kst = old.kst(sym_.axis);
  o.fb.setZero();
  if (model.loads.has_frame_loads()) {
    const Vec3 fb = old.R * (model.props.rhoA * model.loads.gravity);
    o.fb << fb(cols_[0]), fb(cols_[1]);  // the polar in-plane components (b, 3)
    o.fb_normal = fb(sym_.axis);
  }
  return o;
}

void PlanarReduction::new_levels(const RodModel& model, const StepTimes& step, const OldNode& o, const double* x,
                                 NewLevels& L) const {
  // In-plane components, in the order of in_plane_components: u = (u_b, u_3), omega_a, kappa_a,
  // n = (n_b, n_3). With only these nonzero, the 3D flux (node_flux) reduces to
  //   F_u = -s k J n + rhoA s w J u - fb,  F_omega = s n_b,  F_kappa = 0,  F_n = s k J u + (s w, 0)
  // (k x v = s k J v for a polar v, s = sigma_), and the new frame is the old one turned about
  // the normal by theta = -dt (w + w_old) / 2, so fb = rotation(theta) fb_old, d fb / d w =
  // -(dt / 2) s J fb.
  const AlphaParameters& a = model.alpha;
  const double dt = step.dt, s = sigma_, rhoA = model.props.rhoA;
  const Eigen::Map<const Vec6> y(x);
  L.yt = (y - o.y) / (a.gt * dt) - (1.0 - a.gt) / a.gt * o.yt;
  auto J = [](const Eigen::Vector2d& v) { return Eigen::Vector2d(-v(1), v(0)); };
  const Eigen::Vector2d u(y(0), y(1)), n(y(4), y(5));
  const double w = y(2), k = y(3);
  Eigen::Vector2d fb = Eigen::Vector2d::Zero();
  if (model.loads.has_frame_loads()) {
    const double th = -0.5 * dt * (w + o.y(2));
    fb = std::cos(th) * o.fb + (s * std::sin(th)) * J(o.fb);
  }
  const Eigen::Vector2d Ju = J(u), Jn = J(n), Jfb = J(fb);
  const Eigen::Vector2d Fu = -(s * k) * Jn + (rhoA * s * w) * Ju - fb;
  const Eigen::Vector2d Fn = (s * k) * Ju + Eigen::Vector2d(s * w, 0.0);
  L.F << Fu(0), Fu(1), s * n(0), 0.0, Fn(0), Fn(1);
  const bool compliant = model.props.compliant();
  Eigen::Vector2d v(0.0, 1.0), dv = Eigen::Vector2d::Zero();  // strain (v_b, v_3) and dv / dn (diagonal)
  if (compliant) strain_levels(model, step, o, n, L, v, dv);
  Eigen::Matrix<double, 6, 6>& D = L.dF;
  D.setZero();
  D(0, 1) = -rhoA * s * w;  // d F_u / d u = rhoA s w J
  D(1, 0) = rhoA * s * w;
  D(0, 2) = rhoA * s * Ju(0) + 0.5 * dt * s * Jfb(0);  // d F_u / d w, the frame's turn included
  D(1, 2) = rhoA * s * Ju(1) + 0.5 * dt * s * Jfb(1);
  D(0, 3) = -s * Jn(0);  // d F_u / d k
  D(1, 3) = -s * Jn(1);
  D(0, 5) = s * k;  // d F_u / d n = -s k J
  D(1, 4) = -s * k;
  D(2, 4) = s;       // d F_omega / d n_b
  D(4, 1) = -s * k;  // d F_n / d u = s k J
  D(5, 0) = s * k;
  D(4, 2) = s;  // d F_n / d w
  D(4, 3) = s * Ju(0);  // d F_n / d k
  D(5, 3) = s * Ju(1);
  if (!compliant) return;
  // The strain v in place of e3: F_omega = s (v_3 n_b - v_b n_3) (- v x n), F_n gains
  // s w (v_3, -v_b) (- omega x v); v depends on n through dv.
  L.F(2) = s * (v(1) * n(0) - v(0) * n(1));
  L.F(4) = s * k * Ju(0) + s * w * v(1);
  L.F(5) = s * k * Ju(1) - s * w * v(0);
  D(2, 4) = s * (v(1) - n(1) * dv(0));
  D(2, 5) = s * (n(0) * dv(1) - v(0));
  D(4, 2) = s * v(1);
  D(5, 2) = -s * v(0);
  D(4, 5) = s * w * dv(1);
  D(5, 4) = -s * w * dv(0);
}

void PlanarReduction::strain_levels(const RodModel& model, const StepTimes& step, const OldNode& o,
                                    const Eigen::Vector2d& n, NewLevels& L, Eigen::Vector2d& v,
                                    Eigen::Vector2d& dv) const {
  // The 3D kernel's strain rate and strain (rod_kernels.cpp) with the in-plane components
  // embedded (the normal's component of n and v_t is zero).
  const int b = cols_[4] - var::n;
  auto embed3 = [b](double pb, double p3) {
    Vec3 e = Vec3::Zero();
    e(b) = pb;
    e(2) = p3;
    return e;
  };
  const RodProperties& p = model.props;
  const Vec3 vt = strain_rate(p, embed3(o.y(4), o.y(5)), embed3(o.yt(4), o.yt(5)), embed3(n(0), n(1)), step.dt,
                              model.alpha);
  L.yt(4) = vt(b);
  L.yt(5) = vt(2);
  const Vec3 v3 = p.strain(embed3(n(0), n(1)), vt);
  const Vec3 d3 = effective_compliance(p, 1.0 / (model.alpha.gt * step.dt));
  v << v3(b), v3(2);
  dv << d3(b), d3(2);
}

double PlanarReduction::cell_block_into(LocalBlock& b, const RodModel& model, const StepTimes& step, int j,
                                      const OldNode& op, const OldNode& oc, const double* xp, const double* xc,
                                      const NewLevels& lp, const NewLevels& lc, bool jacobian) const {
  if (j < 1 || j > num_cells_) throw std::out_of_range("PlanarReduction::cell_block_into: cell index");
  b.row = (carried_ ? 9 : 3) + static_cast<Eigen::Index>(q_) * (j - 1);
  b.cols.resize(2);
  b.cols[0] = static_cast<Eigen::Index>(q_) * (j - 1);
  b.cols[1] = static_cast<Eigen::Index>(q_) * j;
  b.jac.resize(2);
  for (MatX& J : b.jac) J.setZero(q_, q_);
  using M6 = Eigen::Map<const Vec6>;
  const CellNode<6> P{op.y, op.yt, op.ys, op.F, M6(xp), M6(carried_ ? xp + 6 : xp), lp.yt, lp.F};
  const CellNode<6> C{oc.y, oc.yt, oc.ys, oc.F, M6(xc), M6(carried_ ? xc + 6 : xc), lc.yt, lc.F};
  cell_scheme_residual<6>(b.residual, model.alpha, carried_, model.ds(), Mm6_, Kk6_, P, C);
  if (jacobian) {
    // With strain, the strain rate's slots depend on n through the effective compliance.
    Eigen::Matrix<double, 6, 6> MmJ = Mm6_;
    if (model.props.compliant()) {
      const Vec3 ce = effective_compliance(model.props, 1.0 / (model.alpha.gt * step.dt));
      MmJ(4, 4) = -ce(cols_[4] - var::n);
      MmJ(5, 5) = -ce(2);
    }
    cell_scheme_jacobian<6>(b.jac[0], b.jac[1], model.alpha, carried_, model.ds(), step.dt, MmJ, Kk6_, lp.dF, lc.dF);
  }
  add_bending_viscosity(b, model, step, op, oc, xp, xc, lp, lc);
  // The dropped momentum row along the normal: A_F of -fb_normal (the same at both levels).
  const double bs = model.alpha.bs;
  return std::abs((1.0 - bs) * oc.fb_normal + bs * op.fb_normal);
}

void PlanarReduction::add_bending_viscosity(LocalBlock& b, const RodModel& model, const StepTimes& step,
                                            const OldNode& op, const OldNode& oc, const double* xp, const double* xc,
                                            const NewLevels& lp, const NewLevels& lc) const {
  // -(B kappa_t)_s in the spin row (2) about the normal, as the 3D cell (rod_kernels.cpp).
  const double B = model.props.B_bt(sym_.axis);
  if (B == 0.0) return;
  const AlphaParameters& a = model.alpha;
  const double ds = model.ds(), rate = 1.0 / (a.gt * step.dt);
  if (carried_) {  // the carried kappa_s (unknown 6 + 3) and its rate
    auto kst = [&](const OldNode& o, const double* x) { return (x[9] - o.ys(3)) * rate - (1.0 - a.gt) / a.gt * o.kst; };
    b.residual(2) -= B * ((1.0 - a.bt) * ((1.0 - a.bs) * kst(oc, xc) + a.bs * kst(op, xp)) +
                          a.bt * ((1.0 - a.bs) * oc.kst + a.bs * op.kst));
    b.jac[1](2, 9) -= (1.0 - a.bt) * (1.0 - a.bs) * rate * B;
    b.jac[0](2, 9) -= (1.0 - a.bt) * a.bs * rate * B;
    return;
  }
  b.residual(2) -= B * ((1.0 - a.bt) * (lc.yt(3) - lp.yt(3)) + a.bt * (oc.yt(3) - op.yt(3))) / ds;
  const double D = (1.0 - a.bt) / ds * rate * B;
  b.jac[1](2, 3) -= D;
  b.jac[0](2, 3) += D;
}

double PlanarReduction::add_loads(LocalBlock& cell, const LocalBlock& loads) const {
  // cols_ starts with the 6 in-plane components; the load's rows are the 12 PDE rows.
  for (int i = 0; i < 6; ++i) cell.residual(i) += loads.residual(cols_[static_cast<size_t>(i)]);
  for (size_t side = 0; side < 2; ++side)
    for (int ic = 0; ic < 6; ++ic)
      for (int ir = 0; ir < 6; ++ir)
        cell.jac[side](ir, ic) += loads.jac[side](cols_[static_cast<size_t>(ir)], cols_[static_cast<size_t>(ic)]);
  double dropped = 0.0;
  for (int k : cell_drop_)
    if (k < 12) dropped = std::max(dropped, std::abs(loads.residual(k)));
  return dropped;
}

VecX PlanarReduction::restrict_unknowns(const VecX& full) const {
  if (full.size() != p_) throw std::invalid_argument("PlanarReduction::restrict_unknowns: wrong block size");
  VecX q(q_);
  for (int c = 0; c < q_; ++c) q(c) = full(cols_[static_cast<size_t>(c)]);
  return q;
}

void PlanarReduction::embed(const double* planar, VecX& full) const {
  full.setZero(p_);
  for (int c = 0; c < q_; ++c) full(cols_[static_cast<size_t>(c)]) = planar[c];
}

double PlanarReduction::restrict_block(const LocalBlock& full, LocalBlock& out) const {
  const std::vector<int>* keep = nullptr;
  const std::vector<int>* drop = nullptr;
  const Eigen::Index first_cell = carried_ ? 18 : 6, cell_rows = carried_ ? 24 : 12;
  const Eigen::Index planar_first_cell = carried_ ? 9 : 3, planar_cell_rows = q_;
  if (full.row == full_left_row_) {
    keep = &left_keep_;
    drop = &left_drop_;
    out.row = 0;
  } else if (full.row == full_right_row_) {
    keep = &right_keep_;
    drop = &right_drop_;
    out.row = planar_first_cell + planar_cell_rows * num_cells_;
  } else {
    const Eigen::Index off = full.row - first_cell;
    if (off < 0 || off % cell_rows != 0 || off / cell_rows >= num_cells_)
      throw std::invalid_argument("PlanarReduction::restrict_block: not a block of this model");
    keep = &cell_keep_;
    drop = &cell_drop_;
    out.row = planar_first_cell + planar_cell_rows * (off / cell_rows);
  }
  if (full.residual.size() != static_cast<Eigen::Index>(keep->size() + drop->size()))
    throw std::invalid_argument("PlanarReduction::restrict_block: unexpected number of rows");
  const Eigen::Index n = static_cast<Eigen::Index>(keep->size());
  out.residual.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) out.residual(i) = full.residual((*keep)[static_cast<size_t>(i)]);
  out.cols.resize(full.cols.size());
  out.jac.resize(full.jac.size());
  for (size_t k = 0; k < full.cols.size(); ++k) {
    if (full.cols[k] % p_ != 0 || full.jac[k].cols() != p_)
      throw std::invalid_argument("PlanarReduction::restrict_block: unexpected columns");
    out.cols[k] = full.cols[k] / p_ * q_;
    const MatX& J = full.jac[k];
    MatX& Jq = out.jac[k];
    Jq.resize(n, q_);
    for (int c = 0; c < q_; ++c) {
      const Eigen::Index src = cols_[static_cast<size_t>(c)];
      for (Eigen::Index i = 0; i < n; ++i) Jq(i, c) = J((*keep)[static_cast<size_t>(i)], src);
    }
  }
  double dropped = 0.0;
  for (int r : *drop) dropped = std::max(dropped, std::abs(full.residual(r)));
  return dropped;
}

std::optional<StaticPlanarSplit> static_planar_split(const StaticModel& m, double tol) {
  for (int axis = 0; axis < 2; ++axis) {
    const Vec3 normal = Vec3::Unit(axis);
    const Vec3& k0 = m.props.kappa0;
    bool symmetric = true;
    for (int c = 0; c < 3; ++c)
      if (c != axis && !(std::abs(k0(c)) <= tol * k0.cwiseAbs().maxCoeff())) symmetric = false;
    if (!(std::abs(m.gravity.dot(normal)) <= tol * m.gravity.norm())) symmetric = false;
    for (const StaticPointForce& f : m.point_forces)
      if (!(std::abs(f.force.dot(normal)) <= tol * f.force.norm())) symmetric = false;
    StaticPlanarSplit split;
    split.axis = axis;
    if (symmetric && split_static_end_rows(m, m.left, -1.0, axis, split.left_rows) &&
        split_static_end_rows(m, m.right, 1.0, axis, split.right_rows))
      return split;
  }
  return std::nullopt;
}

double restrict_static_block(const StaticModel& m, const StaticPlanarSplit& split, const LocalBlock& full,
                             LocalBlock& out) {
  const std::array<int, 6> S = in_plane_components(split.axis);
  const Eigen::Index N = m.num_cells;
  const int* keep = S.data();
  int kept = 6;
  if (full.row == 0) {
    keep = split.left_rows.data();
    kept = 3;
    out.row = 0;
  } else if (full.row == 12 * N + 6) {
    keep = split.right_rows.data();
    kept = 3;
    out.row = 3 + 6 * N;
  } else {
    const Eigen::Index off = full.row - 6;
    if (off < 0 || off % 12 != 0 || off / 12 >= N)
      throw std::invalid_argument("restrict_static_block: not a block of this model");
    out.row = 3 + 6 * (off / 12);
  }
  if (full.residual.size() != 2 * kept) throw std::invalid_argument("restrict_static_block: unexpected number of rows");
  out.residual.resize(kept);
  for (int i = 0; i < kept; ++i) out.residual(i) = full.residual(keep[i]);
  out.cols.resize(full.cols.size());
  out.jac.resize(full.jac.size());
  for (size_t k = 0; k < full.cols.size(); ++k) {
    if (full.cols[k] % 12 != 0 || full.jac[k].cols() != 12)
      throw std::invalid_argument("restrict_static_block: unexpected columns");
    out.cols[k] = full.cols[k] / 12 * 6;
    out.jac[k].resize(kept, 6);
    for (int c = 0; c < 6; ++c)
      for (int i = 0; i < kept; ++i) out.jac[k](i, c) = full.jac[k](keep[i], S[static_cast<size_t>(c)]);
  }
  double dropped = 0.0;
  for (Eigen::Index i = 0; i < full.residual.size(); ++i)
    if (std::find(keep, keep + kept, static_cast<int>(i)) == keep + kept)
      dropped = std::max(dropped, std::abs(full.residual(i)));
  return dropped;
}

}  // namespace traverse::rod

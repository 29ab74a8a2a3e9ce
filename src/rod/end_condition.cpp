#include "traverse/rod/end_condition.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "traverse/core/so3.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/rod/static_kernels.hpp"

namespace traverse::rod {

void perpendicular_pair(const Vec3& a, Vec3& b1, Vec3& b2) {
  const double na = a.norm();
  if (!(na > 0.0)) throw std::invalid_argument("perpendicular_pair: zero axis");
  const Vec3 e = a / na;
  Eigen::Index i = 0;
  e.cwiseAbs().minCoeff(&i);
  b1 = e.cross(Vec3::Unit(i)).normalized();
  b2 = e.cross(b1);
}

namespace {

using so3::hat;
using Jacobian6 = Eigen::Matrix<double, 6, 12>;

// ---------------------------------------------------------------------------------------
// Dynamic rows (at the new level: R, and G the sensitivity of R v to omega_new).
// ---------------------------------------------------------------------------------------
struct EndValues {
  Vec3 u, w, n, m;  // velocity, spin, force, moment (body components)
  Vec3 dm;          // d m / d kappa (diagonal): K, plus B_bt d kappa_t / d kappa with viscosity
};

// Rows 3..5 of a pin about the fixed axis `axis`: omega perpendicular to it is zero (2) and
// there is no moment about it (1).
void pin_rows(const Vec3& axis, const Vec3& dm, const Vec3& w, const Vec3& m, const Mat3& R,
              const Mat3& G, Vec6& r, Jacobian6& J) {
  Vec3 b1, b2;
  perpendicular_pair(axis, b1, b2);
  const Vec3 a = R * axis.normalized(), p1 = R * b1, p2 = R * b2;
  r(3) = w.dot(p1);
  r(4) = w.dot(p2);
  J.block<1, 3>(3, var::omega) = p1.transpose() + w.transpose() * hat(p1) * G;
  J.block<1, 3>(4, var::omega) = p2.transpose() + w.transpose() * hat(p2) * G;
  r(5) = m.dot(a);
  J.block<1, 3>(5, var::kappa) = a.cwiseProduct(dm).transpose();
  J.block<1, 3>(5, var::omega) = m.transpose() * hat(a) * G;
}

// The rows of an end that slides along `axis`: no velocity across it (rows 0 and 1) and the
// contact force along it equal to `force` (row k), with their Jacobian.
void slide_rows(const Vec3& axis, double force, int k, const Vec3& u, const Vec3& n, const Mat3& R, const Mat3& G,
                Vec6& r, Jacobian6& J) {
  Vec3 b1, b2;
  perpendicular_pair(axis, b1, b2);
  const Vec3 e = R * axis.normalized(), p1 = R * b1, p2 = R * b2;
  r(0) = u.dot(p1);
  r(1) = u.dot(p2);
  J.block<1, 3>(0, var::u) = p1.transpose();
  J.block<1, 3>(1, var::u) = p2.transpose();
  J.block<1, 3>(0, var::omega) = u.transpose() * hat(p1) * G;
  J.block<1, 3>(1, var::omega) = u.transpose() * hat(p2) * G;
  r(k) = n.dot(e) - force;
  J.block<1, 3>(k, var::n) = e.transpose();
  J.block<1, 3>(k, var::omega) = n.transpose() * hat(e) * G;
}

void clamped_rows(const EndCondition&, const RodProperties&, double, const EndValues& v, const Mat3&, const Mat3&,
                  Vec6& r, Jacobian6& J) {
  r.head<3>() = v.u;
  r.tail<3>() = v.w;
  J.block<3, 3>(0, var::u) = Mat3::Identity();
  J.block<3, 3>(3, var::omega) = Mat3::Identity();
}

void pinned_rows(const EndCondition& c, const RodProperties&, double, const EndValues& v, const Mat3& R,
                 const Mat3& G, Vec6& r, Jacobian6& J) {
  r.head<3>() = v.u;
  J.block<3, 3>(0, var::u) = Mat3::Identity();
  pin_rows(c.axis, v.dm, v.w, v.m, R, G, r, J);
}

void sliding_rows(const EndCondition& c, const RodProperties&, double, const EndValues& v, const Mat3& R,
                  const Mat3& G, Vec6& r, Jacobian6& J) {
  slide_rows(c.axis, 0.0, 5, v.u, v.n, R, G, r, J);
  r.segment<3>(2) = v.w;
  J.block<3, 3>(2, var::omega) = Mat3::Identity();
}

void roller_rows(const EndCondition& c, const RodProperties&, double, const EndValues& v, const Mat3& R,
                 const Mat3& G, Vec6& r, Jacobian6& J) {
  slide_rows(c.slide_axis, c.axial_force, 2, v.u, v.n, R, G, r, J);
  pin_rows(c.axis, v.dm, v.w, v.m, R, G, r, J);
}

void free_rows(const EndCondition&, const RodProperties&, double, const EndValues& v, const Mat3&, const Mat3&,
               Vec6& r, Jacobian6& J) {
  r.head<3>() = v.n;
  r.tail<3>() = v.m;
  J.block<3, 3>(0, var::n) = Mat3::Identity();
  J.block<3, 3>(3, var::kappa) = v.dm.asDiagonal();
}

void prescribed_rows(const EndCondition& c, const RodProperties&, double t, const EndValues& v, const Mat3& R,
                     const Mat3& G, Vec6& r, Jacobian6& J) {
  if (!c.u_fixed || !c.omega_fixed) throw std::invalid_argument("prescribed end condition without functions");
  const Vec3 ub = R * c.u_fixed(t), wb = R * c.omega_fixed(t);
  r.head<3>() = v.u - ub;
  r.tail<3>() = v.w - wb;
  J.block<3, 3>(0, var::u) = Mat3::Identity();
  J.block<3, 3>(0, var::omega) = -hat(ub) * G;
  J.block<3, 3>(3, var::omega) = Mat3::Identity() - hat(wb) * G;
}

// ---------------------------------------------------------------------------------------
// Static rows (docs/statics.md): the end's position and frame where the dynamic rows fix its
// velocity and spin.
// ---------------------------------------------------------------------------------------
struct StaticValues {
  Vec3 r, k, n;  // centreline, curvature, force
  Mat3 R, D;     // frame and its perturbation
};

// Rows 0..2: r = position.
void hold_position(const StaticEnd& c, const StaticValues& v, VecX& res, MatX& J) {
  res.segment<3>(0) = v.r - c.position;
  J.block<3, 3>(0, svar::r).setIdentity();
}

// Rows 0, 1: r - position has no component across `axis`.
void hold_across(const Vec3& axis, const StaticEnd& c, const StaticValues& v, VecX& res, MatX& J) {
  Vec3 b1, b2;
  perpendicular_pair(axis, b1, b2);
  res(0) = b1.dot(v.r - c.position);
  res(1) = b2.dot(v.r - c.position);
  J.block<1, 3>(0, svar::r) = b1.transpose();
  J.block<1, 3>(1, svar::r) = b2.transpose();
}

// Rows row .. row + 2: log(R frame^T) = 0.
void hold_frame(int row, const StaticEnd& c, const StaticValues& v, VecX& res, MatX& J) {
  const Vec3 phi = so3::log(v.R * c.frame.transpose());
  res.segment<3>(row) = phi;
  J.block<3, 3>(row, svar::theta) = so3::left_jacobian(phi).inverse() * v.D;
}

// Row k: the external force along `axis` is axial_force.
void axial_force_row(int k, const Vec3& axis, const StaticEnd& c, const StaticValues& v, double sign, VecX& res,
                     MatX& J) {
  const Vec3 e = axis.normalized(), Re = v.R * e;
  res(k) = v.n.dot(Re) - sign * c.axial_force;
  J.block<1, 3>(k, svar::n) = Re.transpose();
  J.block<1, 3>(k, svar::theta) = (v.n.transpose() * (-hat(Re))) * v.D;
}

// Rows 3..5 of a pin about c.axis: rotation relative to c.frame only about the axis (2) and
// no moment about it (1).
void static_pin_rows(const StaticModel& m, const StaticEnd& c, const StaticValues& v, VecX& res, MatX& J) {
  Vec3 b1, b2;
  perpendicular_pair(c.axis, b1, b2);
  const Vec3 phi = so3::log(c.frame.transpose() * v.R);
  const Mat3 dphi = so3::left_jacobian(phi).inverse() * c.frame.transpose() * v.D;
  res(3) = b1.dot(phi);
  res(4) = b2.dot(phi);
  J.block<1, 3>(3, svar::theta) = b1.transpose() * dphi;
  J.block<1, 3>(4, svar::theta) = b2.transpose() * dphi;
  const Vec3 a = c.axis.normalized(), Ra = v.R * a;
  const Vec3 mm = m.props.K.cwiseProduct(v.k - m.props.kappa0);
  res(5) = mm.dot(Ra);
  J.block<1, 3>(5, svar::kappa) = (Ra.cwiseProduct(m.props.K)).transpose();
  J.block<1, 3>(5, svar::theta) = (mm.transpose() * (-hat(Ra))) * v.D;
}

void clamped_static(const StaticModel&, const StaticEnd& c, const StaticValues& v, double, VecX& res, MatX& J) {
  hold_position(c, v, res, J);
  hold_frame(3, c, v, res, J);
}

void pinned_static(const StaticModel& m, const StaticEnd& c, const StaticValues& v, double, VecX& res, MatX& J) {
  hold_position(c, v, res, J);
  static_pin_rows(m, c, v, res, J);
}

void sliding_static(const StaticModel&, const StaticEnd& c, const StaticValues& v, double sign, VecX& res, MatX& J) {
  hold_across(c.axis, c, v, res, J);
  hold_frame(2, c, v, res, J);
  axial_force_row(5, c.axis, c, v, sign, res, J);
}

void roller_static(const StaticModel& m, const StaticEnd& c, const StaticValues& v, double sign, VecX& res, MatX& J) {
  hold_across(c.slide_axis, c, v, res, J);
  axial_force_row(2, c.slide_axis, c, v, sign, res, J);
  static_pin_rows(m, c, v, res, J);
}

void free_static(const StaticModel& m, const StaticEnd& c, const StaticValues& v, double sign, VecX& res, MatX& J) {
  const Vec3 Fb = v.R * c.end_force;
  res.segment<3>(0) = v.n - sign * Fb;
  J.block<3, 3>(0, svar::n).setIdentity();
  J.block<3, 3>(0, svar::theta) = sign * hat(Fb) * v.D;
  res.segment<3>(3) = m.props.K.cwiseProduct(v.k - m.props.kappa0);
  J.block<3, 3>(3, svar::kappa) = m.props.K.asDiagonal();
}

// ---------------------------------------------------------------------------------------
// Conversions from the scene's EndSpec (beyond its parameters, which every type keeps).
// ---------------------------------------------------------------------------------------
void prescribed_motion(const EndSpec& spec, EndCondition& c) {
  const Vec3 v = spec.velocity, w = spec.rotation_rate;
  c.u_fixed = [v](double) { return v; };
  c.omega_fixed = [w](double) { return w; };
}

// What makes a condition of this type ill-posed, or "".
std::string needs_axis(const EndCondition& c) { return c.axis.norm() > 0.0 ? "" : "zero axis"; }
std::string needs_axes(const EndCondition& c) {
  if (!(c.axis.norm() > 0.0)) return "zero axis";
  return c.slide_axis.norm() > 0.0 ? "" : "zero slide axis";
}
std::string needs_functions(const EndCondition& c) {
  return c.u_fixed && c.omega_fixed ? "" : "prescribed motion without functions";
}

// ---------------------------------------------------------------------------------------
// The table: one entry per EndType, in enumerator order.
// ---------------------------------------------------------------------------------------
using DynamicRows = void (*)(const EndCondition&, const RodProperties&, double, const EndValues&, const Mat3&,
                             const Mat3&, Vec6&, Jacobian6&);
using StaticRows = void (*)(const StaticModel&, const StaticEnd&, const StaticValues&, double, VecX&, MatX&);

struct EndKind {
  EndType type;
  DynamicRows rows;
  StaticRows static_rows;        ///< null: no static form (static_type reads it statically)
  EndType static_type;           ///< the type of its static reading
  bool moves;                    ///< the end point can move
  void (*convert)(const EndSpec&, EndCondition&);  ///< null: the parameters only
  std::string (*problem)(const EndCondition&);     ///< null: always well formed
  /// Statics: the position is held in full (`across` null) or across the axis `across`, or
  /// not at all (holds false); the end load of a continuation is the end force (free), the
  /// force along `load_axis` in row `load_row`, or none.
  bool holds = true;
  Vec3 EndSpec::*across = nullptr;
  bool end_force = false;
  Vec3 EndSpec::*load_axis = nullptr;
  int load_row = 0;
};

const std::vector<EndKind>& end_kinds() {
  using T = EndType;
  using S = EndSpec;
  static const std::vector<EndKind> kinds{
      {T::clamped, clamped_rows, clamped_static, T::clamped, false, nullptr, nullptr},
      {T::pinned, pinned_rows, pinned_static, T::pinned, false, nullptr, needs_axis},
      {T::sliding, sliding_rows, sliding_static, T::sliding, true, nullptr, needs_axis, true, &S::axis, false,
       &S::axis, 5},
      {T::roller, roller_rows, roller_static, T::roller, true, nullptr, needs_axes, true, &S::slide_axis, false,
       &S::slide_axis, 2},
      {T::free, free_rows, free_static, T::free, true, nullptr, nullptr, false, nullptr, true},
      {T::prescribed, prescribed_rows, nullptr, T::clamped, true, prescribed_motion, needs_functions},
  };
  return kinds;
}

// The entry of a type; throws std::logic_error(`unknown`) for a type without one.
const EndKind& kind_of(EndType t, const char* unknown) {
  const auto& kinds = end_kinds();
  const auto i = static_cast<std::size_t>(t);
  if (i >= kinds.size() || kinds[i].type != t) throw std::logic_error(unknown);
  return kinds[i];
}

}  // namespace

EndCondition EndCondition::make_clamped() { return EndCondition{}; }

EndCondition EndCondition::make_pinned(const Vec3& pin_axis) {
  EndCondition c;
  c.type = Type::pinned;
  c.axis = pin_axis;
  return c;
}

EndCondition EndCondition::make_sliding(const Vec3& slide_axis) {
  EndCondition c;
  c.type = Type::sliding;
  c.axis = slide_axis;
  return c;
}

EndCondition EndCondition::make_free() {
  EndCondition c;
  c.type = Type::free;
  return c;
}

EndCondition EndCondition::make_roller(const Vec3& pin_axis, const Vec3& slide_axis, double axial_force) {
  EndCondition c;
  c.type = Type::roller;
  c.axis = pin_axis;
  c.slide_axis = slide_axis;
  c.axial_force = axial_force;
  return c;
}

EndCondition EndCondition::make_prescribed(std::function<Vec3(double)> u_fixed,
                                           std::function<Vec3(double)> omega_fixed) {
  EndCondition c;
  c.type = Type::prescribed;
  c.u_fixed = std::move(u_fixed);
  c.omega_fixed = std::move(omega_fixed);
  return c;
}

int EndCondition::num_rows() const {
  kind_of(type, "EndCondition: unknown type");
  return 6;
}

EndType EndCondition::static_type() const { return kind_of(type, "EndCondition: unknown type").static_type; }

bool EndCondition::end_moves() const { return kind_of(type, "EndCondition: unknown type").moves; }

EndCondition end_condition(const EndSpec& spec) {
  const EndKind& k = kind_of(spec.type, "end_condition: unknown type");
  EndCondition c;
  static_cast<EndSpec&>(c) = spec;
  if (k.convert) k.convert(spec, c);
  return c;
}

StaticEnd static_end(const EndSpec& spec, const Vec3& position) {
  StaticEnd s;
  static_cast<EndSpec&>(s) = spec;
  s.type = kind_of(spec.type, "static_end: unknown type").static_type;  // prescribed motion starts from rest: clamped
  s.position = position;
  return s;
}

void end_condition_rows(const EndCondition& c, const RodProperties& props, double t, const Vec12& y, const Mat3& R,
                        const Mat3& G, Vec6& r, Jacobian6& J, const Vec3& kappa_t, double rate) {
  r.setZero();
  J.setZero();
  EndValues v{y.segment<3>(var::u), y.segment<3>(var::omega), y.segment<3>(var::n),
              props.moment(y.segment<3>(var::kappa)), props.K};
  if (props.B_bt != Vec3::Zero()) {  // the moment's viscous part B_bt kappa_t
    v.m += props.B_bt.cwiseProduct(kappa_t);
    v.dm += rate * props.B_bt;
  }
  kind_of(c.type, "end_condition_rows: unknown type").rows(c, props, t, v, R, G, r, J);
}

void static_end_rows(const StaticModel& m, const StaticEnd& c, const StaticNode& node, double sign, LocalBlock& b) {
  const EndKind& k = kind_of(c.type, "statics: unknown end condition type");
  if (!k.static_rows) throw std::invalid_argument("statics: a prescribed-motion end has no static form; use clamped");
  const Vec3 th = node.x.segment<3>(svar::theta);
  StaticValues v{node.x.segment<3>(svar::r), node.x.segment<3>(svar::kappa), node.x.segment<3>(svar::n),
                 node.frame(), frame_perturbation(th)};
  // The point forces' share of this end node acts on the end: the rows read n - sign R F.
  const Vec3 Fb = v.R * static_end_point_force(m, sign > 0.0);
  v.n -= sign * Fb;
  k.static_rows(m, c, v, sign, b.residual, b.jac[0]);
  if (Fb != Vec3::Zero()) b.jac[0].block<6, 3>(0, svar::theta) += sign * b.jac[0].block<6, 3>(0, svar::n) * hat(Fb) * v.D;
}

bool set_end_load(StaticEnd& e, double P, const Vec3& direction) {
  const EndKind& k = kind_of(e.type, "StaticProblem: unknown end condition type");
  if (!k.static_rows) return false;
  if (k.end_force) e.end_force = P * direction;
  else if (k.load_axis) e.axial_force = P * direction.dot((e.*k.load_axis).normalized());
  return true;
}

Vec6 end_load_derivative(const StaticEnd& e, const StaticNode& node, const Vec3& direction) {
  const EndKind& k = kind_of(e.type, "StaticProblem: unknown end condition type");
  Vec6 d = Vec6::Zero();
  if (k.end_force) d.head<3>() = -(node.frame() * direction);
  else if (k.load_axis) d(k.load_row) = -direction.dot((e.*k.load_axis).normalized());
  return d;
}

bool end_holds_position(const StaticEnd& e) { return kind_of(e.type, "StaticProblem: unknown end condition type").holds; }

Vec6 end_position_derivative(const StaticEnd& e, const Vec3& axis) {
  const EndKind& k = kind_of(e.type, "StaticProblem: unknown end condition type");
  Vec6 d = Vec6::Zero();
  if (!k.holds) return d;
  if (!k.across) {
    d.head<3>() = -axis;
  } else {
    Vec3 b1, b2;
    perpendicular_pair(e.*k.across, b1, b2);
    d(0) = -b1.dot(axis);
    d(1) = -b2.dot(axis);
  }
  return d;
}

namespace {
std::string check_one(const EndCondition& c, const RodProperties& props, const char* which) {
  const std::string w(which);
  if (c.num_rows() != 6) return w + " end: not 6 rows";
  const EndKind& k = kind_of(c.type, "EndCondition: unknown type");
  if (k.problem && !k.problem(c).empty()) return w + " end: " + k.problem(c);
  Vec6 r;
  Eigen::Matrix<double, 6, 12> J;
  end_condition_rows(c, props, 0.0, Vec12::Zero(), Mat3::Identity(), Mat3::Zero(), r, J);
  // Columns in power-conjugate form: kinematic (u, omega), dynamic (n, m = K kappa).
  Eigen::Matrix<double, 6, 6> Jk, Jd;
  Jk << J.block<6, 3>(0, var::u), J.block<6, 3>(0, var::omega);
  Vec3 kinv = props.K.cwiseInverse();
  Jd << J.block<6, 3>(0, var::n), J.block<6, 3>(0, var::kappa) * kinv.asDiagonal();
  Eigen::Matrix<double, 6, 12> Jp;
  Jp << Jk, Jd;
  Eigen::FullPivLU<Eigen::Matrix<double, 6, 12>> lu(Jp);
  lu.setThreshold(1e-10);
  if (lu.rank() != 6) return w + " end: the 6 rows are not independent";
  // Rows that fix only kinematic or only dynamic quantities: their spans must be
  // complementary and power-orthogonal (prescribed flux u.n + omega.m).
  Eigen::Matrix<double, 6, 6> K6 = Eigen::Matrix<double, 6, 6>::Zero(), D6 = K6;
  int nk = 0, nd = 0;
  for (int i = 0; i < 6; ++i) {
    const bool kin = Jd.row(i).norm() == 0.0, dyn = Jk.row(i).norm() == 0.0;
    if (kin) K6.row(nk++) = Jk.row(i);
    else if (dyn) D6.row(nd++) = Jd.row(i);
    else return "";  // mixed rows: rank check only
  }
  if (nk + nd == 6 && (K6.topRows(nk) * D6.topRows(nd).transpose()).norm() > 1e-12)
    return w + " end: kinematic and dynamic rows are not power-conjugate (flux not prescribed)";
  return "";
}
}  // namespace

EndConditionCheck validate_end_conditions(const EndCondition& left, const EndCondition& right) {
  EndConditionCheck out;
  const RodProperties props = RodProperties::circular(0.005, 2.5e8, 0.25, 1500.0);
  try {
    out.message = check_one(left, props, "left");
    if (out.message.empty()) out.message = check_one(right, props, "right");
  } catch (const std::exception& e) {
    out.message = e.what();
  }
  out.ok = out.message.empty();
  return out;
}

}  // namespace traverse::rod

#include "traverse/rod/end_condition.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>

#include "traverse/core/so3.hpp"
#include "traverse/rod/rod_state.hpp"

namespace traverse::rod {

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
  switch (type) {
    case Type::clamped:
    case Type::pinned:
    case Type::sliding:
    case Type::free:
    case Type::prescribed:
    case Type::roller:
      return 6;
    default:
      throw std::logic_error("EndCondition: unknown type");
  }
}

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

// Rows 3..5 of a pin about the fixed axis `axis`: omega perpendicular to it is zero (2) and
// there is no moment about it (1).
void pin_rows(const Vec3& axis, const RodProperties& props, const Vec3& w, const Vec3& m, const Mat3& R,
              const Mat3& G, Vec6& r, Eigen::Matrix<double, 6, 12>& J) {
  using so3::hat;
  Vec3 b1, b2;
  perpendicular_pair(axis, b1, b2);
  const Vec3 a = R * axis.normalized(), p1 = R * b1, p2 = R * b2;
  r(3) = w.dot(p1);
  r(4) = w.dot(p2);
  J.block<1, 3>(3, var::omega) = p1.transpose() + w.transpose() * hat(p1) * G;
  J.block<1, 3>(4, var::omega) = p2.transpose() + w.transpose() * hat(p2) * G;
  r(5) = m.dot(a);
  J.block<1, 3>(5, var::kappa) = a.cwiseProduct(props.K).transpose();
  J.block<1, 3>(5, var::omega) = m.transpose() * hat(a) * G;
}

// The rows of an end that slides along `axis`: no velocity across it (rows 0 and 1) and the
// contact force along it equal to `force` (row k), with their Jacobian.
void slide_rows(const Vec3& axis, double force, int k, const Vec3& u, const Vec3& n, const Mat3& R, const Mat3& G,
                Vec6& r, Eigen::Matrix<double, 6, 12>& J) {
  using so3::hat;
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

}  // namespace

void end_condition_rows(const EndCondition& c, const RodProperties& props, double t,
                        const Vec12& y, const Mat3& R, const Mat3& G, Vec6& r,
                        Eigen::Matrix<double, 6, 12>& J) {
  using so3::hat;
  r.setZero();
  J.setZero();
  const Vec3 u = y.segment<3>(var::u), w = y.segment<3>(var::omega);
  const Vec3 n = y.segment<3>(var::n);
  const Vec3 m = props.moment(y.segment<3>(var::kappa));
  const Mat3 I = Mat3::Identity();
  switch (c.type) {
    case EndCondition::Type::clamped:
      r.head<3>() = u;
      r.tail<3>() = w;
      J.block<3, 3>(0, var::u) = I;
      J.block<3, 3>(3, var::omega) = I;
      break;
    case EndCondition::Type::pinned: {
      r.head<3>() = u;
      J.block<3, 3>(0, var::u) = I;
      pin_rows(c.axis, props, w, m, R, G, r, J);
      break;
    }
    case EndCondition::Type::sliding:
      slide_rows(c.axis, 0.0, 5, u, n, R, G, r, J);
      r.segment<3>(2) = w;
      J.block<3, 3>(2, var::omega) = I;
      break;
    case EndCondition::Type::roller:
      slide_rows(c.slide_axis, c.axial_force, 2, u, n, R, G, r, J);
      pin_rows(c.axis, props, w, m, R, G, r, J);
      break;
    case EndCondition::Type::free:
      r.head<3>() = n;
      r.tail<3>() = m;
      J.block<3, 3>(0, var::n) = I;
      J.block<3, 3>(3, var::kappa) = props.K.asDiagonal();
      break;
    case EndCondition::Type::prescribed: {
      if (!c.u_fixed || !c.omega_fixed)
        throw std::invalid_argument("prescribed end condition without functions");
      const Vec3 ub = R * c.u_fixed(t), wb = R * c.omega_fixed(t);
      r.head<3>() = u - ub;
      r.tail<3>() = w - wb;
      J.block<3, 3>(0, var::u) = I;
      J.block<3, 3>(0, var::omega) = -hat(ub) * G;
      J.block<3, 3>(3, var::omega) = I - hat(wb) * G;
      break;
    }
    default:
      throw std::logic_error("end_condition_rows: unknown type");
  }
}

namespace {
std::string check_one(const EndCondition& c, const RodProperties& props, const char* which) {
  const std::string w(which);
  if (c.num_rows() != 6) return w + " end: not 6 rows";
  if ((c.type == EndCondition::Type::pinned || c.type == EndCondition::Type::sliding ||
       c.type == EndCondition::Type::roller) &&
      !(c.axis.norm() > 0.0))
    return w + " end: zero axis";
  if (c.type == EndCondition::Type::roller && !(c.slide_axis.norm() > 0.0))
    return w + " end: zero slide axis";
  if (c.type == EndCondition::Type::prescribed && (!c.u_fixed || !c.omega_fixed))
    return w + " end: prescribed motion without functions";
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

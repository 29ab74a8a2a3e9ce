#include "traverse/core/so3.hpp"

#include <algorithm>
#include <cmath>

namespace traverse::so3 {

Mat3 hat(const Vec3& v) {
  Mat3 h;
  h << 0.0, -v.z(), v.y(),
       v.z(), 0.0, -v.x(),
       -v.y(), v.x(), 0.0;
  return h;
}

Vec3 vee(const Mat3& a) {
  return Vec3(a(2, 1) - a(1, 2), a(0, 2) - a(2, 0), a(1, 0) - a(0, 1)) * 0.5;
}

namespace {
// Coefficients sin(t)/t, (1-cos t)/t^2 and (t - sin t)/t^3 with series near t = 0.
struct ExpCoefficients {
  double a, b, c;
};
ExpCoefficients coefficients(double t) {
  const double t2 = t * t;
  if (t < 1e-4) {
    return {1.0 - t2 / 6.0 * (1.0 - t2 / 20.0), 0.5 - t2 / 24.0 * (1.0 - t2 / 30.0),
            1.0 / 6.0 - t2 / 120.0 * (1.0 - t2 / 42.0)};
  }
  const double s = std::sin(t), c = std::cos(t);
  return {s / t, (1.0 - c) / t2, (t - s) / (t2 * t)};
}
}  // namespace

Mat3 exp(const Vec3& x) {
  const auto k = coefficients(x.norm());
  const Mat3 h = hat(x);
  return Mat3::Identity() + k.a * h + k.b * h * h;
}

Mat3 right_jacobian(const Vec3& x) {
  const auto k = coefficients(x.norm());
  const Mat3 h = hat(x);
  return Mat3::Identity() - k.b * h + k.c * h * h;
}

Mat3 left_jacobian(const Vec3& x) {
  const auto k = coefficients(x.norm());
  const Mat3 h = hat(x);
  return Mat3::Identity() + k.b * h + k.c * h * h;
}

Vec3 log(const Mat3& r) {
  const double cos_t = std::clamp((r.trace() - 1.0) * 0.5, -1.0, 1.0);
  const double t = std::acos(cos_t);
  const Vec3 w = vee(r);  // = sin(t) e
  if (t < 1e-6) return w * (1.0 + t * t / 6.0);
  if (constants::pi - t > 1e-6) return w * (t / std::sin(t));
  // Near pi: e e^T = (R + I) / 2 on the symmetric part; take the largest column.
  // R = cos t I + (1 - cos t) e e^T + sin t hat(e): the symmetric part gives e e^T.
  const Mat3 ee = (0.5 * (r + r.transpose()) - cos_t * Mat3::Identity()) / (1.0 - cos_t);
  Eigen::Index i = 0;
  ee.diagonal().maxCoeff(&i);
  Vec3 e = ee.col(i) / std::sqrt(ee(i, i));
  if (e.dot(w) < 0.0) e = -e;
  return e * t;
}

double orthonormality_defect(const Mat3& r) {
  return (r * r.transpose() - Mat3::Identity()).cwiseAbs().maxCoeff();
}

}  // namespace traverse::so3

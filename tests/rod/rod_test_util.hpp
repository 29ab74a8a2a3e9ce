#pragma once
// Shared helpers of the rod tests: random states and central-difference Jacobians.
#include <functional>
#include <random>

#include "traverse/core/so3.hpp"
#include "traverse/rod/rod_kernels.hpp"

namespace traverse::rod::test {

inline RodModel scene_model(int N, const AlphaParameters& alpha = AlphaParameters{}) {
  RodModel m;
  m.props = RodProperties::scene_rod();
  m.alpha = alpha;
  m.num_cells = N;
  m.length = 1.0;
  m.left = EndCondition::make_clamped();
  m.right = EndCondition::make_clamped();
  return m;
}

struct Rng {
  std::mt19937 gen{12345};
  double uniform(double a = -1.0, double b = 1.0) {
    return std::uniform_real_distribution<double>(a, b)(gen);
  }
  Vec3 vec3(double scale) { return Vec3(uniform(), uniform(), uniform()) * scale; }
  Vec12 y(double su = 0.3, double sw = 2.0, double sk = 3.0, double sn = 5.0) {
    Vec12 v;
    v << vec3(su), vec3(sw), vec3(sk), vec3(sn);
    return v;
  }
  Mat3 rotation() { return so3::exp(vec3(2.0)); }
  RodNode node() {
    RodNode n;
    n.y = y();
    n.R = rotation();
    n.yt = y(3.0, 20.0, 30.0, 50.0);
    n.ys = y(3.0, 20.0, 30.0, 50.0);
    n.kst = vec3(30.0);
    return n;
  }
  VecX unknowns(const RodModel& m, const RodNode& old) {
    VecX x = node_unknowns(m, old);
    Vec12 d = y(0.05, 0.5, 0.5, 1.0);
    x.head<12>() += d;
    if (m.carries_ys()) x.tail<12>() += y(1.0, 5.0, 5.0, 10.0);
    return x;
  }
};

/// Central-difference Jacobian of f with respect to x; step h (1 + |x_k|).
inline MatX central_jacobian(const std::function<VecX(const VecX&)>& f, const VecX& x,
                             double h = 1e-6) {
  const VecX f0 = f(x);
  MatX J(f0.size(), x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    const double e = h * (1.0 + std::abs(x(k)));
    VecX xp = x, xm = x;
    xp(k) += e;
    xm(k) -= e;
    J.col(k) = (f(xp) - f(xm)) / (2.0 * e);
  }
  return J;
}

/// max |A - B| / max(|B|) (a relative error that ignores the zero pattern).
inline double relative_difference(const MatX& A, const MatX& B) {
  const double s = std::max(B.cwiseAbs().maxCoeff(), 1e-300);
  return (A - B).cwiseAbs().maxCoeff() / s;
}

}  // namespace traverse::rod::test

#include <gtest/gtest.h>

#include <random>

#include "traverse/core/so3.hpp"

using namespace traverse;

namespace {
Vec3 random_vec(std::mt19937& g, double scale) {
  std::uniform_real_distribution<double> d(-scale, scale);
  return Vec3(d(g), d(g), d(g));
}
}  // namespace

TEST(So3, HatIsCrossProduct) {
  std::mt19937 g(1);
  for (int k = 0; k < 10; ++k) {
    const Vec3 a = random_vec(g, 2.0), b = random_vec(g, 2.0);
    EXPECT_LT((so3::hat(a) * b - a.cross(b)).norm(), 1e-14);
    EXPECT_LT((so3::vee(so3::hat(a)) - a).norm(), 1e-15);
  }
}

TEST(So3, RodriguesMatchesSeriesAndIsOrthonormal) {
  std::mt19937 g(2);
  for (double scale : {1e-9, 1e-5, 1e-3, 0.3, 2.0, 3.0}) {
    const Vec3 x = random_vec(g, scale);
    // Truncated power series of exp(hat(x)), enough terms for |x| <= 3*sqrt(3).
    Mat3 series = Mat3::Identity(), term = Mat3::Identity();
    for (int n = 1; n < 40; ++n) {
      term = term * so3::hat(x) / n;
      series += term;
    }
    const Mat3 r = so3::exp(x);
    EXPECT_LT((r - series).cwiseAbs().maxCoeff(), 1e-14) << "|x| = " << x.norm();
    EXPECT_LT(so3::orthonormality_defect(r), 1e-15);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-14);
  }
}

TEST(So3, LogInvertsExp) {
  std::mt19937 g(3);
  for (double scale : {1e-8, 1e-3, 0.5, 1.5}) {
    const Vec3 x = random_vec(g, scale);
    EXPECT_LT((so3::log(so3::exp(x)) - x).norm(), 1e-12 * std::max(1.0, x.norm()));
  }
  const Vec3 near_pi = Vec3(0.2, -0.5, 0.8).normalized() * (constants::pi - 1e-9);
  EXPECT_LT((so3::log(so3::exp(near_pi)) - near_pi).norm(), 1e-6);
}

TEST(So3, JacobiansMatchFiniteDifferences) {
  std::mt19937 g(4);
  for (double scale : {1e-6, 0.1, 1.0, 2.5}) {
    const Vec3 x = random_vec(g, scale);
    const Mat3 r = so3::exp(x);
    const Mat3 jr = so3::right_jacobian(x), jl = so3::left_jacobian(x);
    const double h = 1e-6;
    for (int c = 0; c < 3; ++c) {
      const Vec3 e = Vec3::Unit(c);
      const Mat3 dr = (so3::exp(x + h * e) - so3::exp(x - h * e)) / (2 * h);
      EXPECT_LT((dr - r * so3::hat(jr * e)).cwiseAbs().maxCoeff(), 1e-8);
      EXPECT_LT((dr - so3::hat(jl * e) * r).cwiseAbs().maxCoeff(), 1e-8);
    }
  }
}

// Mode shapes of uniform beams and Galerkin matrices: roots, boundary conditions,
// normalisation, orthogonality and the eigenvalue equation up to n = 30.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "traverse/beam/galerkin.hpp"
#include "traverse/beam/gauss_legendre.hpp"
#include "traverse/beam/uniform_modes.hpp"

using namespace traverse;
using namespace traverse::beam;

namespace {
const Support kSupports[] = {Support::SimplySupported, Support::ClampedFree,
                             Support::ClampedClamped, Support::ClampedPinned};
constexpr int kN = 30;

// Independent statements of the characteristic equations, divided by cosh(l) (or cos l
// cosh l form) so that a root gives O(eps) residual instead of O(eps e^l).
double char_eq(Support s, double l) {
  const double ch = std::cosh(l);
  switch (s) {
    case Support::SimplySupported: return std::sin(l);
    case Support::ClampedFree: return (std::cos(l) * ch + 1.0) / ch;
    case Support::ClampedClamped: return (std::cos(l) * ch - 1.0) / ch;
    case Support::ClampedPinned: return (std::tan(l) - std::tanh(l)) * std::cos(l);
    default: throw std::invalid_argument("support");
  }
}
}  // namespace

TEST(BeamModes, GaussLegendreIsExactToDegree2nMinus1) {
  double worst = 0;
  for (int n = 1; n <= 20; ++n) {
    const GaussLegendre g(n);
    for (int k = 0; k <= 2 * n - 1; ++k) {
      double s = 0;
      for (int q = 0; q < n; ++q) s += g.weights[q] * std::pow(g.points[q], k);
      const double exact = (k % 2 == 1) ? 0.0 : 2.0 / (k + 1);
      worst = std::max(worst, std::abs(s - exact));
    }
  }
  std::cout << "max |quadrature error| of x^k, k <= 2n-1, n <= 20: " << worst << "\n";
  EXPECT_LT(worst, 1e-13);
}

TEST(BeamModes, RootsSatisfyCharacteristicEquations) {
  for (Support s : kSupports) {
    double worst = 0;
    for (int i = 1; i <= kN; ++i) {
      const double l = UniformModes::root(s, i);
      // residual relative to the slope |f'| ~ 1 of the scaled function: error in lambda
      worst = std::max(worst, std::abs(char_eq(s, l)) / std::max(1.0, l));
      // roots are increasing and simple (one per bracket of width pi)
      if (i > 1) {
        EXPECT_GT(l - UniformModes::root(s, i - 1), 2.5);
      }
    }
    std::cout << to_string(s) << ": max |char(lambda_i)|/lambda_i over i <= 30 = " << worst
              << ", lambda_30 = " << UniformModes::root(s, kN) << "\n";
    EXPECT_LT(worst, 1e-15) << to_string(s);
  }
  // Published values (Blevins): cantilever, clamped-clamped, clamped-pinned.
  const double cf[] = {1.87510407, 4.69409113, 7.85475744, 10.99554073};
  const double cc[] = {4.73004074, 7.85320462, 10.9956078, 14.1371655};
  const double cp[] = {3.92660231, 7.06858275, 10.21017612, 13.35176878};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(UniformModes::root(Support::ClampedFree, i + 1), cf[i], 1e-7);
    EXPECT_NEAR(UniformModes::root(Support::ClampedClamped, i + 1), cc[i], 1e-6);
    EXPECT_NEAR(UniformModes::root(Support::ClampedPinned, i + 1), cp[i], 1e-7);
  }
}

TEST(BeamModes, BoundaryConditionsAndNormalisation) {
  const double L = 1.7;
  for (Support s : kSupports) {
    const UniformModes m(s, kN, L, 2.0, 3.0);
    const VecX b = m.betas();
    VecX p(kN), d1(kN), d2(kN), d3(kN);
    // Residuals scaled to O(1): k-th derivative divided by beta^k.
    auto scaled = [&](const VecX& v, int k) { return (v.array() / b.array().pow(k)).abs().maxCoeff(); };
    double bc = 0;
    for (double x : {0.0, L}) {
      m.evaluate(x, p, d1, d2);
      m.third_derivative(x, d3);
      const bool left = (x == 0.0);
      double r = 0;
      switch (s) {
        case Support::SimplySupported: r = std::max(scaled(p, 0), scaled(d2, 2)); break;
        case Support::ClampedFree:
          r = left ? std::max(scaled(p, 0), scaled(d1, 1)) : std::max(scaled(d2, 2), scaled(d3, 3));
          break;
        case Support::ClampedClamped: r = std::max(scaled(p, 0), scaled(d1, 1)); break;
        case Support::ClampedPinned:
          r = left ? std::max(scaled(p, 0), scaled(d1, 1)) : std::max(scaled(p, 0), scaled(d2, 2));
          break;
        default: throw std::invalid_argument("support");
      }
      bc = std::max(bc, r);
    }
    // Normalisation: sample |Phi| densely.
    double maxdev = 0, tipdev = 0;
    VecX mx = VecX::Zero(kN);
    const int M = 20000;
    for (int j = 0; j <= M; ++j) {
      m.evaluate(L * j / M, p, d1, d2);
      mx = mx.cwiseMax(p.cwiseAbs());
    }
    if (s == Support::ClampedFree) {
      m.evaluate(L, p, d1, d2);
      tipdev = (p.array() - 1.0).abs().maxCoeff();
      EXPECT_LT(tipdev, 1e-12);
    } else {
      maxdev = (mx.array() - 1.0).abs().maxCoeff();
      EXPECT_LT((mx.array() - 1.0).maxCoeff(), 1e-12);  // never above 1
      EXPECT_LT(maxdev, 2e-4);  // sampled max within the sampling resolution of 1
      // sign convention
      m.evaluate(0.0, p, d1, d2);
      for (int i = 0; i < kN; ++i) EXPECT_GT(s == Support::SimplySupported ? d1(i) : d2(i), 0.0);
    }
    std::cout << to_string(s) << ": max scaled BC residual (n <= 30) = " << bc
              << ", tip |Phi(L)-1| = " << tipdev << ", max_x|Phi| deviation from 1 (sampled) = "
              << maxdev << "\n";
    EXPECT_LT(bc, 1e-12) << to_string(s);
  }
}

TEST(BeamModes, StableFormMatchesTextbookFormForLowModes) {
  // Textbook cantilever mode in long double (cancellation costs ~e^lambda * 1e-19, i.e.
  // < 1e-13 for modes 1..5), normalised to tip = 1.
  const double L = 2.0;
  const UniformModes m(Support::ClampedFree, 5, L, 1.0, 1.0);
  VecX p(5), d1(5), d2(5);
  double worst = 0;
  for (int i = 0; i < 5; ++i) {
    const long double l = m.lambdas()[i];
    const long double si = (std::cosh(l) + std::cos(l)) / (std::sinh(l) + std::sin(l));
    auto tb = [&](long double xi) {
      return std::cosh(l * xi) - std::cos(l * xi) - si * (std::sinh(l * xi) - std::sin(l * xi));
    };
    for (int j = 0; j <= 50; ++j) {
      const double xi = j / 50.0;
      m.evaluate(xi * L, p, d1, d2);
      worst = std::max(worst, static_cast<double>(std::abs(p(i) - tb(xi) / tb(1.0L))));
    }
  }
  std::cout << "cantilever modes 1..5: max |stable - textbook| = " << worst << "\n";
  EXPECT_LT(worst, 1e-13);
}

TEST(BeamModes, OrthogonalityAndEigenvalueEquation) {
  const double L = 1.7, EI = 2.0, rhoA = 3.0;
  const auto nodes = uniform_nodes(L, 200);
  for (Support s : kSupports) {
    const UniformModes m(s, kN, L, EI, rhoA);
    const GalerkinMatrices g = assemble_galerkin(
        m, nodes, [&](double) { return rhoA; }, [&](double) { return EI; }, 9.8, 10);
    double offM = 0, offK = 0, eig = 0;
    const VecX b = m.betas();
    for (int i = 0; i < kN; ++i) {
      for (int j = 0; j < kN; ++j) {
        if (i == j) continue;
        offM = std::max(offM, std::abs(g.Mb(i, j)) / std::sqrt(g.Mb(i, i) * g.Mb(j, j)));
        offK = std::max(offK, std::abs(g.Kb(i, j)) / std::sqrt(g.Kb(i, i) * g.Kb(j, j)));
      }
      const double expect = std::pow(b(i), 4) * EI / rhoA;
      eig = std::max(eig, std::abs(g.Kb(i, i) / g.Mb(i, i) / expect - 1.0));
    }
    const VecX w = m.circular_frequencies();
    std::cout << to_string(s) << " (n = 30, 200 elements x 10 Gauss points): max offdiag/diag Mb = "
              << offM << ", Kb = " << offK << ", max rel |Kb_ii/Mb_ii - beta^4 EI/rhoA| = " << eig
              << ", omega_30/omega_1 = " << w(kN - 1) / w(0) << "\n";
    EXPECT_LT(offM, 1e-10);
    EXPECT_LT(offK, 1e-10);
    EXPECT_LT(eig, 1e-10);
    for (int i = 0; i < kN; ++i) EXPECT_NEAR(w(i) * w(i), std::pow(b(i), 4) * EI / rhoA, 1e-12 * w(i) * w(i));
  }
}

TEST(BeamModes, CantileverSceneFirstFrequency) {
  // Spec: hollow steel tube, L = 2 m, r = 0.1/0.05 m: omega_1 about 248 rad/s. Closed form:
  // omega_k = (beta_k L)^2 sqrt(EI / (rho A L^4)), beta_k L the k-th root of 1 + cos x cosh x = 0,
  // found here by bisection in the bracket [(k - 1/2) pi, k pi] (k = 1) resp. [(k - 1) pi, k pi].
  const double ro = 0.1, ri = 0.05, E = 2.0e11, rho = 7850, L = 2.0;
  const double A = constants::pi * (ro * ro - ri * ri), I = constants::pi / 4 * (std::pow(ro, 4) - std::pow(ri, 4));
  const UniformModes m(Support::ClampedFree, 3, L, E * I, rho * A);
  const VecX w = m.circular_frequencies();
  std::cout << "cantilever scene omega_1..3 = " << w.transpose() << " rad/s\n";
  for (int k = 1; k <= 3; ++k) {
    double lo = (k == 1 ? 0.5 : k - 1.0) * constants::pi, hi = k * constants::pi;
    const double f_lo = char_eq(Support::ClampedFree, lo);
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      if ((char_eq(Support::ClampedFree, mid) > 0.0) == (f_lo > 0.0)) lo = mid;
      else hi = mid;
    }
    const double bl = 0.5 * (lo + hi);
    const double exact = bl * bl * std::sqrt(E * I / (rho * A * std::pow(L, 4)));
    EXPECT_NEAR(w(k - 1), exact, 1e-12 * exact) << "mode " << k;
  }
  EXPECT_NEAR(w(0), 248.0, 1.0);  // the figure the scene's description quotes
}

#pragma once
// Gauss-Legendre quadrature rules.
#include <vector>

namespace traverse::beam {

/// n-point Gauss-Legendre rule on [-1, 1] (exact for polynomials of degree 2n - 1).
/// Nodes by Newton iteration on P_n from the asymptotic guesses, to machine precision.
struct GaussLegendre {
  std::vector<double> points;
  std::vector<double> weights;
  explicit GaussLegendre(int n);
};

}  // namespace traverse::beam

#include "traverse/beam/gauss_legendre.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "traverse/core/types.hpp"

namespace traverse::beam {

GaussLegendre::GaussLegendre(int n) {
  if (n < 1) throw std::invalid_argument("GaussLegendre: need n >= 1");
  points.resize(static_cast<std::size_t>(n));
  weights.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double x = std::cos(constants::pi * (i + 0.75) / (n + 0.5));
    double dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      // Three-term recurrence for P_n(x) and its derivative.
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      const double pn = (n == 1) ? x : p1, pm = (n == 1) ? 1.0 : p0;
      dp = n * (x * pn - pm) / (x * x - 1.0);
      const double dx = pn / dp;
      x -= dx;
      if (std::abs(dx) <= 2.0 * std::numeric_limits<double>::epsilon()) break;
    }
    // Recompute the derivative at the converged node for the weight.
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= n; ++k) {
      const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    dp = (n == 1) ? 1.0 : n * (x * p1 - p0) / (x * x - 1.0);
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    const std::size_t a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(n - 1 - i);
    points[a] = -x;
    points[b] = x;
    weights[a] = w;
    weights[b] = w;
  }
  if (n % 2 == 1) points[static_cast<std::size_t>(n / 2)] = 0.0;
}

}  // namespace traverse::beam

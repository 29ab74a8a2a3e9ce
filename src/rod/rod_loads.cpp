#include "traverse/rod/rod_loads.hpp"

#include <algorithm>
#include <cmath>

namespace traverse::rod {

PointLoadWeights point_load_weights(double sigma, int num_cells, double ds, double beta) {
  PointLoadWeights w;
  const int N = num_cells;
  const double L = N * ds;
  const double tol = 1e-12 * L;
  if (!(sigma >= -tol && sigma <= L + tol)) return w;  // off the rod (or NaN)
  const double x = std::clamp(sigma / ds, 0.0, static_cast<double>(N));
  int k = static_cast<int>(std::floor(x)) + 1;
  k = std::clamp(k, 1, N);
  const double xi = std::clamp(x - (k - 1), 0.0, 1.0);
  auto E = [&](int j) { return j == 0 ? beta : (j == N ? 1.0 - beta : 1.0); };
  const double e0 = E(k - 1), e1 = E(k);
  double w0 = 1.0 - xi, w1 = xi;
  if (e0 == 0.0) { w0 = 0.0; w1 = 1.0; }
  if (e1 == 0.0) { w1 = 0.0; w0 = 1.0; }
  w.count = 2;
  w.node = {k - 1, k};
  w.weight = {e0 == 0.0 ? 0.0 : w0 / e0, e1 == 0.0 ? 0.0 : w1 / e1};
  return w;
}

}  // namespace traverse::rod

#include "traverse/rod/alpha_parameters.hpp"

#include <stdexcept>

namespace traverse::rod {

namespace {
struct Triple {
  double alpha_m, alpha_f, gamma;
};
Triple chung_hulbert_first_order(double rho) {
  if (!(rho >= 0.0 && rho <= 1.0)) throw std::invalid_argument("rho_inf must lie in [0, 1]");
  const double am = (3.0 - rho) / (2.0 * (1.0 + rho));
  const double af = 1.0 / (1.0 + rho);
  return {am, af, 0.5 + am - af};
}
}  // namespace

AlphaParameters AlphaParameters::from_rho_inf(double rho_t, double rho_s) {
  const Triple t = chung_hulbert_first_order(rho_t);
  const Triple s = chung_hulbert_first_order(rho_s);
  AlphaParameters p;
  p.at = 1.0 - t.alpha_m;
  p.bt = 1.0 - t.alpha_f;
  p.gt = t.gamma;
  p.bs = 1.0 - s.alpha_m;
  p.as = 1.0 - s.alpha_f;
  p.gs = s.gamma;
  return p;
}

}  // namespace traverse::rod

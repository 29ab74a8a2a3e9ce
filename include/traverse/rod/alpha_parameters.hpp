#pragma once
// Parameters (as, bs, gs, at, bt, gt) of the generalised-alpha space-time scheme
// (docs/rod.md, "Equations" and "Discretisation").
namespace traverse::rod {

struct AlphaParameters {
  double as = 0.5, bs = 0.5, gs = 0.5;  ///< space: weight of yt at node j-1, of ys/F at j-1, recursion
  double at = 0.5, bt = 0.5, gt = 0.5;  ///< time: weight of yt at level i-1, of ys/F at i-1, recursion

  /// Chung-Hulbert style mapping for first-order systems (Jansen, Whiting & Hulbert 2000):
  /// alpha_m = (3 - rho)/(2 (1 + rho)), alpha_f = 1/(1 + rho), gamma = 1/2 + alpha_m - alpha_f.
  /// Time:  at = 1 - alpha_m(rho_t), bt = 1 - alpha_f(rho_t), gt = gamma(rho_t)
  ///        (the derivative term Mm yt carries alpha_m, Kk ys and F carry alpha_f).
  /// Space: bs = 1 - alpha_m(rho_s), as = 1 - alpha_f(rho_s), gs = gamma(rho_s)
  ///        (the derivative term Kk ys carries alpha_m; F shares its weight, as docs/rod.md writes).
  /// rho = 1 gives all 1/2. rho_t, rho_s in [0, 1]; throws otherwise.
  static AlphaParameters from_rho_inf(double rho_t, double rho_s = 1.0);

  /// True when the ys history drops out (gs = bs = 1/2): plain box scheme in s, 12 unknowns
  /// per node. Otherwise ys is carried as 12 extra unknowns per node.
  bool box_in_space() const { return gs == 0.5 && bs == 0.5; }
};

}  // namespace traverse::rod

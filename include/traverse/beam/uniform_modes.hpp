#pragma once
// Closed-form bending modes of a uniform Euler-Bernoulli beam, evaluated stably for high modes.
#include <array>
#include <vector>

#include "traverse/beam/mode_set.hpp"

namespace traverse::beam {

/// End conditions; the first word is the end x = 0, the second the end x = L.
enum class Support {
  SimplySupported,  ///< pinned-pinned: w = w'' = 0 at both ends
  ClampedFree,      ///< cantilever: w = w' = 0 at x = 0; w'' = w''' = 0 at x = L
  ClampedClamped,   ///< w = w' = 0 at both ends
  ClampedPinned     ///< w = w' = 0 at x = 0; w = w'' = 0 at x = L
};

const char* to_string(Support s);

/// Modes of a uniform beam (E I, rho A constant): Phi_i'''' = beta_i^4 Phi_i,
/// omega_i = beta_i^2 sqrt(EI / rhoA).
///
/// Stable form: with xi = x / L and lambda_i = beta_i L every mode is stored as
///     Phi_i = A cos(lambda xi) + B sin(lambda xi) + C e^{-lambda xi} + D e^{-lambda (1 - xi)},
/// where all four terms are bounded by their coefficient on [0, L] (the textbook cosh/sinh
/// form cancels terms of size e^{lambda}, losing every digit near mode 30). The coefficients
/// are the null vector of the 4x4 end-condition matrix in this basis (well conditioned).
///
/// Normalisation and sign convention:
///   - ClampedFree: Phi_i(L) = +1 (tip value one, tip deflects up for positive Y_i);
///   - otherwise: max_x |Phi_i(x)| = 1 (maximum found numerically: sampling plus safeguarded
///     Newton on Phi_i' = 0), with sign fixed by Phi_i'(0) > 0 (SimplySupported: Phi_i =
///     sin(i pi x / L)) or Phi_i''(0) > 0 (clamped at x = 0).
class UniformModes final : public ModeSet {
 public:
  /// @param support end conditions; @param n number of modes (>= 1);
  /// @param length L [m]; @param EI bending stiffness [N m^2]; @param rhoA mass per length [kg/m]
  UniformModes(Support support, int n, double length, double EI, double rhoA);

  Eigen::Index size() const override { return static_cast<Eigen::Index>(lambda_.size()); }
  double length() const override { return length_; }
  VecX circular_frequencies() const override;
  void evaluate(double x, Eigen::Ref<VecX> phi, Eigen::Ref<VecX> dphi,
                Eigen::Ref<VecX> ddphi) const override;
  /// Third derivative Phi_i''' [1/m^3] (shear; used to check free-end conditions).
  void third_derivative(double x, Eigen::Ref<VecX> dddphi) const;

  Support support() const { return support_; }
  /// Dimensionless roots lambda_i = beta_i L, i = 0..n-1 (mode i+1).
  const std::vector<double>& lambdas() const { return lambda_; }
  /// Wave numbers beta_i [1/m].
  VecX betas() const;
  /// Stable-form coefficients (A, B, C, D) of mode i (0-based), after normalisation.
  const std::array<double, 4>& coefficients(int i) const { return coef_[static_cast<std::size_t>(i)]; }

  /// lambda_i = beta_i L of mode i (1-based) for the given support, solved to machine precision
  /// by safeguarded Newton iteration on the scaled characteristic function inside a bracket
  /// that provably holds exactly one root.
  static double root(Support support, int i);
  /// Characteristic function scaled to O(1) (divided by cosh lambda where needed):
  ///   SimplySupported: sin(l); ClampedFree: cos(l) + 1/cosh(l);
  ///   ClampedClamped: cos(l) - 1/cosh(l); ClampedPinned: sin(l) - cos(l) tanh(l).
  static double characteristic(Support support, double lambda);

 private:
  Support support_;
  double length_;
  double EI_, rhoA_;
  std::vector<double> lambda_;
  std::vector<std::array<double, 4>> coef_;
};

}  // namespace traverse::beam

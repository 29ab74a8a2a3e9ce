#pragma once
// Structural damping of the beam in its own modes (docs/beam.md).
#include <vector>

#include "traverse/beam/galerkin.hpp"

namespace traverse::beam {

/// How the beam's structural damping is given (plain data).
///   Ratios:   the modal equation q_i'' + 2 zeta_i omega_i q_i' + omega_i^2 q_i = Q_i / m_i, that is
///             the damping matrix C = diag(2 zeta_i omega_i m_i), m_i = Mb_ii, omega_i^2 = Kb_ii / m_i;
///             one ratio applies to every mode, otherwise one per mode.
///   Rayleigh: C = a Mb + b Kb, so zeta_i = a / (2 omega_i) + b omega_i / 2.
struct ModalDamping {
  enum class Kind { None, Ratios, Rayleigh };
  Kind kind = Kind::None;
  std::vector<double> ratios;  ///< zeta_i [-] (one value, or one per mode)
  double mass = 0.0;           ///< Rayleigh a [1/s]
  double stiffness = 0.0;      ///< Rayleigh b [s]
  bool active() const { return kind != Kind::None; }
};

/// The damping matrix C [N s/m per modal coordinate] of the modal equations Mb Y'' + C Y' + Kb Y = Q.
/// Throws std::invalid_argument for a ratio list whose length is neither 1 nor the number of modes,
/// or for negative ratios or coefficients.
MatX modal_damping_matrix(const GalerkinMatrices& m, const ModalDamping& d);

/// The damping ratio of mode i (0-based) implied by d, for the modal matrices m.
double modal_damping_ratio(const GalerkinMatrices& m, const ModalDamping& d, Eigen::Index i);

}  // namespace traverse::beam

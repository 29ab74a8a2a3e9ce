#pragma once
// Abstract set of transverse mode shapes Phi_i(x), i = 1..n, of a beam of length L.
#include "traverse/core/types.hpp"

namespace traverse::beam {

/// A set of n transverse mode shapes on [0, L] used as Galerkin trial functions.
///
/// Implementations: UniformModes (closed-form modes of uniform beams). A non-uniform
/// (tapered) beam can supply numerically computed modes through the same interface; the
/// Galerkin assembly and the time integrators only use this interface.
class ModeSet {
 public:
  virtual ~ModeSet() = default;

  /// Number of modes n.
  virtual Eigen::Index size() const = 0;
  /// Beam length L [m].
  virtual double length() const = 0;
  /// Natural circular frequencies omega_i [rad/s] of the beam the modes belong to (n values,
  /// increasing).
  virtual VecX circular_frequencies() const = 0;
  /// Phi_i(x) [-], Phi_i'(x) [1/m], Phi_i''(x) [1/m^2] for all modes at one position x [m].
  /// The three outputs must already have size n; no allocation happens here.
  virtual void evaluate(double x, Eigen::Ref<VecX> phi, Eigen::Ref<VecX> dphi,
                        Eigen::Ref<VecX> ddphi) const = 0;
};

}  // namespace traverse::beam

#pragma once
// Load stepping for the static form (rod/static_kernels.hpp): the equilibrium under a model's
// loads reached from the equilibrium under no load by scaling gravity, the point forces and
// the end forces with a load factor from 0 to 1, each step one Newton solve. The Newton solve
// is given: NOX over the ranks for the initial states of dynamic runs
// (solver/static_start.hpp), or the tests' serial reference on the whole rod. Also the
// convergence test both use: max |r| <= ftol * (force scale) and the scaled update <= rtol.
#include <array>
#include <functional>
#include <string>

#include "traverse/rod/static_kernels.hpp"

namespace traverse::rod {

struct StaticReport {
  bool converged = false;
  int iterations = 0;        ///< Newton iterations in all
  int load_steps = 0;        ///< accepted load steps
  double residual_norm = 0;  ///< max |r| at the returned state (one solve: where it stopped)
  double load_scale = 0;     ///< the force scale of the convergence test [N] (ftol * load_scale)
  std::string message;       ///< why it failed (empty when converged)
  // solve_with_load_steps:
  double load_factor = 0;      ///< the largest load factor reached (1 when converged)
  double failed_factor = 0;    ///< the load factor of the last failed Newton solve (0: none failed)
  double failed_residual = 0;  ///< max |r| where that solve stopped
  double failed_scale = 0;     ///< its force scale [N]
  std::string failed_reason;   ///< why it failed
};

/// The convergence test of a static Newton solve at one load factor, and the limits.
struct StaticTolerances {
  double rtol = 1e-12;     ///< converged when the scaled update (static_update_scales) <= rtol ...
  double ftol = 1e-9;      ///< ... and max |r| <= ftol * static_force_scale
  int max_iterations = 30;
  int max_load_steps = 200;
};

/// Newton at fixed loads from the current state: `m` holds the (scaled) loads. On success the
/// state is the equilibrium with its frames rebased; on failure it is the state before the
/// solve. The report's converged, iterations, residual_norm, load_scale and message are used.
using StaticNewton = std::function<StaticReport(const StaticModel& m)>;

/// Equilibrium under `m`'s loads from the state `newton` works on (equilibrium under no load):
/// the load factor goes from 0 to 1, first in one step, halving the increment after a failed
/// solve and doubling it after a solve of at most 6 iterations (quadratic convergence to the
/// tight tolerances from a near guess). Fails after max_load_steps accepted steps or when the
/// increment falls below 1e-8.
StaticReport solve_with_load_steps(const StaticModel& m, const StaticNewton& newton,
                                   const StaticTolerances& tol = {});

/// The scales of the update test per kind of unknown, r, theta, kappa, n: the scaled update is
/// max(|dr| / L, |dtheta|, |dkappa| L, |dn| / fscale), i.e. |d| divided by (L, 1, 1/L, fscale).
std::array<double, 4> static_update_scales(double length, double fscale);

/// The scaled update of one node unknown, `index` in 0..11 (r, theta, kappa, n of svar), changed
/// by d: |d| / scales[index / 3]; for a force component n_i in a direction the rod strains in
/// (compliance C_i not zero), the smaller of that and the strain's update |C_i d|: the positions
/// fix such a force only to within E A times their rounding.
double scaled_update(int index, double d, const std::array<double, 4>& scales, const Vec3& compliance);

/// The force scale of the convergence test: the largest of E I / L^2 + the rod's weight and
/// the point and end forces [N].
double static_force_scale(const StaticModel& m);

/// The model with gravity, point forces and end forces multiplied by `factor`.
StaticModel scaled_loads(const StaticModel& m, double factor);

}  // namespace traverse::rod

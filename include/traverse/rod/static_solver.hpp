#pragma once
// Newton solver for the static form (rod/static_kernels.hpp) with load stepping, on any
// StaticNewtonSystem: over the ranks for the initial states of dynamic runs
// (solver/static_start.hpp: the equilibrium under the scene's dead loads), or the tests'
// serial reference on the whole rod.
#include <string>

#include "traverse/rod/static_kernels.hpp"

namespace traverse::rod {

struct StaticReport {
  bool converged = false;
  int iterations = 0;        ///< Newton iterations in all
  int load_steps = 0;        ///< accepted load steps
  double residual_norm = 0;  ///< max |r| at the returned state (newton: where it stopped)
  double load_scale = 0;     ///< the force scale of the convergence test [N] (ftol * load_scale)
  std::string message;       ///< why it failed (empty when converged)
  // solve_with_load_steps:
  double load_factor = 0;      ///< the largest load factor reached (1 when converged)
  double failed_factor = 0;    ///< the load factor of the last failed Newton solve (0: none failed)
  double failed_residual = 0;  ///< max |r| where that solve stopped
  double failed_scale = 0;     ///< its force scale [N]
  std::string failed_reason;   ///< why it failed
};

/// The state and the linear algebra the static Newton works on: one rank's piece of the rod
/// (the distributed start, solver/static_start.hpp), or the whole rod (the tests' reference). Every call is collective where the state is distributed, and
/// returns the same value on every rank.
class StaticNewtonSystem {
 public:
  virtual ~StaticNewtonSystem() = default;
  /// Residual and Jacobian at the current state of `m`; false when the residual is not finite.
  virtual bool assemble(const StaticModel& m) = 0;
  /// Factorises the assembled Jacobian; false (and `why`) when it is singular.
  virtual bool factorize(std::string& why) = 0;
  /// Adds the Newton update dx = -J^-1 r to the state and returns the largest scaled update,
  /// max over nodes of static_update_node's measure (infinite when not finite); folds theta
  /// into the frame of every node where |theta| > 1 (keeps increments small). `m`: its length
  /// and compliance.
  virtual double update(const StaticModel& m, double fscale) = 0;
  /// max |r| at the current state (not finite when it is not).
  virtual double residual_max(const StaticModel& m) = 0;
  virtual void rebase_all() = 0;
  /// A Newton solve begins: keeps the current state (restore() goes back to it).
  virtual void start() = 0;
  virtual void restore() = 0;
};

class StaticSolver {
 public:
  double rtol = 1e-12;     ///< converged when max|dx| <= rtol (scaled per unknown kind) ...
  double ftol = 1e-9;      ///< ... and max|r| <= ftol * (load scale)
  int max_iterations = 30;
  int max_load_steps = 200;
  /// Newton from the system's state (frames rebased on success, restored on failure).
  StaticReport newton(const StaticModel& m, StaticNewtonSystem& sys) const;
  /// Equilibrium under `m`'s loads reached from the system's state (equilibrium under no
  /// load) by scaling gravity, point forces and end forces with lambda from 0 to 1: first in
  /// one step, halving the increment after a failure and doubling it after an easy success.
  StaticReport solve_with_load_steps(const StaticModel& m, StaticNewtonSystem& sys) const;
};

/// One node's share of a Newton update: x += d, then theta folded into the frame when
/// |theta| > 1; returns max(|dr|/L, |dtheta|, |dkappa| L, |dn|') of d with |dn|' = |dn_i| / fscale,
/// or, in a direction the rod strains in (C_i not zero), the smaller of that and the strain's
/// update |C_i dn_i|: the positions fix such a force only to within E A times their rounding.
double static_update_node(StaticNode& node, const Vec12& d, const StaticModel& m, double fscale);

/// The force scale of the convergence test: the largest of E I / L^2 + the rod's weight and
/// the point and end forces [N].
double static_force_scale(const StaticModel& m);

/// The model with gravity, point forces and end forces multiplied by `factor`.
StaticModel scaled_loads(const StaticModel& m, double factor);

}  // namespace traverse::rod

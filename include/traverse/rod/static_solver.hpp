#pragma once
// Serial Newton solver for the static form (rod/static_kernels.hpp): sparse LU on the whole
// rod, with load stepping. Used for initial states (equilibrium under the scene's dead
// loads) and as the reference the distributed continuation must reproduce.
#include <Eigen/SparseCore>

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

class StaticSolver {
 public:
  double rtol = 1e-12;     ///< converged when max|dx| <= rtol (scaled per unknown kind) ...
  double ftol = 1e-9;      ///< ... and max|r| <= ftol * (load scale)
  int max_iterations = 30;
  int max_load_steps = 200;

  VecX residual(const StaticModel& m, const std::vector<StaticNode>& nodes) const;
  void residual_and_jacobian(const StaticModel& m, const std::vector<StaticNode>& nodes, VecX& r,
                             Eigen::SparseMatrix<double>& J) const;

  /// Newton from `nodes` (updated in place; frames rebased on success, restored on failure).
  StaticReport newton(const StaticModel& m, std::vector<StaticNode>& nodes) const;

  /// Equilibrium under `m`'s loads reached from `nodes` (equilibrium under no load) by
  /// scaling gravity, point forces and end forces with lambda from 0 to 1: first in one step,
  /// halving the increment after a failure and doubling it after an easy success.
  StaticReport solve_with_load_steps(const StaticModel& m, std::vector<StaticNode>& nodes) const;
};

/// The model with gravity, point forces and end forces multiplied by `factor`.
StaticModel scaled_loads(const StaticModel& m, double factor);

}  // namespace traverse::rod

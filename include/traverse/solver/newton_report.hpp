#pragma once
// What one Newton solve of a rod time step did (filled by NewtonSolver).
#include <string>
#include <vector>

namespace traverse::solver {

struct NewtonReport {
  bool converged = false;
  int iterations = 0;             ///< Newton iterations taken
  double residual_norm = 0.0;     ///< max |f| at the returned iterate (units of the rows)
  double update_wrms = 0.0;       ///< weighted RMS norm of the last update (< 1 means small)
  int linear_iterations = 0;      ///< Krylov iterations summed over the solve (0 for direct)
  /// max |f| at the initial guess and after each iteration (size iterations + 1 when the
  /// initial residual was available).
  std::vector<double> residual_history;
  std::string status;             ///< "converged", "failed: max iterations", "failed: ..." etc.
};

}  // namespace traverse::solver

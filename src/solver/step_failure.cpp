#include "traverse/solver/step_failure.hpp"

#include <cstdio>
#include <string>

namespace traverse::solver {

namespace {
std::string message(double t_step, double dt_step, double t_fail, double dt_fail, int depth,
                    const NewtonReport& r) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "rod time step failed: step from t = %.9g s with dt = %.9g s; Newton did not "
                "converge on the substep from t = %.9g s with dt = %.9g s (subdivision depth %d): "
                "%s after %d iterations, max|f| = %.3e, update WRMS = %.3e",
                t_step, dt_step, t_fail, dt_fail, depth, r.status.c_str(), r.iterations,
                r.residual_norm, r.update_wrms);
  return buf;
}
}  // namespace

StepFailure::StepFailure(double t_step, double dt_step, double t_fail, double dt_fail, int depth,
                         NewtonReport report)
    : time::StepFailed(message(t_step, dt_step, t_fail, dt_fail, depth, report)),
      t_step_(t_step), dt_step_(dt_step), t_fail_(t_fail), dt_fail_(dt_fail), depth_(depth),
      report_(std::move(report)) {}

}  // namespace traverse::solver

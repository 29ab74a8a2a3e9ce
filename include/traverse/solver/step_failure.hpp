#pragma once
// Thrown by DistributedStepper::step when Newton fails even after subdividing the step.
#include <stdexcept>

#include "traverse/solver/newton_report.hpp"
#include "traverse/time/time_integrator.hpp"

namespace traverse::solver {

class StepFailure : public time::StepFailed {
 public:
  /// t_step, dt_step: the step that was asked for [s]; t_fail, dt_fail: the (sub)step whose
  /// Newton solve failed [s]; depth: how many times dt_step had been halved (0 = not
  /// subdivided); report: the failing Newton solve.
  StepFailure(double t_step, double dt_step, double t_fail, double dt_fail, int depth,
              NewtonReport report);

  double time() const { return t_step_; }        ///< start of the requested step [s]
  double step() const { return dt_step_; }       ///< requested step [s]
  double failed_time() const { return t_fail_; } ///< start of the failing substep [s]
  double failed_step() const { return dt_fail_; }///< failing substep [s]
  int depth() const { return depth_; }
  const NewtonReport& report() const { return report_; }

 private:
  double t_step_, dt_step_, t_fail_, dt_fail_;
  int depth_;
  NewtonReport report_;
};

}  // namespace traverse::solver

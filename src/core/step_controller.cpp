#include "traverse/core/step_controller.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace traverse {

double tolerance_scale(double tolerance, int order) { return std::pow(tolerance / 1e-3, 1.0 / order); }

double StepController::landing_step(double proposed, double remaining) {
  if (proposed >= remaining * (1.0 - 1e-12)) return remaining;
  if (proposed > 0.5 * remaining) return 0.5 * remaining;
  return proposed;
}

double StepController::clamp(double dt) const {
  double h = std::max(dt, p_.dt_min);
  if (p_.dt_max > 0.0) h = std::min(h, p_.dt_max);
  return h;
}

StepDecision StepController::decide(double dt, double error, int newton_iterations) {
  StepDecision d;
  const double err = std::isfinite(error) ? std::max(error, 0.0) : std::numeric_limits<double>::infinity();
  d.accept = err <= 1.0;
  // Optimal factor for an error O(dt^(p+1)): the error would be safety^(p+1) of the tolerance.
  const double expo = 1.0 / (p_.order + 1);
  double factor = err > 0.0 ? p_.safety * std::pow(err, -expo) : p_.growth;
  if (d.accept) {
    double most = rejected_last_ ? 1.0 : p_.growth;
    if (newton_iterations > p_.newton_target) most = std::min(most, 1.0);
    factor = std::min(factor, most);
    rejected_last_ = false;
  } else {
    factor = std::clamp(factor, p_.shrink, p_.safety);
    rejected_last_ = true;
  }
  d.next_dt = clamp(dt * factor);
  return d;
}

double StepController::after_failure(double dt) {
  rejected_last_ = true;
  return clamp(dt * std::min(0.5, std::max(p_.shrink, 0.25)));
}

void StepControlTotals::record_accepted(double dt) {
  ++accepted;
  smallest_dt = accepted == 1 ? dt : std::min(smallest_dt, dt);
  largest_dt = std::max(largest_dt, dt);
}

std::string StepControlTotals::summary() const {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%ld steps accepted, %ld rejected (error), %ld failed (Newton); dt %.4g .. %.4g s",
                accepted, rejected, failed, smallest_dt, largest_dt);
  return buf;
}

}  // namespace traverse

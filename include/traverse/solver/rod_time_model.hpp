#pragma once
// The rod with prescribed loads as the time integrator's model (time/time_integrator.hpp):
// fixed steps with the stepper's own subdivision, adaptive attempts checked by the error
// estimate (extrapolation, or step doubling while the history is short), the left end's
// position integrated in time.
#include <mpi.h>

#include <functional>
#include <vector>

#include "traverse/rod/time_error.hpp"
#include "traverse/solver/rod_error_estimate.hpp"
#include "traverse/solver/rod_stepper.hpp"
#include "traverse/time/time_integrator.hpp"

namespace traverse::solver {

/// The adaptive estimate's quantities of this rank's owned nodes, now.
std::vector<rod::NodeLevel> owned_levels(const RodStepper& st);

/// The position of the rod's left end: fixed for ends that hold it, else integrated in time
/// from its velocity R^T u (trapezoidal, second order).
class LeftEnd {
 public:
  LeftEnd(const RodStepper& st, bool moves, const Vec3& r0, MPI_Comm comm)
      : st_(st), moves_(moves), r0_(r0), comm_(comm) {}
  const Vec3& position() const { return r0_; }
  void set_position(const Vec3& r) { r0_ = r; }
  /// Call before a step of length h, then after_step(h) (collective).
  void before_step() { v_old_ = moves_ ? velocity() : Vec3::Zero(); }
  void after_step(double h) {
    if (moves_) r0_ = rod::trapezoidal_step(r0_, v_old_, velocity(), h);
  }

 private:
  Vec3 velocity() const;  ///< R^T u at node 0, broadcast from its owner
  const RodStepper& st_;
  bool moves_;
  Vec3 r0_, v_old_ = Vec3::Zero();
  MPI_Comm comm_;
};

/// Counters of the Newton solves, for the run's report.
struct SolveCounts {
  long newton = 0, solves = 0;
  long guess_retries = 0;  ///< solves that failed from the blended guess and were redone from the old level
};

class RodTimeModel : public time::SteppedModel {
 public:
  /// `estimate`: the adaptive steps' (nullptr for fixed steps); `kinks`: the first time after
  /// t where the loads have a kink (empty: none).
  RodTimeModel(RodStepper& stepper, LeftEnd& left, RodErrorEstimate* estimate, std::function<double(double)> kinks)
      : st_(stepper), left_(left), est_(estimate), kinks_(std::move(kinks)) {}
  double time() const override { return st_.time(); }
  void step(double h) override;
  time::Attempt attempt(double h) override;
  std::vector<double> accept() override;
  void reject() override;
  double next_kink(double t) const override { return kinks_ ? kinks_(t) : HUGE_VAL; }
  const SolveCounts& counts() const { return counts_; }

 private:
  /// One Newton solve of h; false (the state unchanged, `why` set) when it did not converge.
  bool solve(double h, StepReport& rep, std::string& why);
  time::Attempt extrapolated(double h);
  time::Attempt doubled(double h);
  void restore_start();
  RodStepper& st_;
  LeftEnd& left_;
  RodErrorEstimate* est_;
  std::function<double(double)> kinks_;
  SolveCounts counts_;
  /// The attempt in hand: its length, and the new level (extrapolated) or the two half levels
  /// and the state they started from (doubled).
  double h_ = 0.0;
  bool doubled_ = false;
  std::vector<rod::NodeLevel> y_, mid_;
  rod::RodState saved_;
  Vec3 r_saved_ = Vec3::Zero();
};

}  // namespace traverse::solver

#include "run_observer.hpp"

#include "interrupt.hpp"
#include "restart.hpp"
#include "traverse/scene/schema.hpp"
#include "traverse/solver/rod_stepper.hpp"

namespace traverse::app {

void RunObserver::store(long step) {
  hooks_.store(step);
  stored_ = std::chrono::steady_clock::now();
}

bool RunObserver::store_due() { return restart_due(stored_, opt_.restart_interval, comm_); }

int RunObserver::interrupt_requested() { return app::interrupt_requested(comm_); }

void RunObserver::progress(double t, long step, double next_dt, const StepControlTotals* totals) {
  if (hooks_.stepped) hooks_.stepped();
  if (totals)
    progress_.update(t, step, next_dt, *totals);
  else
    progress_.update(t, step);
}

void RunObserver::interrupted(int sig, long step, const std::string& where) {
  stop_interrupted_run(sig, hooks_.time(), where, w_, opt_.output, progress_, [&] { store(step); });
}

void RunObserver::failed(const std::string& where, const std::string& why, long step, const time::StepFailed* cause) {
  progress_.done();
  std::string msg;
  if (dynamic_cast<const solver::PlanarityLost*>(cause)) {
    msg = where + ": " + why + "; traverse run --restart " + opt_.output +
          " --set scheme.planar=off continues on the 3D path";
  } else {
    msg = cause && hooks_.explain ? hooks_.explain(where, *cause) : where + ": " + why;
    msg += " (traverse run --restart " + opt_.output + " --set ... continues from t = " +
           scene::format_number(hooks_.time()) + " s)";
  }
  store(step);  // the model kept the state before the failed step
  w_.fail(msg);
  throw NumericsError(msg);
}

}  // namespace traverse::app

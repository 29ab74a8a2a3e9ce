// One validated scene, run by the runner of its model.
#include <cstdio>
#include <stdexcept>

#include "interrupt.hpp"
#include "run.hpp"
#include "traverse/core/comm.hpp"
#include "traverse/core/stop_request.hpp"

namespace traverse::app {

namespace {

// The stop hook of the run's set-up (traverse/core/stop_request.hpp): the signal handlers'
// flag, over the ranks where there are several (the static solves it is polled in are then
// distributed, every rank at the same iteration). Removed when the run ends.
class SetUpStops {
 public:
  explicit SetUpStops(MPI_Comm comm) {
    stop_hook() = [comm, this] {
      signal_ = par::size(comm) > 1 ? interrupt_requested(comm) : local_interrupt_signal();
      return signal_ != 0;
    };
  }
  ~SetUpStops() { stop_hook() = nullptr; }
  SetUpStops(const SetUpStops&) = delete;
  SetUpStops& operator=(const SetUpStops&) = delete;
  int signal() const { return signal_; }

 private:
  int signal_ = 0;
};

void run_model(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  switch (sc.model) {
    case scene::Model::Beam:
      run_beam(sc, opt, comm);
      break;
    case scene::Model::Rod:
      if (sc.continuation.enabled) {
        run_statics(sc, opt, comm);
      } else {
        run_rod(sc, opt, comm);
      }
      break;
    default:
      throw std::logic_error("traverse run: model not handled");
  }
}

}  // namespace

void run_scene(const scene::Scene& sc, const RunOptions& options, MPI_Comm comm) {
  RunOptions opt = options;
  opt.progress_interval = sc.output.progress_interval;
  opt.flush_interval = sc.output.flush_interval;
  if (!sc.continuation.enabled && par::rank(comm) == 0)
    for (const std::string& w : setup::idle_load_warnings(sc)) std::fprintf(stderr, "traverse: warning: %s\n", w.c_str());
  if (opt.verbose) {  // the plan: what `traverse check` prints (the checks are collective)
    const std::string plan = setup::check_run(sc, opt.limits, comm);
    if (par::rank(comm) == 0) std::printf("plan: %s\n", plan.c_str());
  }
  SetUpStops stops(comm);
  try {
    run_model(sc, opt, comm);
  } catch (const StopRequested& e) {
    // Nothing of the run was written yet: no output file to mark.
    const std::string msg = "interrupted (" + signal_name(stops.signal()) + ") " + e.what() +
                            " of the initial state; nothing written";
    throw Interrupted(stops.signal(), "", msg, msg);
  }
}

}  // namespace traverse::app

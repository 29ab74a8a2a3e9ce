#pragma once
// What a run does around the time integrator (time/time_integrator.hpp): write the outputs,
// store restart points when their interval has passed, report progress, stop on a signal and
// end on a numerical failure with a message that says where, why and how to continue.
#include <mpi.h>

#include <chrono>
#include <functional>
#include <string>

#include "progress.hpp"
#include "run.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/time/time_integrator.hpp"

namespace traverse::app {

class RunObserver : public time::Observer {
 public:
  struct Hooks {
    std::function<void()> write;      ///< the outputs of the current state
    std::function<void(long)> store;  ///< a restart point of the current state as that of a step
    std::function<double()> time;     ///< the model's time [s]
    /// The message of a model's failure (`where`: e.g. "time step 12 of 100"); empty: where: why.
    std::function<std::string(const std::string& where, const time::StepFailed& e)> explain;
    std::function<void()> stepped;  ///< after every time step (optional): the probes' extremes
  };
  RunObserver(Hooks hooks, output::Writer& writer, const RunOptions& options, Progress& progress, MPI_Comm comm)
      : hooks_(std::move(hooks)), w_(writer), opt_(options), progress_(progress), comm_(comm) {}
  void output() override { hooks_.write(); }
  void store(long step) override;
  bool store_due() override;
  int interrupt_requested() override;
  void progress(double t, long step, double next_dt, const StepControlTotals* totals) override;
  [[noreturn]] void interrupted(int sig, long step, const std::string& where) override;
  /// Stores the restart point of `step`, marks the output file failed and throws NumericsError.
  [[noreturn]] void failed(const std::string& where, const std::string& why, long step,
                           const time::StepFailed* cause) override;

 private:
  Hooks hooks_;
  output::Writer& w_;
  const RunOptions& opt_;
  Progress& progress_;
  MPI_Comm comm_;
  std::chrono::steady_clock::time_point stored_ = std::chrono::steady_clock::now();
};

}  // namespace traverse::app

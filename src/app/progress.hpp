#pragma once
// Progress on stderr: position, steps per second and estimated time left, at most once per
// interval (output.progress_interval, default 1 s; 0: at every update), only where enabled
// (a terminal, or --progress) and never with -q. On a terminal the line is rewritten in
// place; elsewhere (a log file, a pipe) every report is its own line. Rate and time left come from the last 10 s of the run, not from its start.
#include <chrono>
#include <deque>
#include <string>

#include "traverse/core/step_controller.hpp"

namespace traverse::app {

class Progress {
 public:
  /// `what` names the progress variable (e.g. "t"), `units` its units, `total` its end value,
  /// `interval` the wall seconds between reports.
  Progress(bool enabled, std::string what, std::string units, double start, double total, double interval = 1.0);
  /// Reports `current` after `steps` steps if `interval` has passed since the last report;
  /// `detail` (e.g. the step size) is shown after the rate.
  void update(double current, long steps, const char* detail = nullptr);
  /// The same for an adaptive run, with the detail "dt = <proposed_dt> s, <N> rejected"
  /// (rejected by the error estimate or failed), formatted only when a report is due.
  void update(double current, long steps, double proposed_dt, const StepControlTotals& totals);
  /// Ends the progress line.
  void done();

 private:
  bool due() const;  ///< enabled, and `interval` since the last report
  struct Sample {
    std::chrono::steady_clock::time_point when;
    double current;
    long steps;
  };
  bool enabled_, tty_;
  std::string what_, units_;
  double start_, total_;
  std::chrono::duration<double> interval_;
  std::chrono::steady_clock::time_point begin_, last_;
  std::deque<Sample> recent_;  ///< reports of the last 10 s (and the one before them)
  bool printed_ = false;
};

/// Whether progress should be shown: --progress, or stderr is a terminal; never with -q.
bool progress_wanted(bool quiet, bool forced);

}  // namespace traverse::app

#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace traverse::app {

bool progress_wanted(bool quiet, bool forced) {
  if (quiet) return false;
  return forced || isatty(fileno(stderr));
}

Progress::Progress(bool enabled, std::string what, std::string units, double start, double total, double interval)
    : enabled_(enabled), tty_(isatty(fileno(stderr)) != 0), what_(std::move(what)), units_(std::move(units)),
      start_(start), total_(total), interval_(interval), begin_(std::chrono::steady_clock::now()), last_(begin_) {
  recent_.push_back({begin_, start, 0});
}

void Progress::update(double current, long steps, const char* detail) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < interval_) return;
  last_ = now;
  // The rate over the last 10 s: keep the newest sample older than that as the reference.
  while (recent_.size() > 1 && now - recent_[1].when >= std::chrono::seconds(10)) recent_.pop_front();
  const Sample& ref = recent_.front();
  const double span = std::chrono::duration<double>(now - ref.when).count();
  const double rate = span > 0.0 ? (current - ref.current) / span : 0.0;     // units per second
  const double step_rate = span > 0.0 ? double(steps - ref.steps) / span : 0.0;
  recent_.push_back({now, current, steps});
  const double frac = total_ > start_ ? (current - start_) / (total_ - start_) : 1.0;
  const double left = rate > 0.0 ? (total_ - current) / rate : 0.0;
  std::fprintf(stderr, "%s  %s = %.6g %s of %.6g (%3.0f%%), %.0f steps/s%s%s, about %.0f s left%s", tty_ ? "\r" : "",
               what_.c_str(), current, units_.c_str(), total_, 100.0 * frac, step_rate, detail ? ", " : "",
               detail ? detail : "", left, tty_ ? "   " : "\n");
  std::fflush(stderr);
  printed_ = true;
}

bool Progress::due() const { return enabled_ && std::chrono::steady_clock::now() - last_ >= interval_; }

void Progress::update(double current, long steps, double proposed_dt, const StepControlTotals& totals) {
  if (!due()) return;
  char detail[96];
  std::snprintf(detail, sizeof detail, "dt = %.3g s, %ld rejected", proposed_dt, totals.rejected + totals.failed);
  update(current, steps, detail);
}

void Progress::done() {
  if (enabled_ && printed_ && tty_) std::fprintf(stderr, "\n");
  printed_ = false;
}

}  // namespace traverse::app

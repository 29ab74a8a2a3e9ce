#include "progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace traverse::app {

bool progress_wanted(bool quiet, bool forced) {
  if (quiet) return false;
  return forced || isatty(fileno(stderr));
}

Progress::Progress(bool enabled, std::string what, std::string units, double start, double total)
    : enabled_(enabled), what_(std::move(what)), units_(std::move(units)), start_(start), total_(total),
      begin_(std::chrono::steady_clock::now()), last_(begin_) {}

void Progress::update(double current, long steps) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < std::chrono::seconds(1)) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - begin_).count();
  const double frac = total_ > start_ ? (current - start_) / (total_ - start_) : 1.0;
  const double left = frac > 0.0 ? elapsed * (1.0 - frac) / frac : 0.0;
  std::fprintf(stderr, "\r  %s = %.6g %s of %.6g (%3.0f%%), %.0f steps/s, about %.0f s left   ", what_.c_str(),
               current, units_.c_str(), total_, 100.0 * frac, steps / elapsed, left);
  std::fflush(stderr);
  printed_ = true;
}

void Progress::done() {
  if (enabled_ && printed_) std::fprintf(stderr, "\n");
  printed_ = false;
}

}  // namespace traverse::app

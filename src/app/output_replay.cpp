#include "output_replay.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "traverse/output/output_error.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

OutputReplay::OutputReplay(const RunOptions& opt, const std::vector<std::string>& probe_names,
                           const std::vector<std::string>& field_names, std::string what, MPI_Comm comm)
    : opt_(opt), names_(probe_names), what_(std::move(what)) {
  if (!opt.restart) return;
  const std::string source = output::restart_source(opt.output);
  output::check_restart_outputs(source, names_, field_names);
  try {
    output::Reader r(source);
    kept_ = r.steps_written();
    time_ = r.time();
    for (const auto& n : names_) probes_.push_back(r.probe(n));
  } catch (const output::OutputError& e) {
    throw UsageError{"--restart: cannot read " + source + " (" + e.what() + ")"};
  }
  output::move_aside_for_restart(opt.output, comm);
}

void OutputReplay::check(std::size_t o, double t, const std::vector<std::vector<double>>& probes) const {
  auto differs = [](double a, double b) {
    return !(a == b || (std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)));
  };
  std::string bad;
  if (differs(time_[o], t)) bad = "time " + scene::format_number(time_[o]) + " vs " + scene::format_number(t);
  for (size_t q = 0; bad.empty() && q < probes.size(); ++q)
    for (size_t c = 0; bad.empty() && c < probes[q].size(); ++c)
      if (differs(probes_[q].values[o * probes_[q].components + c], probes[q][c]))
        bad = "probe " + names_[q] + " = " + scene::format_number(probes_[q].values[o * probes_[q].components + c]) +
              " vs " + scene::format_number(probes[q][c]);
  if (!bad.empty())
    throw UsageError{"--restart " + opt_.output + ": re-integrating " + what_ + " does not reproduce output step " +
                     std::to_string(o) + " (" + bad + "); the scene or the program differ from the run being restarted"};
}

void OutputReplay::written(std::size_t steps, MPI_Comm comm) const {
  if (opt_.restart && steps == kept_) output::remove_restart_source(opt_.output, comm);
}

void OutputReplay::finished(std::size_t steps, MPI_Comm comm) const {
  if (opt_.restart && steps < kept_) output::remove_restart_source(opt_.output, comm);
}

}  // namespace traverse::app

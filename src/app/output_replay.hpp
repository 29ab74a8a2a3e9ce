#pragma once
// --restart of a run that is integrated again from t = 0 (the beam, and the runs with a
// coupled mass, whose steppers cannot be set to a stored state; docs/reliability.md): the
// output steps the restart source holds are checked against the replay (time and every
// probe component to 1e-12), then rewritten, and the run continues.
#include <mpi.h>

#include <cstddef>
#include <string>
#include <vector>

#include "run.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/output/writer.hpp"

namespace traverse::app {

class OutputReplay {
 public:
  /// Reads the restart source's output steps and moves it aside (opt.restart only). `what`
  /// names what is integrated again in the message of a mismatch (e.g. "the beam").
  OutputReplay(const RunOptions& opt, const std::vector<std::string>& probe_names,
               const std::vector<std::string>& field_names, std::string what, MPI_Comm comm);
  std::size_t kept() const { return kept_; }
  /// Throws UsageError when output step o (< kept()) of the replay differs from the file.
  void check(std::size_t o, double t, const std::vector<std::vector<double>>& probes) const;
  /// After each written output step / at the end: removes the source once it is replaced.
  void written(std::size_t steps, MPI_Comm comm) const;
  void finished(std::size_t steps, MPI_Comm comm) const;
  /// Writes output step `written` of `outputs` (evaluated: probes(), write(w, t)) at time t,
  /// checked against the file while it replays a kept step, and counts it.
  template <class Outputs>
  void write(Outputs& outputs, output::Writer& w, double t, long& written, MPI_Comm comm) const {
    const auto o = static_cast<std::size_t>(written);
    if (o < kept()) check(o, t, outputs.probes());
    outputs.write(w, t);
    ++written;
    this->written(static_cast<std::size_t>(written), comm);
  }

 private:
  const RunOptions& opt_;
  std::vector<std::string> names_;
  std::string what_;
  std::size_t kept_ = 0;
  std::vector<double> time_;
  std::vector<output::Series> probes_;
};

}  // namespace traverse::app

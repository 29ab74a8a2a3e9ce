#pragma once
// Serial reader of the files traverse::output::Writer produces (tests, restart, tools).
// Opens the file read-only with HDF5's default (POSIX) driver: any rank may open it
// independently, no MPI needed. Everything is trimmed to the root attribute
// `steps_written`, never to the dataset extents.
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "traverse/output/output_error.hpp"
#include "traverse/output/output_types.hpp"

namespace traverse::output {

/// A time series or a restart array as stored: `values` row-major, `rows` x `components`.
struct Series {
  std::vector<double> values;
  std::size_t rows = 0;
  std::size_t components = 1;
  std::string units;                         ///< attribute `units` ("" if absent)
  std::string description;                   ///< attribute `description` ("" if absent)
  std::vector<std::string> component_names;  ///< attribute `components` split at ',' (may be empty)
};

class Reader {
 public:
  /// Opens `path` read-only; throws OutputError if it cannot.
  explicit Reader(const std::string& path);
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;
  Reader(Reader&&) noexcept;
  Reader& operator=(Reader&&) noexcept;

  /// Root attribute `steps_written`: the number of complete steps.
  std::size_t steps_written() const;
  /// A string root attribute (`status`, `model`, `scene`, ...); throws if absent.
  std::string attribute(const std::string& name) const;
  bool has_attribute(const std::string& name) const;
  /// Shortcut for attribute("status").
  std::string status() const;

  /// `/time` [s], steps_written values.
  std::vector<double> time() const;
  /// `/sigma` [m], steps_written rows x moving_loads() components.
  Series sigma() const;
  std::size_t moving_loads() const;
  /// `/mesh/s` [m], one value per node.
  std::vector<double> arclength() const;
  std::size_t node_count() const;

  std::vector<std::string> probe_names() const;
  /// `/probes/<name>`, steps_written rows.
  Series probe(const std::string& name) const;
  /// The probe's extremes over every time step (Writer::write_probe_extremes), when the run
  /// recorded them (a complete beam run does).
  std::optional<ProbeExtremes> probe_extremes(const std::string& name) const;

  std::vector<std::string> field_names() const;
  /// Metadata of `/fields/<name>` (values empty, rows = number of nodes).
  Series field_info(const std::string& name) const;
  /// One step of `/fields/<name>`: nodes [first, first+count) x components, node-major.
  /// count = SIZE_MAX means "to the last node". Throws if step >= steps_written.
  std::vector<double> field(const std::string& name, std::size_t step, std::size_t first = 0,
                            std::size_t count = static_cast<std::size_t>(-1)) const;

  /// `/events` (Writer::write_events): empty when the file has none.
  std::vector<RunEvent> events() const;

  /// True when `/restart` exists and its attribute `valid` is 1.
  bool has_restart() const;
  double restart_time() const;          ///< `/restart` attribute `time` [s]
  std::size_t restart_step() const;     ///< `/restart` attribute `steps_written`
  std::vector<std::string> restart_names() const;
  /// `/restart/<name>`; for per-node arrays, rows [first, first+count) only.
  Series restart(const std::string& name, std::size_t first = 0,
                 std::size_t count = static_cast<std::size_t>(-1)) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace traverse::output

#pragma once
// Parallel HDF5 output of one run: one file written collectively by all ranks, plus an
// XDMF sidecar for ParaView. File layout and guarantees: docs/output.md.
#include <mpi.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "traverse/output/output_error.hpp"
#include "traverse/output/output_types.hpp"

namespace traverse::output {

/// Writes `/time`, `/sigma`, `/probes/*`, `/fields/*`, `/mesh/*`, `/xdmf/*`, `/restart/*` and
/// the root attributes of one output file. Every member function except the accessors is
/// COLLECTIVE over the communicator given to the constructor: all ranks call it, in the same
/// order, with the same replicated arguments.
///
/// Cost and crash safety: write_step only copies the step into memory. The steps kept in
/// memory are appended to the file (one write per dataset for all of them) and flushed, and
/// only then announced in the root attribute `steps_written`, when flush_interval() seconds
/// of wall time have passed since the last flush (rank 0's clock decides for all ranks), when
/// they fill max_pending_bytes, and in flush(), write_restart(), finish() and fail(). A run
/// killed at any moment leaves a file whose first `steps_written` steps read back intact; it
/// loses at most the steps of the last flush interval. The XDMF sidecar is rewritten after a
/// flush at most every xdmf_interval() seconds (longer when writing it takes long), and always
/// by finish() and fail(); `traverse xdmf` (write_sidecar) rewrites it from the file.
class Writer {
 public:
  /// Creates `path` (and the sidecar `path` with extension ".xmf") and writes the run
  /// metadata, `/mesh/s`, empty `/time` and `/sigma` (shape (steps,) if moving_loads == 1,
  /// else (steps, moving_loads)) and status "running". Throws OutputError (on all ranks) if
  /// the folder does not exist or is not a writable folder, or if the file or its sidecar
  /// exists and `overwrite` is false. `comm` is duplicated (one of a single rank, like
  /// MPI_COMM_NULL, is not: the file is then written through HDF5's POSIX driver, without MPI
  /// calls). MPI must be initialised for a communicator, and the Writer must be destroyed
  /// before MPI_Finalize.
  Writer(MPI_Comm comm, const std::string& path, bool overwrite, const RunInfo& info,
         const NodeLayout& nodes, std::size_t moving_loads = 1);
  /// Sets status "failed: output closed before finish() or fail()" if neither was called,
  /// then closes the file. Never throws (errors are swallowed). Collective like H5Fclose.
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;
  Writer(Writer&&) noexcept;
  Writer& operator=(Writer&&) noexcept;

  /// Declares a probe before the first step; returns its index for write_step.
  std::size_t add_probe(const ProbeSpec& spec);
  /// Declares a field before the first step; returns its index for write_step.
  std::size_t add_field(const FieldSpec& spec);

  /// Appends one output step. `time` [s]; `sigma` [m]: position of each moving load, size
  /// moving_loads; `probes[i]`: values of the i-th declared probe (size = its components;
  /// replicated, rank 0's are written); `fields[j]`: this rank's values of the j-th declared
  /// field, node-major, size local node count * components. Keeps the step in memory; writes
  /// and flushes the kept steps when one of the conditions above holds (see the class comment).
  void write_step(double time, const std::vector<double>& sigma,
                  const std::vector<std::vector<double>>& probes,
                  const std::vector<DoubleView>& fields);

  /// Appends the steps kept in memory, flushes, then announces them (`steps_written`).
  void flush();

  /// Wall-time cadence [s] of the automatic flushes (default 1; 0: after every step) and of
  /// the sidecar rewrites while running (default 5, or 20 times as long as the last rewrite
  /// took if that is longer; 0: after every flush). Collective; call it before write_step.
  void set_intervals(double flush_seconds, double xdmf_seconds);
  double flush_interval() const;
  double xdmf_interval() const;
  /// The kept steps are flushed when their field data reach this many bytes (all ranks
  /// together; default 64 MiB), whatever the time.
  static constexpr std::size_t max_pending_bytes = std::size_t(64) << 20;

  /// Replaces the content of the `/restart` group by `arrays` (arrays of earlier calls
  /// that are not repeated are removed) and records `time` [s] and the current
  /// steps_written as attributes, after flushing the steps kept in memory. The group's
  /// attribute `valid` is 0 while it is being written and 1 once the arrays are flushed.
  void write_restart(double time, const std::vector<RestartArray>& arrays);

  /// Writes the events table `/events` (datasets `time` [s] and `position` [m], one entry per
  /// event, attributes `count`, `loads` and `reasons`: the events' load names and reason words,
  /// comma-separated) and the root attribute `end_reason` (the first event's reason, or
  /// "end_time" when there is none). Replaces an earlier table. Replicated arguments (rank 0's
  /// are written).
  void write_events(const std::vector<RunEvent>& events);

  /// Writes the extremes of the probe of index `probe` (add_probe) over every time step as the
  /// attributes `min`, `max`, `time_of_min`, `time_of_max` of `/probes/<name>` (a value per
  /// component). Collective: every rank passes the same values.
  void write_probe_extremes(std::size_t probe, const ProbeExtremes& extremes);

  /// Sets the root string attribute `name` (collective: every rank passes the same value).
  void set_attribute(const std::string& name, const std::string& value);

  /// Flushes the kept steps, writes the sidecar, sets status "complete" and flushes. The file
  /// stays open until destruction.
  void finish();
  /// As finish() with status "failed: <reason>" (the numerics failed, or the run was stopped).
  void fail(const std::string& reason);

  /// Steps passed to write_step (those kept in memory included: all are in the file after
  /// the next flush).
  std::size_t steps_written() const;
  /// Steps in the file and announced in its `steps_written` attribute.
  std::size_t steps_flushed() const;
  const std::string& path() const;
  const std::string& xdmf_path() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace traverse::output

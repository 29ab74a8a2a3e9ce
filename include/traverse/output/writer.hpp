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

/// Writes `/time`, `/sigma`, `/probes/*`, `/fields/*`, `/mesh/*`, `/restart/*` and the root
/// attributes of one output file. Every member function except the accessors is COLLECTIVE
/// over the communicator given to the constructor: all ranks call it, in the same order,
/// with the same replicated arguments. Crash safety: after every write_step the file is
/// flushed so that a run killed at any later moment leaves a file whose first
/// `steps_written` steps read back intact.
class Writer {
 public:
  /// Creates `path` (and the sidecar `path` with extension ".xmf") and writes the run
  /// metadata, `/mesh/s`, empty `/time` and `/sigma` (shape (steps,) if moving_loads == 1,
  /// else (steps, moving_loads)) and status "running". Throws OutputError (on all ranks) if
  /// the folder does not exist or is not a writable folder, or if the file or its sidecar
  /// exists and `overwrite` is false. `comm` is duplicated. MPI must be initialised, and
  /// the Writer must be destroyed before MPI_Finalize.
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
  /// field, node-major, size local node count * components. Writes all data, flushes, then
  /// increments `steps_written` and flushes again, then rewrites the XDMF sidecar.
  void write_step(double time, const std::vector<double>& sigma,
                  const std::vector<std::vector<double>>& probes,
                  const std::vector<DoubleView>& fields);

  /// Replaces the content of the `/restart` group by `arrays` (arrays of earlier calls
  /// that are not repeated are removed) and records `time` [s] and the current
  /// steps_written as attributes. The group's attribute `valid` is 0 while it is being
  /// written and 1 once the arrays are flushed.
  void write_restart(double time, const std::vector<RestartArray>& arrays);

  /// Sets status "complete" and flushes. The file stays open until destruction.
  void finish();
  /// Sets status "failed: <reason>" and flushes (the numerics failed; collective).
  void fail(const std::string& reason);

  std::size_t steps_written() const;
  const std::string& path() const;
  const std::string& xdmf_path() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace traverse::output

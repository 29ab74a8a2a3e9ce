#pragma once
// Restart of a run from its own output file (docs/reliability.md, "Restart").
//
// Restart points: the runners store, at their restart cadence, the complete state of the
// integrator in `/restart` through Writer::write_restart, DOUBLE-BUFFERED in two
// slots "a" and "b" (the newest point goes into the slot not holding the previous one, the
// previous one is rewritten with identical bytes). Each slot is
//   <slot>.state  per-node, `components` doubles per node (the runner's packing)
//   <slot>.meta   replicated: [format = 1, time, time-step index, steps_written,
//                              checksum (high 32 bits), checksum (low 32 bits), extra...]
// The checksum (FNV-1a over every node's values and the meta entries, summed over nodes)
// lets a restart use a slot even when the run was killed while `/restart` was being
// rewritten (group attribute `valid` = 0): a partially rewritten slot fails its checksum,
// the other one is intact.
//
// Restarting: the file OUT.h5 is renamed OUT.h5.before-restart, a new OUT.h5 is created
// with the same probes and fields, the output steps up to the restart point are copied
// into it, and the run continues from the restart point, appending. When the copy is
// complete (and the restart point stored again) the .before-restart file is removed; if a
// restart is killed before that, the next --restart uses the .before-restart file.
#include <mpi.h>

#include <cstddef>
#include <string>
#include <vector>

#include "traverse/output/output_error.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/output/writer.hpp"

namespace traverse::output {

/// The file a restart of `path` reads: `path`.before-restart if it exists, else `path`.
std::string restart_source(const std::string& path);

/// Rank 0 renames `path` to `path`.before-restart unless that already exists (then `path`
/// is a partial copy of an earlier restart and is replaced). Collective; returns the source.
std::string move_aside_for_restart(const std::string& path, MPI_Comm comm);

/// Rank 0 removes the .before-restart file of `path` (collective).
void remove_restart_source(const std::string& path, MPI_Comm comm);

/// Rank 0 rewrites the root attribute `status` of the closed file `path` (HDF5 C API);
/// collective (barrier before and after). Errors are reported on stderr, never thrown. An
/// empty `path` (a run stopped before it opened its output) does nothing.
void set_file_status(const std::string& path, const std::string& status, MPI_Comm comm);

/// One restart point as read back (full state on every rank).
struct RestartPoint {
  double time = 0.0;
  long step = 0;                 ///< time-step index (0 = initial state)
  std::size_t steps_written = 0; ///< output steps in the file at this point
  std::vector<double> extra;     ///< runner-specific replicated values
  std::vector<double> state;     ///< nodes x components, node-major
  std::size_t components = 0;
  std::string slot;              ///< "a" or "b"
};

/// Writes double-buffered restart points (collective, every rank).
class RestartSlots {
 public:
  RestartSlots(MPI_Comm comm, std::size_t components, std::size_t first_node);
  /// Stores a new restart point: `local` holds this rank's nodes (count x components).
  void write(Writer& writer, double time, long step, const std::vector<double>& extra,
             const std::vector<double>& local);

 private:
  MPI_Comm comm_;
  std::size_t components_, first_;
  int current_ = -1;  // slot of the newest point (0 = "a", 1 = "b"), -1 none yet
  std::vector<double> state_[2], meta_[2];
};

/// The newest restart point of `source` whose checksum holds and which lies within the
/// file's steps_written; throws RestartError naming the file if there is none.
RestartPoint read_restart_point(const std::string& source, std::size_t nodes, std::size_t components);

/// Checks that `source` holds exactly the probes and fields a runner declares (as sets);
/// throws RestartError naming the difference. Call before move_aside_for_restart.
void check_restart_outputs(const std::string& source, const std::vector<std::string>& probe_names,
                           const std::vector<std::string>& field_names);

/// Copies output steps [0, steps) of `source` into `writer`: time, sigma, the probes
/// `probe_names` and this rank's node range [first, first + count) of the fields
/// `field_names`, both in the writer's declaration order. Checks that the source holds
/// exactly these probes and fields (RestartError otherwise).
void copy_output_steps(const std::string& source, Writer& writer, std::size_t steps,
                       const std::vector<std::string>& probe_names,
                       const std::vector<std::string>& field_names, std::size_t first, std::size_t count);

}  // namespace traverse::output

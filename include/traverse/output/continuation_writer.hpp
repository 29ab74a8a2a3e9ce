#pragma once
// Output of a continuation (statics) run: one HDF5 file, written by rank 0 and flushed after
// every point, with the layout documented in docs/output.md ("Continuation files"):
//   /continuation/<parameter>          (points)  the continued parameter [its unit]
//   /continuation/<probe>              (points)  each probe [its unit]
//   /continuation/unstable_modes       (points)  int, -1 when stability was not computed
//   /continuation/critical_eigenvalue  (points)  omega^2 nearest zero [1/s^2]
//   /continuation/branch               (points)  int: 0 the primary branch, k the k-th switched one
//   /bifurcations/{type, branch, located, <parameter>, <probe>...}   (bifurcations)
//   /bifurcations/state_<i>/{r, R, kappa, n}                         state at bifurcation i
//   /states/<name>/{r, R, kappa, n}    named states (e.g. "final": the state a dynamic
//                                      scene can start from), (nodes x 3 or 9)
//   /mesh/s (nodes)                    arclength [m]
// Root attributes as for the time-series files (traverse_version, command_line, scene,
// scene_file, model, status running/complete/failed: ...), plus points_written.
// Every member function is collective (all ranks call it with the same arguments).
#include <mpi.h>

#include <memory>
#include <string>
#include <vector>

#include "traverse/output/output_types.hpp"

namespace traverse::output {

/// A rod state at the nodes, node-major: r (3), R (9, rows d1 d2 d3), kappa (3), n (3).
struct NodalState {
  std::vector<double> r, R, kappa, n;
};

class ContinuationWriter {
 public:
  /// Creates the file (refusing to overwrite without `overwrite`, checking the folder
  /// first; OutputError on all ranks). `s`: arclength of every node.
  ContinuationWriter(MPI_Comm comm, const std::string& path, bool overwrite, const RunInfo& info,
                     const std::vector<double>& s, const std::string& parameter, const std::string& parameter_unit,
                     const std::vector<std::string>& probes, const std::vector<std::string>& probe_units);
  ~ContinuationWriter();
  ContinuationWriter(const ContinuationWriter&) = delete;
  ContinuationWriter& operator=(const ContinuationWriter&) = delete;

  void add_point(int branch, double parameter, const std::vector<double>& probes, int unstable_modes,
                 double critical_eigenvalue);
  void add_bifurcation(const std::string& type, int branch, bool located, double parameter,
                       const std::vector<double>& probes, const NodalState& state);
  void write_state(const std::string& name, const NodalState& state);
  void finish();
  void fail(const std::string& reason);
  std::size_t points_written() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Reads /states/<name> of a continuation file (any rank, no MPI). Throws OutputError
/// naming the file and what is missing.
NodalState read_state(const std::string& path, const std::string& name);

}  // namespace traverse::output

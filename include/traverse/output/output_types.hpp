#pragma once
// Plain data types shared by traverse::output::Writer and traverse::output::Reader.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "traverse/core/types.hpp"

namespace traverse::output {

/// Version of the file layout documented in docs/output.md (root attribute
/// `traverse_output_format`). Increased when the layout changes incompatibly.
inline constexpr int file_format_version = 1;

/// Run-level metadata stored as root attributes of the output file.
struct RunInfo {
  std::string version;       ///< traverse version string -> attribute `traverse_version`
  std::string command_line;  ///< full command line -> `command_line`
  std::string scene_text;    ///< full validated scene text (YAML) -> `scene`
  std::string scene_file;    ///< path of the scene file -> `scene_file`
  std::string model;         ///< structural model, e.g. "beam" or "rod" -> `model`
  /// Further string root attributes (name, value) the runner records, e.g. the rod's
  /// `rod_path` (names: [A-Za-z0-9_.-], not one of the attributes above).
  std::vector<std::pair<std::string, std::string>> attributes = {};
};

/// A probe's extremes over every time step of a run (not only the output steps), per
/// component: the smallest and largest value and the first time each was reached [s]. NaN
/// values (a load's deflection while it is off the structure) do not count.
struct ProbeExtremes {
  std::vector<double> min, max, time_of_min, time_of_max;
};

/// An event that ended (or marked) a run: a coupled mass leaving the structure, lifting off.
struct RunEvent {
  double time = 0.0;      ///< [s]
  double position = 0.0;  ///< position of the load along the structure [m]
  std::string load;       ///< the load's name
  std::string reason;     ///< a word, e.g. left_beam_at_L, lift_off
};

/// Distribution of the structure's nodes over the ranks. Global node indices 0..N-1 follow
/// the structure (node i and i+1 are neighbours along the arclength); every rank owns one
/// contiguous range, the ranges do not overlap and together cover all nodes (a rank may own
/// none).
struct NodeLayout {
  std::size_t global_count = 0;  ///< N, total number of nodes
  std::size_t first = 0;         ///< global index of this rank's first node
  std::size_t count = 0;         ///< number of nodes this rank owns
  std::vector<double> s;         ///< arclength of the local nodes [m], size `count`
};

/// Non-owning view of contiguous doubles (no C++20 std::span). The viewed storage must
/// outlive the call it is passed to.
struct DoubleView {
  const double* data = nullptr;
  std::size_t size = 0;
  DoubleView() = default;
  DoubleView(const double* d, std::size_t n) : data(d), size(n) {}
  DoubleView(const std::vector<double>& v) : data(v.data()), size(v.size()) {}  // NOLINT
  DoubleView(const VecX& v) : data(v.data()), size(static_cast<std::size_t>(v.size())) {}  // NOLINT
};

/// A probe: a time series of one scalar or one small vector, `/probes/<name>`.
struct ProbeSpec {
  std::string name;                          ///< [A-Za-z0-9_.-]+, unique among probes
  std::size_t components = 1;                ///< 1: dataset (steps,); else (steps, components)
  std::string units;                         ///< SI units of the values, e.g. "m", "N"
  std::string description;                   ///< what it measures (free text)
  std::vector<std::string> component_names;  ///< optional, e.g. {"x","y","z"}; empty or size `components`
};

/// A field: values at every node, `/fields/<name>` of shape (steps, nodes, components).
struct FieldSpec {
  std::string name;                          ///< [A-Za-z0-9_.-]+, unique among fields
  std::size_t components = 1;                ///< >= 1
  std::string units;                         ///< SI units, e.g. "m", "rad"
  std::string description;                   ///< what it is (free text)
  std::vector<std::string> component_names;  ///< optional; default "0,1,...". Size `components`
  /// Use this field (3 components: x, y, z in m) as the node positions in the XDMF sidecar.
  /// At most one field may set it. Without one, a 3-component field named "r" is used;
  /// without that, the reference positions /mesh/position. A beam writer provides the field
  /// "position" = (x, w, 0) built from the deflection w and sets this flag.
  bool geometry = false;
  /// Whether the field is an array of the XDMF sidecar (one HDF5 object per output step,
  /// 15-50 us each: docs/output.md). false: only in /fields, e.g. the beam's deflection,
  /// which the beam's geometry (x, w, 0) already shows.
  bool sidecar = true;
};

/// How a restart array is distributed over the ranks.
enum class RestartDistribution {
  per_node,    ///< one row of `components` values per node; each rank passes its node range
  replicated,  ///< same values on every rank; rank 0's are written
};

/// One named array of the `/restart` group.
struct RestartArray {
  std::string name;  ///< [A-Za-z0-9_.-]+, unique within one write_restart call
  RestartDistribution distribution = RestartDistribution::replicated;
  /// per_node: values per node, dataset (nodes,) if 1 else (nodes, components).
  /// replicated: ignored, dataset (size,).
  std::size_t components = 1;
  /// per_node: this rank's nodes, size local count * components, node-major (value of
  /// component c of local node i at i*components + c). replicated: any size, equal on all ranks.
  DoubleView data;
};

}  // namespace traverse::output

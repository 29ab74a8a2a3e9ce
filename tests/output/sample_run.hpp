#pragma once
// A deterministic sample run shared by the output tests (C++ and, by the same formulas,
// tests/output/check_roundtrip.py). All values are exactly representable doubles so that
// read-back can be compared with ==.
#include <mpi.h>

#include <cstddef>
#include <string>
#include <vector>

#include "traverse/output/writer.hpp"

namespace traverse::output::sample {

inline constexpr std::size_t nodes = 7;
inline constexpr std::size_t loads = 2;

inline double time(std::size_t step) { return 0.25 * static_cast<double>(step); }
inline double sigma(std::size_t step, std::size_t load) {
  return 0.5 * static_cast<double>(step) + 10.0 * static_cast<double>(load);
}
inline double s(std::size_t node) { return 0.125 * static_cast<double>(node); }
/// Probe p (0: "midspan_w", 1 comp; 1: "reaction", 3 comps).
inline double probe(std::size_t p, std::size_t step, std::size_t comp) {
  return 100.0 * static_cast<double>(p) + static_cast<double>(step) + 0.25 * static_cast<double>(comp);
}
/// Field f (0: "w" 1 comp; 1: "r" 3 comps; 2: "strain" 6 comps).
inline double field(std::size_t f, std::size_t step, std::size_t node, std::size_t comp) {
  return 1000.0 * static_cast<double>(f) + 10.0 * static_cast<double>(step) +
         0.5 * static_cast<double>(node) + 0.0625 * static_cast<double>(comp);
}
inline constexpr std::size_t field_components[3] = {1, 3, 6};
inline constexpr std::size_t probe_components[2] = {1, 3};

/// Uneven split: rank r of p owns a contiguous range; with 2 ranks 4 + 3 nodes.
inline NodeLayout layout(MPI_Comm comm) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const std::size_t base = nodes / static_cast<std::size_t>(size);
  const std::size_t extra = nodes % static_cast<std::size_t>(size);
  const std::size_t r = static_cast<std::size_t>(rank);
  NodeLayout l;
  l.global_count = nodes;
  l.count = base + (r < extra ? 1 : 0);
  l.first = r * base + std::min(r, extra);
  for (std::size_t i = 0; i < l.count; ++i) l.s.push_back(s(l.first + i));
  return l;
}

inline RunInfo run_info() {
  RunInfo info;
  info.version = "0.1.0-test";
  info.command_line = "traverse --scene bridge.yaml --output out.h5";
  // Longer than HDF5's 64 KiB compact attribute limit on purpose.
  std::string scene = "model: rod\nloads:\n";
  while (scene.size() < 100000) scene += "  - {speed: 27.5, mass: 3.2e4}  # unicode \xc3\xa9\n";
  info.scene_text = scene;
  info.scene_file = "scenes/bridge.yaml";
  info.model = "rod";
  return info;
}

/// Declares the sample probes and fields.
inline void declare(Writer& w) {
  w.add_probe({"midspan_w", 1, "m", "vertical deflection at midspan", {}});
  w.add_probe({"reaction", 3, "N", "support reaction force", {"x", "y", "z"}});
  w.add_field({"w", 1, "m", "vertical deflection", {}, false});
  w.add_field({"r", 3, "m", "centreline position", {"x", "y", "z"}, false});
  w.add_field({"strain", 6, "1", "strain measures", {"g1", "g2", "g3", "k1", "k2", "k3"}, false});
}

/// Writes step `step` of the sample run (collective).
inline void write_step(Writer& w, const NodeLayout& l, std::size_t step) {
  std::vector<double> sig;
  for (std::size_t j = 0; j < loads; ++j) sig.push_back(sigma(step, j));
  std::vector<std::vector<double>> probes(2);
  for (std::size_t p = 0; p < 2; ++p)
    for (std::size_t c = 0; c < probe_components[p]; ++c) probes[p].push_back(probe(p, step, c));
  std::vector<std::vector<double>> local(3);
  for (std::size_t f = 0; f < 3; ++f)
    for (std::size_t i = 0; i < l.count; ++i)
      for (std::size_t c = 0; c < field_components[f]; ++c)
        local[f].push_back(field(f, step, l.first + i, c));
  w.write_step(time(step), sig, probes, {local[0], local[1], local[2]});
}

/// Restart arrays: "state" per node (2 comps) = node + 0.5*comp + step; "loads" replicated.
inline void write_restart(Writer& w, const NodeLayout& l, std::size_t step) {
  std::vector<double> state, rep{1.5, 2.5, static_cast<double>(step)};
  for (std::size_t i = 0; i < l.count; ++i)
    for (std::size_t c = 0; c < 2; ++c)
      state.push_back(static_cast<double>(l.first + i) + 0.5 * static_cast<double>(c) +
                      static_cast<double>(step));
  w.write_restart(time(step), {{"state", RestartDistribution::per_node, 2, state},
                               {"loads", RestartDistribution::replicated, 1, rep}});
}

}  // namespace traverse::output::sample

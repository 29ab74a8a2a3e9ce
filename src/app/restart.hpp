#pragma once
// The scene of a restarted run (docs/reliability.md, "Restart"); the restart points
// themselves are the output module's (traverse/output/restart.hpp).
#include <mpi.h>

#include <chrono>
#include <string>
#include <vector>

#include "traverse/output/restart.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

/// The scene of a restart: `scene_file` (with `overrides`) when given, else the scene text
/// stored in the restart source (root attribute `scene`) with `overrides`. Throws
/// UsageError if the file cannot be read as a traverse output, SceneError for bad overrides.
scene::Scene restart_scene(const std::string& path, const std::string& scene_file,
                           const std::vector<std::string>& overrides);

/// The newest restart point of `source` for `--restart output` of a rod run with `components`
/// values per node (`other`: those of the other kind, fixed dt or time.adaptive, which gets a
/// UsageError saying so); its extra[dt_index] must be time.dt = `dt` (UsageError otherwise).
output::RestartPoint read_rod_restart_point(const std::string& output, const std::string& source, std::size_t nodes,
                                            std::size_t components, std::size_t other, bool adaptive, double dt,
                                            std::size_t dt_index);

/// Whether `interval` seconds of wall time have passed since `last` (interval <= 0: always);
/// rank 0's clock decides for all (collective).
bool restart_due(std::chrono::steady_clock::time_point last, double interval, MPI_Comm comm);

}  // namespace traverse::app

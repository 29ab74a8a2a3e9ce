#include "restart.hpp"

#include "cli.hpp"
#include "traverse/core/comm.hpp"

namespace traverse::app {

scene::Scene restart_scene(const std::string& path, const std::string& scene_file,
                           const std::vector<std::string>& overrides) {
  const std::string source = output::restart_source(path);
  std::string text, name;
  try {
    output::Reader r(source);
    text = r.attribute("scene");
    name = r.has_attribute("scene_file") ? r.attribute("scene_file") : std::string("scene");
  } catch (const output::OutputError& e) {
    throw UsageError{"--restart " + path + ": cannot read it as a traverse output file (" + e.what() + ")"};
  }
  if (!scene_file.empty()) return scene::load_scene(scene_file, overrides);
  return scene::parse_scene(text, name + " (as stored in " + source + ")", overrides);
}

output::RestartPoint read_rod_restart_point(const std::string& output, const std::string& source, std::size_t nodes,
                                            std::size_t components, std::size_t other, bool adaptive, double dt,
                                            std::size_t dt_index) {
  output::RestartPoint point;
  try {
    point = output::read_restart_point(source, nodes, components);
  } catch (const output::RestartError&) {
    // A point of the other kind (adaptive or fixed dt) says what changed.
    bool other_kind = true;
    try {
      (void)output::read_restart_point(source, nodes, other);
    } catch (const output::RestartError&) {
      other_kind = false;
    }
    if (!other_kind) throw;  // the first error, as it was
    throw UsageError{"--restart " + output + ": the run being restarted " +
                     (adaptive ? "took fixed steps" : "was adaptive (time.adaptive)") + "; a restart keeps it " +
                     (adaptive ? "so: no time.adaptive" : "so: keep time.adaptive")};
  }
  const auto& x = point.extra;
  if (x.size() <= dt_index || x[dt_index] != dt)
    throw UsageError{"--restart " + output + ": time.dt = " + scene::format_number(dt) +
                     " s differs from the run being restarted (" +
                     (x.size() <= dt_index ? std::string("unknown") : scene::format_number(x[dt_index])) +
                     " s); a restart keeps the time step"};
  return point;
}

bool restart_due(std::chrono::steady_clock::time_point last, double interval, MPI_Comm comm) {
  if (interval <= 0.0) return true;
  int due = std::chrono::duration<double>(std::chrono::steady_clock::now() - last).count() >= interval;
  par::bcast(&due, 1, MPI_INT, 0, comm);
  return due != 0;
}

}  // namespace traverse::app

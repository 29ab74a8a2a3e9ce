#include "restart.hpp"

#include "cli.hpp"

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

}  // namespace traverse::app

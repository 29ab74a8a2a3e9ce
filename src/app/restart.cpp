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

void pack_node(const rod::RodNode& nd, double* o) {
  for (int i = 0; i < 12; ++i) o[i] = nd.y(i);
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c) o[12 + 3 * i + c] = nd.R(i, c);
  for (int i = 0; i < 12; ++i) o[21 + i] = nd.yt(i);
  for (int i = 0; i < 12; ++i) o[33 + i] = nd.ys(i);
}

rod::RodNode unpack_node(const double* o) {
  rod::RodNode nd;
  for (int i = 0; i < 12; ++i) nd.y(i) = o[i];
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c) nd.R(i, c) = o[12 + 3 * i + c];
  for (int i = 0; i < 12; ++i) nd.yt(i) = o[21 + i];
  for (int i = 0; i < 12; ++i) nd.ys(i) = o[33 + i];
  return nd;
}

}  // namespace traverse::app

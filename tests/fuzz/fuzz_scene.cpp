// libFuzzer target: the scene reader and validator on arbitrary bytes.
// Contract: traverse::scene::parse_scene either returns a Scene or throws
// traverse::scene::SceneError; anything else (another exception, a crash, a leak, a
// sanitizer report, a hang) is a bug. Inputs whose first line starts with "#set " also
// exercise the --set path: the rest of that line is one override "key.path=value".
// Built only with -DTRAVERSE_FUZZ=ON (clang); run with scripts/fuzz.sh.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "traverse/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  if (text.rfind("#set ", 0) == 0) {
    const std::size_t eol = text.find('\n');
    overrides.push_back(text.substr(5, eol == std::string::npos ? std::string::npos : eol - 5));
  }
  try {
    const traverse::scene::Scene sc = traverse::scene::parse_scene(text, "fuzz.yaml", overrides);
    // A valid scene must also describe itself and survive a round trip through that text.
    const std::string described = traverse::scene::describe_scene(sc, false);
    (void)traverse::scene::parse_scene(described, "fuzz-described.yaml");
  } catch (const traverse::scene::SceneError&) {
    // the only allowed failure
  }
  return 0;
}

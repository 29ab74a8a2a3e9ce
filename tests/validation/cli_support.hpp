#pragma once
// What the validation tests that drive the executable share: running it, reading what it
// wrote, the scene folder and a scratch folder. TRAVERSE_EXE, TRAVERSE_SOURCE_DIR and
// TRAVERSE_BINARY_DIR are the test target's compile definitions.
#include <filesystem>
#include <string>
#include <vector>

#include "h5_dataset.hpp"
#include "process.hpp"

namespace traverse::testing {

/// `traverse ARGS`: its exit code; its output into `out` when given.
inline int run_traverse(const std::string& args, std::string* out = nullptr) {
  const auto r = run_command(std::string(TRAVERSE_EXE) + " " + args);
  if (out) *out = r.out;
  return r.code;
}

/// The repository's scenes.
inline std::filesystem::path inputs_dir() { return std::filesystem::path(TRAVERSE_SOURCE_DIR) / "inputs"; }

/// test-scratch/NAME in the build tree, made if missing.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto d = std::filesystem::path(TRAVERSE_BINARY_DIR) / "test-scratch" / name;
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace traverse::testing

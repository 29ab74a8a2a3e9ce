#pragma once
// Command line of the traverse executable.
#include <string>
#include <vector>

#include "traverse/setup/run_limits.hpp"
#include "sweep_spec.hpp"

namespace traverse::app {

/// Exit codes (documented in README.md and `traverse --help`).
enum ExitCode : int {
  kSuccess = 0,
  kOtherError = 1,    ///< anything else (a bug, an unexpected system error)
  kBadInput = 2,      ///< scene, overrides, command line or output path
  kNumericsFailed = 3,  ///< non-convergence after the allowed retries
};


struct CommandLine {
  enum class Command { Help, Version, Run, Check, Xdmf, Sweep };
  Command command = Command::Help;
  std::string scene;                   ///< scene file (xdmf: the output file)
  std::string output;                  ///< -o (empty: the scene's output.file; sweep: the output directory)
  std::string restart;                 ///< --restart FILE: continue the run of FILE (run only)
  double restart_interval = -1.0;      ///< --restart-interval S: wall seconds between restart points (-1: the scene's)
  std::vector<std::string> overrides;  ///< --set KEY.PATH=VALUE, in order
  bool overwrite = false;
  bool quiet = false;
  bool verbose = false;                ///< -v: run also prints its plan (time steps, memory, output size)
  bool progress = false;               ///< --progress: report progress even when not a terminal
  bool types = false;                  ///< check --types: also document every registered type
  std::vector<VaryOption> vary;        ///< sweep --vary KEY=v1,v2,..., in order
  SummarySpec summary;                 ///< sweep --summary PROBE[.c]:REDUCTION
  setup::RunLimits limits;                    ///< --max-memory, --max-steps (run and check)
  std::string invocation;              ///< the whole command line, for the output file
};

/// Thrown for a malformed command line (exit code 2).
struct UsageError {
  std::string message;
};

CommandLine parse_command_line(int argc, const char* const* argv);

std::string usage_text();

}  // namespace traverse::app

#include "cli.hpp"

#include <cmath>
#include <cstdlib>

namespace traverse::app {

std::string usage_text() {
  return R"(traverse: slender elastic structures under moving loads

Usage:
  traverse run SCENE.yaml [-o OUT.h5] [--set KEY.PATH=VALUE ...] [--overwrite] [-q | -v] [--progress]
               [--restart-interval S] [--max-memory SIZE] [--max-steps N]
  traverse run --restart OUT.h5 [SCENE.yaml] [--set KEY.PATH=VALUE ...] [-q] [--progress]
  traverse check SCENE.yaml [--set KEY.PATH=VALUE ...] [--types] [--max-memory SIZE] [--max-steps N]
  traverse sweep SCENE.yaml -o DIR --vary KEY=v1,v2,... [--with KEY=...] [--vary KEY=a:b:step ...] [--set ...]
               [--summary PROBE[.x|.y|.z]:REDUCTION] [--overwrite] [-q] [--max-memory SIZE] [--max-steps N]
  traverse xdmf OUT.h5 [-o OUT.xmf]
  traverse --help | --version
  mpirun -n K traverse run SCENE.yaml ...      (K MPI ranks)
  mpirun -n K traverse sweep SCENE.yaml ...    (the cases spread over K ranks, one rank each)

Commands:
  run      validate the scene, run it, write the HDF5 output (and its .xmf sidecar)
  check    validate only and print the complete scene, every default filled in and
           documented (--types: also list every end-condition, load, probe and section type)
  sweep    run the scene once per case of the cartesian product of the --vary options,
           in one process (or spread over the MPI ranks): DIR/case_NNNN.h5 per case and DIR/index.csv (case, each varied
           value, output, status, exit code, wall time, the --summary value); a failed
           case is recorded and the others go on; the exit code is 0 when every case
           completed, else that of the first failed case (docs/sweeps.md)
  xdmf     (re)write the XDMF sidecar of an output file (any run's, a killed one's too) from
           the file alone, for ParaView and meshio (docs/output.md)

Options:
  -o, --output FILE   output file (default: the scene's output.file)
  --set KEY=VALUE     override any scene key, e.g. --set loads.mass.speed=100 (repeatable;
                      VALUE in YAML syntax, e.g. --set output.fields=[deflection])
  --vary KEY=VALUES   sweep: the values of one key, comma-separated YAML values and ranges
                      a:b:step (a, a + step, ... up to b), e.g. --vary loads.F.speed=1:3:0.5
  --with KEY=VALUES   sweep: a key varied together with the --vary before it (as many values:
                      the i-th value of each in the same case), e.g. an end time for each speed
  --summary P:R       sweep: the index's scalar of each case, reduction R (min, max, absmax,
                      mean, final) of probe P over the output steps (P.x, P.y, P.z: one
                      component), e.g. --summary midspan.y:min
  --overwrite         replace an existing output file (sweep: the index and case files)
  -q, --quiet         no progress, no summary
  -v, --verbose       run: also print the plan before the run (time steps, memory and
                      output size estimates, the output stride and why: what check prints)
  --progress          report progress on stderr even when it is not a terminal
  --restart FILE      continue the run whose output is FILE (killed, interrupted or failed)
                      from its last restart point, appending to FILE; the scene is the one
                      stored in FILE unless SCENE.yaml is given (--set applies either way)
  --restart-interval S  rod runs: store a restart point after an output step only when S
                      seconds (wall clock) have passed since the last one (default: the
                      scene's output.restart_interval, 60 s; 0: after every output step);
                      always also at the end and when the run stops (signal, failure)
  --max-memory SIZE   refuse (exit 2) a run whose estimated memory per rank exceeds SIZE
                      (e.g. 4G, 512M; K, M, G, T are powers of 1024; default: the memory
                      available on this host, shared by the ranks on it)
  --max-steps N       refuse (exit 2) a run of more than N time steps (default 10000000;
                      2^32 is the most a time grid resolves)

Before anything large is allocated, run and check estimate the run's time steps and memory
per rank and refuse what exceeds the limits, with the keys that decide it
(docs/reliability.md, "Limits").

Ctrl-C (SIGINT) or SIGTERM stops a run after the current time step: the output keeps
every step written, its status says "interrupted at t = ...", the exit code is 130
(SIGINT) or 143 (SIGTERM); continue it with --restart. A second Ctrl-C kills at once.

Exit codes: 0 success; 2 bad input (scene, overrides, command line, output path);
            3 the numerics failed; 130/143 stopped by SIGINT/SIGTERM; 1 anything else.
)";
}

namespace {

// The options of `xdmf` (a Help command for --help).
void parse_xdmf(int argc, const char* const* argv, CommandLine& cl) {
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      cl.command = CommandLine::Command::Help;
      return;
    } else if ((a == "-o" || a == "--output") && i + 1 < argc && argv[i + 1][0] != '\0') {
      cl.output = argv[++i];
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError{"'xdmf': unknown option or missing value '" + a + "'"};
    } else if (cl.scene.empty()) {
      cl.scene = a;
    } else {
      throw UsageError{"'xdmf': expected one output file, found a second one '" + a + "'"};
    }
  }
  if (cl.scene.empty()) throw UsageError{"'xdmf': expected an output file (OUT.h5), found none"};
}

// What a complete command line needs beyond its options.
CommandLine& checked(CommandLine& cl, const std::string& cmd) {
  if (!cl.restart.empty()) {
    if (cl.overwrite) throw UsageError{"--overwrite: not allowed with --restart (the restart continues " + cl.restart + ")"};
    if (!cl.output.empty() && cl.output != cl.restart)
      throw UsageError{"-o " + cl.output + ": not allowed with --restart (the restart appends to " + cl.restart + ")"};
    return cl;
  }
  if (cl.scene.empty()) throw UsageError{"'" + cmd + "': expected a scene file, found none"};
  if (cl.command == CommandLine::Command::Sweep) {
    if (cl.output.empty()) throw UsageError{"'sweep': expected -o DIR, the directory of the case files and the index, found none"};
    if (cl.vary.empty()) throw UsageError{"'sweep': expected at least one --vary KEY=v1,v2,..., found none"};
  }
  return cl;
}

}  // namespace

CommandLine parse_command_line(int argc, const char* const* argv) {
  CommandLine cl;
  for (int i = 0; i < argc; ++i) cl.invocation += (i ? " " : "") + std::string(argv[i]);
  if (argc < 2) throw UsageError{"expected a command (run, check, sweep, xdmf, --help or --version), found nothing"};
  const std::string cmd = argv[1];
  if (cmd == "--help" || cmd == "-h" || cmd == "help") {
    cl.command = CommandLine::Command::Help;
    return cl;
  }
  if (cmd == "--version") {
    cl.command = CommandLine::Command::Version;
    return cl;
  }
  if (cmd == "run") {
    cl.command = CommandLine::Command::Run;
  } else if (cmd == "check") {
    cl.command = CommandLine::Command::Check;
  } else if (cmd == "sweep") {
    cl.command = CommandLine::Command::Sweep;
  } else if (cmd == "xdmf") {
    cl.command = CommandLine::Command::Xdmf;
    parse_xdmf(argc, argv, cl);
    return cl;
  } else {
    throw UsageError{"expected a command (run, check, sweep, xdmf, --help or --version), found '" + cmd + "'"};
  }
  const bool sweep = cl.command == CommandLine::Command::Sweep;
  const bool run = cl.command == CommandLine::Command::Run || sweep;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const std::string& opt) -> std::string {
      if (i + 1 >= argc) throw UsageError{opt + ": expected a value after it, found nothing"};
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      cl.command = CommandLine::Command::Help;
      return cl;
    } else if (a == "--set") {
      cl.overrides.push_back(value(a));
    } else if (a.rfind("--set=", 0) == 0) {
      cl.overrides.push_back(a.substr(6));
    } else if (run && (a == "-o" || a == "--output")) {
      cl.output = value(a);
      if (cl.output.empty()) throw UsageError{a + ": expected a file name, found an empty string"};
    } else if (sweep && a == "--vary") {
      cl.vary.push_back(parse_vary(value(a)));
    } else if (sweep && a.rfind("--vary=", 0) == 0) {
      cl.vary.push_back(parse_vary(a.substr(7)));
    } else if (sweep && a == "--with") {
      cl.vary.push_back(parse_vary(value(a), a));
      cl.vary.back().with_previous = true;
    } else if (sweep && a == "--summary") {
      cl.summary = parse_summary(value(a));
    } else if (run && !sweep && a == "--restart") {
      cl.restart = value(a);
      if (cl.restart.empty()) throw UsageError{a + ": expected the output file to continue, found an empty string"};
    } else if (run && !sweep && a == "--restart-interval") {
      const std::string v = value(a);
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0' || !(x >= 0.0) || !std::isfinite(x))
        throw UsageError{a + ": expected a number of seconds >= 0, found '" + v + "'"};
      cl.restart_interval = x;
    } else if (a == "--max-memory") {
      const std::string v = value(a);
      const double bytes = setup::parse_bytes(v);
      if (!(bytes >= 1.0))
        throw UsageError{a + ": expected a size such as 4G, 512M or 1000000 (bytes; K, M, G, T are powers of 1024), found '" +
                         v + "'"};
      cl.limits.max_memory = bytes;
    } else if (a == "--max-steps") {
      const std::string v = value(a);
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0' || !(x >= 1.0) || x != std::floor(x) || !(x <= kMaxGridSteps))
        throw UsageError{a + ": expected a whole number of time steps in [1, 4294967296], found '" + v + "'"};
      cl.limits.max_steps = static_cast<long>(x);
    } else if (run && a == "--overwrite") {
      cl.overwrite = true;
    } else if (run && (a == "-q" || a == "--quiet")) {
      cl.quiet = true;
    } else if (run && !sweep && (a == "-v" || a == "--verbose")) {
      cl.verbose = true;
    } else if (run && !sweep && a == "--progress") {
      cl.progress = true;
    } else if (!run && a == "--types") {
      cl.types = true;
    } else if (!a.empty() && a[0] == '-') {
      throw UsageError{"'" + cmd + "': unknown option '" + a + "'"};
    } else if (cl.scene.empty()) {
      cl.scene = a;
    } else {
      throw UsageError{"'" + cmd + "': expected one scene file, found a second one '" + a + "'"};
    }
  }
  return checked(cl, cmd);
}

}  // namespace traverse::app

// libFuzzer target: the scene reader and validator, and the up-front limits of a run.
//
// Two kinds of input:
//  * text (the first byte is below 0x80): arbitrary bytes -> traverse::scene::parse_scene,
//    which either returns a Scene or throws traverse::scene::SceneError; a valid scene must
//    also describe itself and survive a round trip through that text. An input whose first
//    line starts with "#set " also exercises the --set path: the rest of that line is one
//    override "key.path=value".
//  * extreme values (the first byte is 0x80 or above): valid YAML with valid types. The
//    bytes choose one of four small base scenes (two beams, two rods) and up to six
//    overrides "key=value" from tables of keys and of extreme values (0, denormals, 1e-300,
//    1e300, the largest double, the integer limits, ...) or a raw double; the scene is
//    parsed and put through the checks of a run (setup/run_limits.hpp: load ratio, memory,
//    counters, time grid). Their invariants are asserted: an accepted grid has a whole
//    number of steps in [1, limit] whose times increase and end at t_end. With
//    TRAVERSE_FUZZ_EXE set to a traverse executable, the scene is then also run by it
//    (refused scenes, and accepted ones cheap enough to run in well under a second): its
//    exit code must be 0, 2 or 3, a scene refused here must be refused there (2), exit 2
//    must leave no output file, and a completed run must report the steps and output steps
//    the plan says. A crash, another exception, a sanitizer report, an exit code or a
//    count that breaks these rules, or a run longer than kChildSeconds is a finding.
// Built only with -DTRAVERSE_FUZZ=ON (clang); run with scripts/fuzz.sh.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include "traverse/setup/run_limits.hpp"
#include "traverse/scene/scene.hpp"

namespace {

namespace fs = std::filesystem;
using traverse::scene::Scene;
using traverse::scene::SceneError;

// The executable's limits during fuzzing: small enough that every accepted run is cheap.
constexpr long kFuzzMaxSteps = 2000;
constexpr double kFuzzMaxMemory = 1024.0 * 1024.0 * 1024.0;  // --max-memory 1G
constexpr double kChildSeconds = 15.0;                        // a run longer than this is a hang

struct Base {
  const char* text;
  std::vector<const char*> keys;  // the keys the overrides may set
};

// Four small scenes; the load is always called L.
const std::vector<Base>& bases() {
  static const std::vector<Base> b = {
      {R"(model: beam
beam: {length: 2.0, youngs_modulus: 2.0e11, density: 7850, section: {type: hollow_circle, outer_radius: 0.1, inner_radius: 0.05}, supports: clamped-free, modes: 3}
mesh: {nodes: 21}
loads:
  L: {type: moving_mass, mass_fraction: 0.2, speed: 50}
time: {dt: 1.0e-4}
output: {every: 10, probes: {tip: {type: deflection, at: 2.0}}}
)",
       {"time.dt", "time.end", "loads.L.entry_time", "loads.L.speed", "loads.L.acceleration", "loads.L.start",
        "loads.L.mass_fraction", "gravity", "output.every", "mesh.nodes", "beam.length", "beam.youngs_modulus",
        "beam.density", "beam.modes", "beam.quadrature_points", "beam.section.outer_radius"}},
      {R"(model: beam
beam: {length: 10.0, youngs_modulus: 2.0e11, density: 7850, section: {type: rectangle, width: 0.1, height: 0.2}, supports: simply-supported, modes: 4, integrator: newmark}
mesh: {ds: 1.0}
loads:
  L: {type: moving_force, force: 1000.0, speed: 20.0}
output: {fields: [deflection]}
)",
       {"time.dt", "time.end", "loads.L.entry_time", "loads.L.speed", "loads.L.acceleration", "loads.L.start",
        "loads.L.force", "gravity", "output.every", "mesh.ds", "beam.length", "beam.youngs_modulus", "beam.density",
        "beam.modes", "beam.section.height"}},
      {R"(model: rod
gravity: 9.8
rod: {length: 1.0, youngs_modulus: 2.5e8, poisson_ratio: 0.25, density: 1500, section: {type: solid_circle, radius: 0.005}}
ends: {left: {type: clamped}, right: {type: sliding, axis: [0, 0, 1]}}
mesh: {ds: 0.1}
initial_state: {type: static}
loads:
  L: {type: moving_force, force: 2.0, speed: 3.63418}
output: {probes: {mid: {type: point, at: 0.5, quantity: position}}}
)",
       {"time.dt", "time.end", "loads.L.entry_time", "loads.L.speed", "loads.L.acceleration", "loads.L.start",
        "loads.L.force", "gravity", "output.every", "mesh.ds", "rod.length", "rod.youngs_modulus", "rod.density",
        "rod.section.radius", "scheme.rho_inf", "scheme.rho_inf_space"}},
      {R"(model: rod
gravity: 9.8
rod: {length: 1.0, youngs_modulus: 2.5e8, shear_modulus: 1.0e8, density: 1500, section: {type: rectangle, width: 0.01, height: 0.005}}
ends: {left: {type: pinned}, right: {type: roller}}
mesh: {nodes: 11}
initial_state: {type: rest}
loads:
  L: {type: moving_mass, mass: 0.1, speed: 1.0}
time: {dt: 0.01, end: 0.5}
output: {fields: [r]}
)",
       {"time.dt", "time.end", "loads.L.entry_time", "loads.L.speed", "loads.L.acceleration", "loads.L.start",
        "loads.L.mass", "gravity", "output.every", "mesh.nodes", "rod.length", "rod.youngs_modulus", "rod.density",
        "rod.shear_modulus", "ends.right.force", "scheme.rho_inf"}},
  };
  return b;
}

// Extreme values (and a few ordinary ones to combine them with).
const std::vector<double>& values() {
  static const std::vector<double> v = {0.0, -1.0, 4.9e-324, 2.2250738585072014e-308, 1e-300, 1e-30, 1e-12, 1e-9,
                                        1e-6, 1e-3, 0.5, 1.0, 2.0, 3.0, 10.0, 100.0, 1e3, 1e6, 1e7, 1e7 + 1, 1e9, 1e12,
                                        4.5e15, 1e18, 1e30, 1e300, std::numeric_limits<double>::max(),
                                        2147483646.0, 2147483647.0, 2147483648.0, 4294967296.0, 9.3e18,
                                        std::numeric_limits<double>::infinity(),
                                        std::numeric_limits<double>::quiet_NaN(), 0.999999999999, 0.25};
  return v;
}

std::string yaml_number(double x) {
  if (std::isnan(x)) return ".nan";
  if (std::isinf(x)) return x > 0 ? ".inf" : "-.inf";
  char buf[40];
  if (x == std::floor(x) && std::abs(x) < 1e16) std::snprintf(buf, sizeof buf, "%.0f", x);
  else std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

// A decoded extreme-value input.
struct Extreme {
  std::size_t base = 0;
  std::vector<std::string> overrides;
};

Extreme decode(const std::uint8_t* data, std::size_t size) {
  Extreme e;
  std::size_t i = 1;
  auto byte = [&]() -> unsigned { return i < size ? data[i++] : 0u; };
  e.base = byte() % bases().size();
  const auto& keys = bases()[e.base].keys;
  const int count = static_cast<int>(byte() % 7);
  for (int k = 0; k < count && i < size; ++k) {
    const std::string key = keys[byte() % keys.size()];
    const unsigned which = byte();
    double x = 0.0;
    if (which % 8 == 7 && i + 8 <= size) {  // a raw double
      std::memcpy(&x, data + i, 8);
      i += 8;
    } else {
      x = values()[which % values().size()];
      if (which & 0x80) x = -x;
    }
    e.overrides.push_back(key + "=" + yaml_number(x));
  }
  return e;
}

// The checks of a run, as the executable makes them with --max-memory 1G --max-steps 2000.
// Memory is estimated for both paths of a rod (the executable decides planar or 3D from the
// model); `refused` is certain only when both estimates exceed the limit.
struct Plan {
  bool refused = false;    // certainly refused (exit 2)
  bool uncertain = false;  // refused on one path estimate only
  traverse::setup::TimePlan time;
  std::string why;
};

Plan plan_of(const Scene& sc) {
  namespace setup = traverse::setup;
  Plan p;
  const setup::MemoryLimit limit{kFuzzMaxMemory, "fuzzing"};
  try {
    setup::check_properties(sc);
    setup::check_load_ratio(sc);
    if (sc.model == traverse::scene::Model::Beam) {
      setup::check_memory(sc, setup::beam_memory(sc, 1), limit);
      setup::check_load_speeds(sc);
      p.time = setup::beam_time_plan(sc);
    } else {
      const double three_d = setup::rod_memory(sc, {false, 1}).bytes, planar = setup::rod_memory(sc, {true, 1}).bytes;
      if (!(planar <= three_d))
        throw std::logic_error("fuzz: the planar estimate " + std::to_string(planar) + " exceeds the 3D one " +
                               std::to_string(three_d));
      setup::check_memory(sc, setup::rod_memory(sc, {true, 1}), limit);
      if (three_d > kFuzzMaxMemory) p.uncertain = true;
      setup::check_counters(sc, {false, 1});
      setup::check_load_speeds(sc);
      p.time = setup::rod_time_plan(sc);
    }
    setup::check_time_plan(sc, p.time, kFuzzMaxSteps);
  } catch (const SceneError& e) {
    p.refused = true;
    p.why = e.what();
    return p;
  }
  // The grid's invariants: a whole number of steps in [1, limit], increasing times, the last at t_end.
  const traverse::TimeGrid& g = p.time.grid;
  if (g.steps < 1 || g.steps > kFuzzMaxSteps || g.time(g.steps) != g.t_end || !(g.time(1) > 0.0))
    throw std::logic_error("fuzz: bad grid: " + std::to_string(g.steps) + " steps");
  for (long k : {1L, g.steps - 1, g.steps}) {
    if (k < 1) continue;
    const double h = g.time(k) - g.time(k - 1);
    const bool ok = k == g.steps ? h > 0.0 && h <= g.dt * (1.0 + 1e-6) : std::abs(h - g.dt) <= 1e-6 * g.dt;
    if (!ok)
      throw std::logic_error("fuzz: step " + std::to_string(k) + " of " + std::to_string(g.steps) + " has length " +
                             std::to_string(h) + " s, dt = " + std::to_string(g.dt) + " s");
  }
  return p;
}

// Whether an accepted scene is cheap enough to run through the executable (the output file
// is flushed, and its XDMF sidecar rewritten, at every output step: those count most).
bool cheap(const Scene& sc, const Plan& p) {
  const double steps = static_cast<double>(p.time.grid.steps), nodes = sc.mesh.nodes;
  if (steps / sc.output.every > 200.0) return false;
  if (sc.model == traverse::scene::Model::Beam) {
    const double modes = sc.beam.modes;
    return nodes <= 5000 && steps * modes * modes <= 2e7 && nodes * modes * sc.beam.quadrature_points <= 2e6;
  }
  return nodes <= 200 && nodes * steps <= 20000;
}

// Runs argv with stdout and stderr into one string; the exit code, -signal, or aborts on a hang.
int run_child(const std::vector<std::string>& args, std::string& out) {
  int fd[2];
  if (pipe(fd) != 0) std::abort();
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(fd[1], 1);
    dup2(fd[1], 2);
    close(fd[0]);
    close(fd[1]);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(fd[1]);
  const auto start = std::chrono::steady_clock::now();
  char buf[4096];
  while (true) {
    pollfd p{fd[0], POLLIN, 0};
    const int ready = poll(&p, 1, 200);
    if (ready > 0) {
      const ssize_t n = read(fd[0], buf, sizeof buf);
      if (n <= 0) break;
      out.append(buf, static_cast<std::size_t>(n));
    }
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > kChildSeconds) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
      std::string cmd;
      for (const auto& a : args) cmd += a + " ";
      std::fprintf(stderr, "fuzz finding: the run took over %.0f s (a hang)\ncommand: %s\noutput:\n%s\n", kChildSeconds,
                   cmd.c_str(), out.c_str());
      std::abort();
    }
  }
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

[[noreturn]] void finding(const std::string& what, const std::vector<std::string>& args, const std::string& out) {
  std::string cmd;
  for (const auto& a : args) cmd += a + " ";
  std::fprintf(stderr, "fuzz finding: %s\ncommand: %s\noutput:\n%s\n", what.c_str(), cmd.c_str(), out.c_str());
  std::abort();
}

long number_after(const std::string& out, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(pattern))) return -1;
  return std::stol(m[1].str());
}

// The executable on the scene: exit codes and counts against the plan.
void run_executable(const char* exe, const Extreme& e, const Scene& sc, const Plan& plan) {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("traverse-fuzz-" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
  }();
  const fs::path scene = dir / "fuzz.yaml", output = dir / "fuzz.h5";
  {
    std::ofstream f(scene);
    f << bases()[e.base].text;
  }
  fs::remove(output);
  fs::remove(dir / "fuzz.xmf");
  std::vector<std::string> args = {exe, "run", scene.string(), "-o", output.string(), "--max-memory", "1G",
                                   "--max-steps", std::to_string(kFuzzMaxSteps)};
  for (const auto& o : e.overrides) {
    args.push_back("--set");
    args.push_back(o);
  }
  std::string out;
  const int code = run_child(args, out);
  if (code != 0 && code != 2 && code != 3) finding("exit code " + std::to_string(code), args, out);
  if (code == 2 && fs::exists(output)) finding("exit 2 left an output file", args, out);
  if (plan.refused && code != 2) finding("refused by the checks (" + plan.why + ") but exit " + std::to_string(code), args, out);
  if (code != 0 || plan.refused) return;
  const long N = plan.time.grid.steps, every = sc.output.every;
  const long outputs = 1 + N / every + (N % every != 0 ? 1 : 0);
  if (number_after(out, "([0-9]+) output steps") != outputs)
    finding("expected " + std::to_string(outputs) + " output steps of " + std::to_string(N) + " steps", args, out);
  const long reported = number_after(out, "([0-9]+) steps of dt");
  const long loads = static_cast<long>(sc.loads.size());
  const bool beam = sc.model == traverse::scene::Model::Beam;
  if (beam ? (reported < N || reported > N + 2 * loads) : reported != N)
    finding("expected " + std::to_string(N) + " steps, the run reported " + std::to_string(reported), args, out);
}

void fuzz_extreme(const std::uint8_t* data, std::size_t size) {
  const Extreme e = decode(data, size);
  Plan plan;
  Scene sc;
  try {
    sc = traverse::scene::parse_scene(bases()[e.base].text, "fuzz.yaml", e.overrides);
  } catch (const SceneError&) {
    return;  // refused by the validator (exit 2): the text mode covers that path
  }
  plan = plan_of(sc);
  const char* exe = std::getenv("TRAVERSE_FUZZ_EXE");
  if (!exe || !*exe || plan.uncertain) return;
  if (plan.refused || cheap(sc, plan)) run_executable(exe, e, sc, plan);
}

void fuzz_text(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  if (text.rfind("#set ", 0) == 0) {
    const std::size_t eol = text.find('\n');
    overrides.push_back(text.substr(5, eol == std::string::npos ? std::string::npos : eol - 5));
  }
  try {
    const Scene sc = traverse::scene::parse_scene(text, "fuzz.yaml", overrides);
    // A valid scene must also describe itself and survive a round trip through that text.
    const std::string described = traverse::scene::describe_scene(sc, false);
    (void)traverse::scene::parse_scene(described, "fuzz-described.yaml");
  } catch (const SceneError&) {
    // the only allowed failure
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 0 && data[0] >= 0x80) fuzz_extreme(data, size);
  else fuzz_text(data, size);
  return 0;
}

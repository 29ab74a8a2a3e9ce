// The traverse executable as a user meets it: exit codes, --help, --version, --set,
// refusal to overwrite, and the data-driven bad-input suite (tests/app/bad_input/*.yaml:
// each file is a scene whose first lines say the message fragment expected
// ("# expect: ...") and any extra command-line arguments ("# args: ...")).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "process.hpp"
#include "traverse/output/reader.hpp"

using traverse::testing::scratch;

namespace fs = std::filesystem;
using traverse::output::Reader;

namespace {

using Result = traverse::testing::RunResult;

Result run_with(const std::string& prefix, const std::string& args);
Result run(const std::string& args) { return run_with("", args); }

const fs::path kScene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "beam" / "cantilever.yaml";
const fs::path kCable = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "rod" / "hanging_cable_F2_a0.5.yaml";
// The cable at a coarse spacing (21 nodes, 20 steps).
const std::string kCoarse = " --set mesh.ds=0.05 -q";

std::string mpirun(int ranks) {
  return "mpiexec --allow-run-as-root --oversubscribe -n " + std::to_string(ranks) + " ";
}

Result run_with(const std::string& prefix, const std::string& args) {
  return traverse::testing::run_command(prefix + std::string(TRAVERSE_EXE) + " " + args);
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return 1e300;
  double m = 0.0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}
// A short, cheap version of the scene for runs.
const std::string kFast = " --set beam.modes=2 --set time.dt=1e-4 --set output.every=50 -q";

}  // namespace

TEST(Cli, HelpAndVersion) {
  auto r = run("--help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("traverse run SCENE.yaml"), std::string::npos);
  EXPECT_NE(r.out.find("Exit codes"), std::string::npos);
  r = run("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_TRUE(std::regex_search(r.out, std::regex("^traverse [0-9]+\\.[0-9]+\\.[0-9]+")));
}

TEST(Cli, CommandLineErrorsExitWithCode2) {
  for (const auto& [args, fragment] : std::vector<std::pair<std::string, std::string>>{
           {"", "expected a command"},
           {"fly", "found 'fly'"},
           {"run", "expected a scene file, found none"},
           {"run a.yaml b.yaml", "found a second one 'b.yaml'"},
           {"run " + kScene.string() + " --frobnicate", "unknown option '--frobnicate'"},
           {"run " + kScene.string() + " -o", "-o: expected a value after it"},
           {"check " + kScene.string() + " --overwrite", "unknown option '--overwrite'"},
           {"run /no/such/scene.yaml", "/no/such/scene.yaml: expected a readable scene file, found no such file"},
           {"run " + kScene.string() + " --max-memory lots", "--max-memory: expected a size such as 4G"},
           {"run " + kScene.string() + " --max-memory 0", "--max-memory: expected a size such as 4G"},
           {"check " + kScene.string() + " --max-steps 0", "--max-steps: expected a whole number of time steps in [1, 4294967296]"},
           {"run " + kScene.string() + " --max-steps 1e20", "found '1e20'"},
           {"run " + kScene.string() + " --max-steps 2.5", "found '2.5'"},
       }) {
    const auto r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(fragment), std::string::npos) << args << "\n" << r.out;
  }
}

TEST(Cli, CheckPrintsTheCompleteDocumentedScene) {
  auto r = run("check " + kScene.string() + " --set beam.modes=5");
  EXPECT_EQ(r.code, 0) << r.out;
  for (const char* f : {"valid", "modes: 5", "Number of Galerkin modes", "quadrature_points: 6", "[Pa]",
                        "integrator: rk4", "# mesh.ds:"}) {
    if (std::string(f) == "# mesh.ds:") continue;  // ds is set through nodes here
    EXPECT_NE(r.out.find(f), std::string::npos) << f << "\n" << r.out;
  }
  r = run("check " + kScene.string() + " --types");
  EXPECT_NE(r.out.find("moving_force: A point force without inertia"), std::string::npos) << r.out;
}

TEST(Cli, VerboseRunPrintsItsPlanFirst) {
  // -v: the run's plan (check's line: steps, memory, output steps and size) before the run's
  // own lines; without it, or with -q, no plan.
  const fs::path d = scratch("verbose");
  const std::string out = (d / "run.h5").string();
  const std::string base = "run " + kScene.string() + " -o " + out + " --overwrite --set beam.modes=2 --set time.dt=1e-4";
  const auto check = run("check " + kScene.string() + " --set beam.modes=2 --set time.dt=1e-4");
  ASSERT_EQ(check.code, 0) << check.out;
  const auto from = check.out.find("(") + 1, to = check.out.find(")). The complete scene");
  ASSERT_NE(to, std::string::npos) << check.out;
  const std::string plan = check.out.substr(from, to + 1 - from);
  auto r = run(base + " -v");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto at = r.out.find("plan: ");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_LT(at, r.out.find("beam scene")) << r.out;
  // The same figures as check's but the memory limit (MemAvailable changes between the two):
  // the steps before the first ';', the output steps and size after the last.
  const std::string line = r.out.substr(at + 6, r.out.find('\n', at) - at - 6);
  const auto steps = [](const std::string& s) { return s.substr(0, s.find(';')); };
  const auto output = [](const std::string& s) { return s.substr(s.rfind("; ", s.find(" output steps"))); };
  EXPECT_EQ(steps(line), steps(plan)) << line << "\n" << plan;
  ASSERT_NE(line.find(" output steps"), std::string::npos) << line;
  EXPECT_EQ(output(line), output(plan)) << line << "\n" << plan;
  for (const char* quiet : {"", " -v -q"}) {
    r = run(base + quiet);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(r.out.find("plan: "), std::string::npos) << quiet << ": " << r.out;
  }
}

TEST(Cli, RunWritesOutputAndRefusesToOverwrite) {
  const fs::path d = scratch("overwrite");
  const std::string out = (d / "run.h5").string();
  auto r = run("run " + kScene.string() + " -o " + out + kFast);
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_TRUE(fs::exists(out));
  ASSERT_TRUE(fs::exists(d / "run.xmf"));
  const auto size = fs::file_size(out);
  r = run("run " + kScene.string() + " -o " + out + kFast);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--overwrite"), std::string::npos) << r.out;
  EXPECT_EQ(fs::file_size(out), size);
  r = run("run " + kScene.string() + " -o " + out + kFast + " --overwrite");
  EXPECT_EQ(r.code, 0) << r.out;
}

// The later --set wins over kFast's and reaches the run: the file has an output step every
// time step (output.every = 1 against 50) and the modal state of 4 modes (positions and
// velocities: 8 values, against 4 for kFast's 2 modes).
TEST(Cli, SetOverridesReachTheRun) {
  const fs::path d = scratch("set");
  const std::string a = (d / "a.h5").string(), b = (d / "b.h5").string();
  const auto r = run("run " + kScene.string() + " -o " + a + kFast + " --set beam.modes=4 --set output.every=1");
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_EQ(run("run " + kScene.string() + " -o " + b + kFast).code, 0);
  const Reader ra(a), rb(b);
  const std::vector<double> t = ra.time(), tb = rb.time();
  ASSERT_GE(t.size(), 3u);
  ASSERT_GE(tb.size(), 3u);
  EXPECT_NEAR(t[1] - t[0], 1e-4, 1e-12);
  EXPECT_NEAR(tb[1] - tb[0], 50 * 1e-4, 1e-12);
  EXPECT_EQ(ra.restart("modal_state").values.size(), 8u);
  EXPECT_EQ(rb.restart("modal_state").values.size(), 4u);
}

TEST(Cli, UnstableTimeStepFailsWithCode3AndAMarkedFile) {
  const fs::path d = scratch("unstable");
  const std::string out = (d / "u.h5").string();
  // RK4 with dt far above its stability limit for 10 modes of this stiff beam.
  const auto r = run("run " + kScene.string() + " -o " + out + " -q --set beam.modes=10 --set time.dt=1e-3 --set loads.mass.speed=5");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("numerics failed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reduce time.dt"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out)) << "the output written so far is kept";
}

TEST(Cli, BadInputSuite) {
  // Each file: "# expect: FRAGMENT" lines (every one must be in the message), optionally
  // "# args: ..." (extra command-line arguments) and "# exit: 3" (the numerics fail; default
  // 2: refused). Exit 2 names the file and leaves no output file; exit 3 leaves none or one
  // whose status says failed (nothing that could be taken for a result).
  const fs::path dir = fs::path(TRAVERSE_SOURCE_DIR) / "tests" / "app" / "bad_input";
  const fs::path d = scratch("bad");
  int cases = 0, failing = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    std::ifstream in(entry.path());
    std::string line, args;
    std::vector<std::string> expect;
    int exit_code = 2;
    while (std::getline(in, line) && line.rfind("# ", 0) == 0) {
      if (line.rfind("# expect: ", 0) == 0) expect.push_back(line.substr(10));
      if (line.rfind("# args: ", 0) == 0) args = line.substr(8);
      if (line.rfind("# exit: ", 0) == 0) exit_code = std::stoi(line.substr(8));
    }
    const std::string name = entry.path().filename().string();
    ASSERT_FALSE(expect.empty()) << entry.path() << " has no '# expect:' line";
    ASSERT_TRUE(exit_code == 2 || exit_code == 3) << name << ": '# exit:' must be 2 or 3";
    args = std::regex_replace(args, std::regex("@SCENE@"), entry.path().string());
    const std::string out = (d / (entry.path().stem().string() + ".h5")).string();
    const bool own_output = args.find("-o ") != std::string::npos;
    const auto r = run("run " + entry.path().string() + " " + args + (own_output ? "" : " -o " + out) + " -q");
    EXPECT_EQ(r.code, exit_code) << name << "\n" << r.out;
    for (const auto& e : expect)
      EXPECT_NE(r.out.find(e), std::string::npos) << name << ": expected '" << e << "' in\n" << r.out;
    if (exit_code == 3) {
      ++failing;
      EXPECT_NE(r.out.find("numerics failed: "), std::string::npos) << name << "\n" << r.out;
      // A failed time step keeps the steps written so far, marked failed; a failed start writes nothing.
      if (r.out.find("numerics failed: time step ") != std::string::npos) {
        EXPECT_TRUE(fs::exists(out)) << name << ": the steps written before the failure are kept";
      }
      if (fs::exists(out)) {
        const std::string status = traverse::output::Reader(out).status();
        EXPECT_EQ(status.rfind("failed: ", 0), 0u) << name << ": the output file's status is '" << status << "'";
      }
      continue;
    }
    if (!own_output) {
      EXPECT_FALSE(fs::exists(out)) << name << " left an output file";
    }
    if (r.out.find(name) == std::string::npos && !own_output)
      ADD_FAILURE() << name << ": message does not name the file:\n" << r.out;
    ++cases;
  }
  std::cout << "  bad-input cases: " << cases << " refused (exit 2), " << failing << " failing numerics (exit 3)\n";
  EXPECT_GE(cases, 40);
  EXPECT_GE(failing, 3);
}

TEST(Cli, RodRunWritesProbesFieldsAndStatus) {
  const fs::path d = scratch("rod");
  const std::string out = (d / "cable.h5").string();
  const auto r = run("run " + kCable.string() + " -o " + out + kCoarse);
  ASSERT_EQ(r.code, 0) << r.out;
  traverse::output::Reader f(out);
  EXPECT_EQ(f.status(), "complete");
  EXPECT_EQ(f.steps_written(), 21u);
  const auto mid = f.probe("midspan");
  ASSERT_EQ(mid.components, 3u);
  // Starts at the static sag under gravity (linear beam value 0.0245 m), then goes down.
  EXPECT_NEAR(mid.values[1], -0.0245, 0.002);
  double lowest = 0.0;
  for (size_t k = 0; k < mid.rows; ++k) lowest = std::min(lowest, mid.values[3 * k + 1]);
  EXPECT_LT(lowest, -0.1);
  const auto r_field = f.field("r", f.steps_written() - 1);
  EXPECT_EQ(r_field.size(), 21u * 3u);
  EXPECT_NEAR(r_field[0], 0.0, 1e-12);  // left end fixed at the origin
  EXPECT_TRUE(f.has_attribute("scene"));
}

// rod.model: extensible through the executable: a clamped rod pulled at its end by a roller's
// force F from t = 0, at Courant number c dt / ds = 1 (where the box scheme is exact at the
// nodes, tests/rod/test_rod_strain.cpp). The tip's position probe integrates the strain field
// along s by the trapezoidal rule; across the strain front (a jump F / (E A) at a node) that
// rule errs by at most ds / 2 times the jump, ds / (4 L) of the peak 2 F L / (E A). The field v
// is the compliance law v3 = 1 + n3 / (E A), v1 = v2 = 0; stretch is v3 and axial_force n3 here.
TEST(Cli, ExtensibleRodFollowsTheAxialStepResponse) {
  const fs::path d = scratch("extensible");
  const double L = 1.0, E = 2.5e8, rho = 1500.0, r = 0.005, F = 10.0, EA = E * M_PI * r * r;
  const double c = std::sqrt(E / rho), ds = L / 20, dt = ds / c, T = 4.0 * L / c, peak = 2.0 * F * L / EA;
  char scene[2048];
  std::snprintf(scene, sizeof scene, R"(model: rod
gravity: 0
rod: {length: %.17g, youngs_modulus: %.17g, poisson_ratio: 0.25, density: %.17g,
      section: {type: solid_circle, radius: %.17g}, model: extensible}
ends:
  left: {type: clamped}
  right: {type: roller, force: %.17g}
mesh: {nodes: 21}
initial_state: {type: rest}
time: {dt: %.17g, end: %.17g}
output:
  probes:
    tip: {type: point, at: %.17g, quantity: position}
  fields: [v, n, stretch, axial_force]
)", L, E, rho, r, F, dt, 160 * dt, L);
  const fs::path yaml = d / "axial.yaml";
  std::ofstream(yaml) << scene;
  const std::string out = (d / "axial.h5").string();
  const auto res = run("run " + yaml.string() + " -o " + out + " -q --overwrite");
  ASSERT_EQ(res.code, 0) << res.out;
  Reader f(out);
  const auto tip = f.probe("tip");
  const std::vector<double> t = f.time();
  double err = 0.0, law = 0.0;
  for (size_t k = 0; k < tip.rows; ++k) {
    // The force sampled at the levels acts from dt / 2 (the trapezoidal average of the first step).
    const double x = std::fmod(std::max(0.0, t[k] - 0.5 * dt), T) / T;
    err = std::max(err, std::abs(tip.values[3 * k + 2] - L - peak * (x < 0.5 ? 2.0 * x : 2.0 - 2.0 * x)));
  }
  const std::size_t last = f.steps_written() - 1;
  const std::vector<double> v = f.field("v", last), n = f.field("n", last);
  const std::vector<double> stretch = f.field("stretch", last), axial = f.field("axial_force", last);
  ASSERT_EQ(stretch.size(), v.size() / 3);
  double fields = 0.0;
  for (size_t j = 0; j < v.size() / 3; ++j) {
    law = std::max({law, std::abs(v[3 * j]), std::abs(v[3 * j + 1]), std::abs(v[3 * j + 2] - 1.0 - n[3 * j + 2] / EA)});
    fields = std::max({fields, std::abs(stretch[j] - v[3 * j + 2]), std::abs(axial[j] - n[3 * j + 2]) / F});
  }
  EXPECT_LT(fields, 1e-14);
  std::printf("  tip displacement error / peak %.2e (bound ds / (4 L) = %.2e); |v - (e3 + C n)| %.1e\n", err / peak,
              ds / (4.0 * L), law);
  EXPECT_LT(err / peak, ds / (4.0 * L));
  EXPECT_LT(law, 1e-12 * peak);
}

TEST(Cli, RodGivesTheSameAnswersOnOneAndTwoRanksAndWithEachLinearSolver) {
  const fs::path d = scratch("rod-ranks");
  struct Case {
    std::string name, prefix, args;
  };
  const std::vector<Case> cases{
      {"klu2_np1", "", " --set 'solver.Linear Solver=KLU2'"},
      {"gmres_schwarz_np1", "", " --set 'solver.Linear Solver=GMRES'"},
      {"gmres_ilut_np1", "", " --set 'solver.Linear Solver=GMRES' --set solver.Preconditioner=ILUT"},
      {"auto_np2", mpirun(2), ""},  // GMRES + Schwarz with KLU2 subdomains
      {"klu2_np2", mpirun(2), " --set 'solver.Linear Solver=KLU2'"},  // rerouted to the same
      {"gmres_schwarz_np2", mpirun(2), " --set 'solver.Linear Solver=GMRES'"},
  };
  std::vector<double> reference;
  for (const auto& c : cases) {
    const std::string out = (d / (c.name + ".h5")).string();
    const auto r = run_with(c.prefix, "run " + kCable.string() + " -o " + out + kCoarse + c.args);
    ASSERT_EQ(r.code, 0) << c.name << "\n" << r.out;
    if (c.name == "klu2_np2") {
      const auto noisy = run_with(c.prefix, "run " + kCable.string() + " -o " + out + " --overwrite --set mesh.ds=0.05" + c.args);
      EXPECT_NE(noisy.out.find("rerouted"), std::string::npos) << noisy.out;
    }
    const auto mid = traverse::output::Reader(out).probe("midspan").values;
    if (reference.empty()) {
      reference = mid;
      continue;
    }
    const double diff = max_difference(mid, reference);
    std::cout << "  " << c.name << ": max |midspan - KLU2 on 1 rank| = " << diff << " m\n";
    EXPECT_LT(diff, 1e-10) << c.name;
  }
  const auto refused = run_with(mpirun(2), "run " + kCable.string() + " -o " + (d / "refused.h5").string() + kCoarse +
                                               " --set 'solver.Linear Solver=KLU2' --set 'solver.On Broken Direct Solver=refuse'");
  EXPECT_EQ(refused.code, 2) << refused.out;
  EXPECT_NE(refused.out.find("KLU2"), std::string::npos) << refused.out;
  EXPECT_FALSE(fs::exists(d / "refused.h5"));
}

// A beam scene with a coupled mass (docs/beam.md "Coupled mass"): the run ends at the event
// (the bead leaves the strip at x = L) with exit 0, status complete, the event in /events and
// end_reason; the probes hold the mass's state, contact forces and energies; --restart replays.
TEST(Cli, CoupledMassBeamRunEndsAtItsEvent) {
  const fs::path scene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "beam" / "coupled_bead.yaml";
  const fs::path d = scratch("coupled");
  const std::string out = (d / "bead.h5").string();
  const auto r = run("run " + scene.string() + " -o " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("ended by the event left_beam_at_L"), std::string::npos) << r.out;
  traverse::output::Reader f(out);
  EXPECT_EQ(f.status(), "complete");
  EXPECT_EQ(f.attribute("end_reason"), "left_beam_at_L");
  const auto events = f.events();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].load, "bead");
  EXPECT_EQ(events[0].reason, "left_beam_at_L");
  EXPECT_NEAR(events[0].position, 2.0, 1e-9);
  const auto t = f.time();
  EXPECT_DOUBLE_EQ(t.back(), events[0].time);
  EXPECT_LT(events[0].time, 2.0);  // before time.end
  const auto x = f.probe("bead_position"), pos = f.probe("bead_fixed_position"), w = f.probe("bead_deflection");
  ASSERT_EQ(pos.components, 3u);
  EXPECT_NEAR(x.values.back(), 2.0, 1e-9);
  for (size_t k = 0; k < x.rows; ++k) {
    EXPECT_EQ(pos.values[3 * k], x.values[k]);
    EXPECT_EQ(pos.values[3 * k + 1], w.values[k]);
  }
  const auto balance = f.probe("energy_balance"), kinetic = f.probe("energy_mass_kinetic");
  double drift = 0.0;
  for (double b : balance.values) drift = std::max(drift, std::abs(b - balance.values.front()));
  std::printf("  coupled bead: event at t = %.9f s; energy balance drift %.3e J of mass kinetic energy %.4f J\n",
              events[0].time, drift, kinetic.values.front());
  EXPECT_LT(drift, 1e-8 * kinetic.values.front());
  const auto normal = f.probe("bead_normal_force");
  for (double n : normal.values) EXPECT_GT(n, 0.0);  // the bead presses on the strip all the way
  // --restart re-integrates from t = 0 and checks the file's steps: the complete run is
  // reproduced; with another mass it is refused (exit 2).
  const auto again = run("run " + scene.string() + " --restart " + out + " -q");
  EXPECT_EQ(again.code, 0) << again.out;
  EXPECT_EQ(traverse::output::Reader(out).events().size(), 1u);
  const auto other = run("run " + scene.string() + " --restart " + out + " -q --set loads.bead.mass=1.1");
  EXPECT_EQ(other.code, 2) << other.out;
  EXPECT_NE(other.out.find("does not reproduce output step 0"), std::string::npos) << other.out;
}

// A rod scene with a coupled mass (docs/rod.md "Coupled mass"): the run ends when the bead leaves
// the cable at s = L, with the event interpolated in the last step; the same run on 2 ranks gives
// the same file; a --restart of the complete file continues nothing and keeps it as it was.
TEST(Cli, CoupledMassRodRunEndsAtItsEvent) {
  const fs::path scene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "rod" / "coupled_bead_cable.yaml";
  const fs::path d = scratch("coupled_rod");
  const std::string out = (d / "bead.h5").string();
  const auto r = run("run " + scene.string() + " -o " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("ended by the event left_rod_at_L"), std::string::npos) << r.out;
  traverse::output::Reader f(out);
  EXPECT_EQ(f.status(), "complete");
  EXPECT_EQ(f.attribute("end_reason"), "left_rod_at_L");
  const auto events = f.events();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].load, "bead");
  EXPECT_EQ(events[0].position, 1.0);
  const auto t = f.time();
  const auto sigma = f.probe("bead_position");
  EXPECT_GT(sigma.values.back(), 1.0);                        // the last step ends beyond the end
  EXPECT_LT(sigma.values[sigma.rows - 2], 1.0);               // the one before on the rod
  EXPECT_GT(events[0].time, t[t.size() - 2]);
  EXPECT_LE(events[0].time, t.back());
  const auto balance = f.probe("energy_balance"), kinetic = f.probe("energy_mass_kinetic");
  double drift = 0.0;
  for (double b : balance.values) drift = std::max(drift, std::abs(b - balance.values.front()));
  const auto tang = f.probe("bead_tangential_force"), normal = f.probe("bead_normal_force");
  ASSERT_EQ(normal.components, 3u);
  double tmax = 0.0;
  for (size_t k = 1; k < tang.rows; ++k) tmax = std::max(tmax, std::abs(tang.values[k]));
  std::printf("  coupled bead on the cable: event at t = %.9f s; energy balance drift %.3e J (mass kinetic energy "
              "%.4f J at t = 0); max |tangential contact force| %.2e N\n", events[0].time, drift, kinetic.values.front(),
              tmax);
  EXPECT_LT(drift, 1e-2 * kinetic.values.front());  // the line mass's O(ds^2) at 40 cells (docs/rod.md)
  EXPECT_LT(tmax, 1e-10);
  EXPECT_GT(normal.values[3 * 1 + 1], 0.0);  // the cable pushes the bead up
  const std::string two_out = (d / "two.h5").string();
  const auto two = run_with(mpirun(2), "run " + scene.string() + " -o " + two_out + " -q");
  ASSERT_EQ(two.code, 0) << two.out;
  std::string why;
  const double diff = traverse::testing::max_file_difference(out, two_out, why);
  std::printf("  coupled bead, 1 vs 2 ranks: max |difference| %.2e (%s)\n", diff, why.c_str());
  EXPECT_LE(diff, 1e-10) << why;
  EXPECT_EQ(traverse::output::Reader(two_out).events().size(), 1u);
  fs::copy_file(out, d / "before.h5", fs::copy_options::overwrite_existing);
  const auto again = run("run --restart " + out + " -q");
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_EQ(traverse::testing::max_file_difference((d / "before.h5").string(), out, why), 0.0) << why;
  const auto kept = traverse::output::Reader(out).events();
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_EQ(kept[0].time, events[0].time);
  EXPECT_EQ(kept[0].reason, "left_rod_at_L");
}

/// The largest |v - v[0]| of a probe's values.
double drift_of(const std::vector<double>& v) {
  double d = 0.0;
  for (double b : v) d = std::max(d, std::abs(b - v.front()));
  return d;
}

// Coulomb friction on the rod with time.end: auto (docs/rod.md "Coupled mass"): the bead of
// coupled_bead_cable.yaml with mu = 0.5 slows down in the sag and sticks: exit 0, the event stick
// in /events and end_reason, the last output step at the stop (the step shortened to it: speed
// ~0), the energy balance closed by work_friction (to the line mass's O(ds^2), as without it).
TEST(Cli, CoupledMassRodFrictionSticksAndEndsTheRun) {
  const fs::path scene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "rod" / "coupled_bead_cable.yaml";
  const std::string out = (scratch("coupled_stick") / "stick.h5").string();
  const auto r = run("run " + scene.string() + " -o " + out + " --set loads.bead.friction=0.5 --set time.end=auto");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("ended by the event stick"), std::string::npos) << r.out;
  traverse::output::Reader f(out);
  EXPECT_EQ(f.status(), "complete");
  EXPECT_EQ(f.attribute("end_reason"), "stick");
  const auto events = f.events();
  ASSERT_EQ(events.size(), 1u);
  const auto t = f.time();
  const auto speed = f.probe("bead_speed"), sigma = f.probe("bead_position");
  const auto friction = f.probe("work_friction"), balance = f.probe("energy_balance");
  const double drift = drift_of(balance.values);
  std::printf("  stick at t = %.9f s, sigma = %.6f m (mu g deceleration alone: %.4f m), final speed %.2e m/s; "
              "work_friction %.5f J, energy balance drift %.3e J\n", events[0].time, events[0].position,
              0.1 + 4.0 / (2 * 0.5 * 9.8), speed.values.back(), friction.values.back(), drift);
  EXPECT_DOUBLE_EQ(t.back(), events[0].time);
  EXPECT_DOUBLE_EQ(sigma.values.back(), events[0].position);
  EXPECT_LT(std::abs(speed.values.back()), 1e-9);
  EXPECT_GT(events[0].position, 0.3);
  EXPECT_LT(events[0].position, 0.8);
  EXPECT_GT(friction.values.back(), 0.05);
  EXPECT_LT(drift, 0.01 * friction.values.back());
}

// The beam's coupled mass with friction and time.end: auto: coupled_bead.yaml's bead (3 m/s) with
// mu = 0.3 sticks before the strip's end, near x0 + v0^2 / (2 mu g), and work_friction is near
// mu M g times the distance slid (the strip's sag under the bead changes both by a few percent).
TEST(Cli, CoupledMassBeamFrictionSticks) {
  const fs::path scene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "beam" / "coupled_bead.yaml";
  const std::string out = (scratch("coupled_beam_stick") / "stick.h5").string();
  const auto r = run("run " + scene.string() + " -o " + out + " -q --set loads.bead.friction=0.3 --set time.end=auto");
  ASSERT_EQ(r.code, 0) << r.out;
  traverse::output::Reader f(out);
  EXPECT_EQ(f.attribute("end_reason"), "stick");
  const auto events = f.events();
  ASSERT_EQ(events.size(), 1u);
  const double level = 0.05 + 9.0 / (2 * 0.3 * 9.8);
  const double drift = drift_of(f.probe("energy_balance").values), work = f.probe("work_friction").values.back();
  std::printf("  beam: stick at t = %.6f s, x = %.6f m (level rigid line %.6f m); work_friction %.4f J, balance drift "
              "%.2e J\n", events[0].time, events[0].position, level, work, drift);
  EXPECT_NEAR(events[0].position, level, 0.05 * level);
  const double sliding = 0.3 * 9.8 * (events[0].position - 0.05);  // mu M g times the distance slid
  std::printf("  mu M g (x_stop - x0) = %.4f J\n", sliding);
  EXPECT_NEAR(work, sliding, 0.05 * sliding);
  EXPECT_LT(drift, 1e-6 * work);
}

// time.end: auto reaching its bound: the zip line's trolley swings in the sag without an event;
// with time.auto_limit = 0.2 s the run ends there with exit 0, the event time_limit and a message.
TEST(Cli, CoupledMassAutoEndStopsAtItsLimit) {
  const fs::path scene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "rod" / "coupled_zip_line.yaml";
  const fs::path d = scratch("coupled_limit");
  const std::string out = (d / "zip.h5").string();
  const auto r = run("run " + scene.string() + " -o " + out + " --set time.end=auto --set time.auto_limit=0.2");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("no event (leaving, lift-off, stick) by time.auto_limit = 0.2 s"), std::string::npos) << r.out;
  traverse::output::Reader f(out);
  EXPECT_EQ(f.status(), "complete");
  EXPECT_EQ(f.attribute("end_reason"), "time_limit");
  const auto events = f.events();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NEAR(events[0].time, 0.2, 1e-12);
  EXPECT_NEAR(f.time().back(), 0.2, 1e-12);
  const auto beam = run("run " + (fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "beam" / "coupled_bead.yaml").string() +
                        " -o " + (d / "bead.h5").string() +
                        " -q --set time.end=auto --set time.auto_limit=0.1");
  ASSERT_EQ(beam.code, 0) << beam.out;
  traverse::output::Reader fb((d / "bead.h5").string());
  EXPECT_EQ(fb.attribute("end_reason"), "time_limit");
  EXPECT_NEAR(fb.time().back(), 0.1, 1e-12);
}

// The inspection robot of the 20 N class (docs/results.md), at twice the scene's ds and dt: its
// weight pulls the soft cable into a V that travels with it, so it first runs down into the V
// faster than the rigid level line's D / c = 0.1 m/s and then climbs out of it for the rest of
// the span at about a quarter of D / c (measured 0.246 D / c over [6, 12] s, asserted within
// (0.2, 0.3)); it leaves at s = L after about 16 s (asserted in (15, 17) s; 16.02 s at the scene's
// mesh); the energy balance closes to 1 % of the dissipated work.
TEST(Cli, CoupledRobotOfThe20NClassClimbsOutOfItsOwnSag) {
  const fs::path scene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "rod" / "coupled_inspection_robot_20N.yaml";
  const std::string out = (scratch("coupled_robot20") / "robot.h5").string();
  const auto r = run("run " + scene.string() + " -o " + out + " -q --set mesh.ds=0.025 --set time.dt=0.005");
  ASSERT_EQ(r.code, 0) << r.out;
  traverse::output::Reader f(out);
  EXPECT_EQ(f.attribute("end_reason"), "left_rod_at_L");
  const auto t = f.time();
  const auto sigma = f.probe("robot_position"), speed = f.probe("robot_speed");
  auto at = [&](double time) {
    size_t k = 0;
    while (k + 1 < t.size() && t[k] < time) ++k;
    return k;
  };
  const size_t k6 = at(6.0), k12 = at(12.0);
  ASSERT_LT(k12 + 1, t.size());
  const double terminal = 20.0 / 200.0, climb = (sigma.values[k12] - sigma.values[k6]) / (t[k12] - t[k6]);
  const double fastest = *std::max_element(speed.values.begin(), speed.values.end());
  const auto balance = f.probe("energy_balance"), loss = f.probe("work_dissipated");
  const double drift = drift_of(balance.values);
  std::printf("  robot 20 N class: fastest %.4f m/s = %.3f D / c; mean speed %.5f m/s over [%.2f, %.2f] s = %.3f D / c; "
              "leaves at t = %.4f s; balance drift %.3e J of %.4f J dissipated\n", fastest, fastest / terminal, climb,
              t[k6], t[k12], climb / terminal, t.back(), drift, loss.values.back());
  EXPECT_GT(fastest, 1.5 * terminal);
  EXPECT_GT(climb, 0.2 * terminal);
  EXPECT_LT(climb, 0.3 * terminal);
  EXPECT_GT(t.back(), 15.0);
  EXPECT_LT(t.back(), 17.0);
  EXPECT_LT(drift, 0.01 * loss.values.back());
}

// The same robot with its resistance through the air (the spec's form, acting on the robot
// alone): where the cable's material moves backwards along its tangent under the robot faster
// than the robot advances along it, that resistance's power c sigma' d3 . p' is negative and it
// feeds energy in. Measured at the scene's mesh: work_dissipated rises to 8.1 J and then falls
// by 40.8 J by t = 1.83 s, 5.6 times the drive's whole work; the energy balance still closes to
// 0.04 J (the numerics follow the model's runaway; docs/rod.md "Coupled mass").
TEST(Cli, CoupledRobotWithAirResistanceIsFedEnergyByIt) {
  const fs::path scene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "rod" / "coupled_inspection_robot_20N.yaml";
  const std::string out = (scratch("coupled_robot20_air") / "robot.h5").string();
  const auto r = run("run " + scene.string() + " -o " + out + " -q --set loads.robot.resistance_through=air --set "
                     "time.auto_limit=1.83");
  ASSERT_EQ(r.code, 0) << r.out;
  traverse::output::Reader f(out);
  EXPECT_EQ(f.attribute("end_reason"), "time_limit");
  const auto loss = f.probe("work_dissipated").values, drive = f.probe("work_drive").values;
  const double most = *std::max_element(loss.begin(), loss.end()), fed = most - loss.back();
  const double drift = drift_of(f.probe("energy_balance").values);
  std::printf("  air resistance: work_dissipated up to %.4f J, then %.4f J at t = %.3f s (fed in %.4f J; drive %.4f J); "
              "balance drift %.3e J\n", most, loss.back(), f.time().back(), fed, drive.back(), drift);
  EXPECT_GT(most, 5.0);
  EXPECT_GT(fed, 2.0 * drive.back());
  EXPECT_LT(drift, 0.01 * fed);
}

// Unilateral contact on the rod: inputs/rod/coupled_lift_off_arc.yaml at a coarse mesh and step
// (20 cells, dt = 2e-3 s) ends with the event lift_off near the rigid-wire answer
// R acos((v0^2/(g R) + 2 cos theta0) / 3) = 0.795613 m (docs/rod.md "Coupled mass").
namespace {

// Runs the rod scene `file` of inputs/rod into `out` with `args`: a complete run that ended with
// the one event lift_off; its events (empty after a failed check).
std::vector<traverse::output::RunEvent> lift_off_run(const std::string& file, const std::string& out,
                                                     const std::string& args) {
  const fs::path scene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "rod" / file;
  const auto r = run("run " + scene.string() + " -o " + out + " -q " + args);
  EXPECT_EQ(r.code, 0) << r.out;
  if (r.code != 0) return {};
  traverse::output::Reader f(out);
  EXPECT_EQ(f.status(), "complete");
  EXPECT_EQ(f.attribute("end_reason"), "lift_off");
  auto events = f.events();
  EXPECT_EQ(events.size(), 1u);
  return events.size() == 1u ? events : decltype(events){};
}

}  // namespace

TEST(Cli, CoupledMassRodLiftOff) {
  const std::string out = (scratch("coupled_lift") / "arc.h5").string();
  const auto events = lift_off_run("coupled_lift_off_arc.yaml", out, "--set mesh.ds=0.05 --set time.dt=2e-3");
  ASSERT_EQ(events.size(), 1u);
  const double exact = std::acos((1.0 / 9.8 + 2.0 * std::cos(0.05)) / 3.0);
  std::printf("  lift-off at t = %.6f s, sigma = %.6f m (rigid wire %.6f m)\n", events[0].time, events[0].position, exact);
  EXPECT_NEAR(events[0].position, exact, 5e-3 * exact);
}

// A sprung mass on the rod with unilateral contact (inputs/rod/sprung_cabin_cable.yaml at 1.5
// m/s): the cabin's body swings up after the cable's dip and unloads the wheel; the run ends with
// lift_off in the step where the rod's contact force along d2 turns negative, at the zero
// interpolated between that step's midpoint and the one before. With the default bilateral
// contact the same run goes on to the end, through steps where the rod pulls the wheel.
TEST(Cli, SprungMassRodLiftOff) {
  const fs::path scene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "rod" / "sprung_cabin_cable.yaml";
  const std::string out = (scratch("sprung_lift") / "cabin.h5").string(), both = (scratch("sprung_lift") / "b.h5").string();
  const auto events = lift_off_run("sprung_cabin_cable.yaml", out,
                                   "--set loads.cabin.speed=1.5 --set loads.cabin.contact=unilateral");
  ASSERT_EQ(events.size(), 1u);
  traverse::output::Reader f(out);
  const auto c = f.probe("cabin_contact_force").values;
  const auto t = f.time();
  ASSERT_GE(c.size(), 3u);
  for (std::size_t k = 1; k + 1 < c.size(); ++k) EXPECT_GT(c[k], 0.0) << "step " << k;  // c[0]: NaN, no step yet
  EXPECT_LT(c.back(), 0.0);
  EXPECT_GT(events[0].time, t[t.size() - 3]);
  EXPECT_LT(events[0].time, t.back());
  std::printf("  lift-off at t = %.6f s, sigma = %.6f m (last contact forces %.4f, %.4f N)\n", events[0].time,
              events[0].position, c[c.size() - 2], c.back());
  const auto r = run("run " + scene.string() + " -o " + both + " -q --set loads.cabin.speed=1.5");
  ASSERT_EQ(r.code, 0) << r.out;
  traverse::output::Reader g(both);
  EXPECT_EQ(g.attribute("end_reason"), "end_time");
  EXPECT_GT(g.time().back(), t.back());
}

// A Young's modulus typed in GPa (210 for steel) on a 20 m beam: the static deflection under
// its own weight is thousands of spans. Refused before the run (exit 2, no output), by run
// and by check, naming the key and the bound.
TEST(Cli, BeamBeyondSmallDeflectionsIsRefusedBeforeTheRun) {
  const fs::path d = scratch("validity-static");
  const std::string out = (d / "gpa.h5").string();
  const std::string gpa = " --set beam.youngs_modulus=210 --set beam.length=20";
  for (const std::string& cmd :
       {"run " + kScene.string() + " -o " + out + kFast + gpa, "check " + kScene.string() + gpa}) {
    const auto r = run(cmd);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("beam.youngs_modulus: expected a beam whose static deflection"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("L / 10 = 2 m"), std::string::npos) << r.out;
  }
  EXPECT_FALSE(fs::exists(out));
  // Steel in Pa: a 10 m cantilever sags 0.15 m under its own weight (q L^4 / 8 E I), inside
  // the range; at 20 m it sags 2.5 m, more than L / 10.
  EXPECT_EQ(run("check " + kScene.string() + " --set beam.length=10").code, 0);
  EXPECT_EQ(run("check " + kScene.string() + " --set beam.length=20").code, 2);
}

// A soft cantilever (E = 6e8 Pa: 8 cm of static tip deflection) under a mass of 0.6 of the
// total: the tip passes L / 10 = 0.2 m while the mass rides out. Exit 3 at the first output
// step beyond the bound, which the file keeps (marked failed); every earlier one is inside.
TEST(Cli, BeamLeavingSmallDeflectionsFailsWithCode3) {
  const fs::path d = scratch("validity-run");
  const std::string out = (d / "soft.h5").string();
  const auto r = run("run " + kScene.string() + " -o " + out + " -q --set beam.youngs_modulus=6e8 --set time.dt=1e-4"
                     " --set loads.mass.speed=5 --set loads.mass.mass_fraction=0.6 --set output.every=1");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("leaves the small-deflection range"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("loads.mass.mass_fraction"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("beam.youngs_modulus"), std::string::npos) << r.out;
  const Reader f(out);
  EXPECT_EQ(f.status().rfind("failed: beam model: the deflection leaves", 0), 0u) << f.status();
  const auto tip = f.probe("tip").values;
  ASSERT_GE(tip.size(), 2u);
  EXPECT_GT(std::abs(tip.back()), 0.2);
  for (std::size_t i = 0; i + 1 < tip.size(); ++i) EXPECT_LE(std::abs(tip[i]), 0.2) << "output step " << i;
}

// A load that can do nothing: a moving mass (beam) and a force given as a weight (rod) with
// gravity 0 are warned about, naming the key; with gravity, or a force, nothing is said.
TEST(Cli, LoadsThatCanDoNothingAreWarnedAbout) {
  const fs::path d = scratch("idle-loads");
  const auto beam = run("run " + kScene.string() + " -o " + (d / "beam.h5").string() + kFast + " --set gravity=0");
  EXPECT_EQ(beam.code, 0) << beam.out;
  EXPECT_NE(beam.out.find("warning"), std::string::npos) << beam.out;
  EXPECT_NE(beam.out.find("loads.mass.mass_fraction, and gravity = 0"), std::string::npos) << beam.out;
  const auto rod = run("run " + kCable.string() + " -o " + (d / "rod.h5").string() + kCoarse +
                       " --set gravity=0 --set 'loads.F={type: moving_force, mass: 0.2, speed: 3.63418}'");
  EXPECT_EQ(rod.code, 0) << rod.out;
  EXPECT_NE(rod.out.find("loads.F.mass, and gravity = 0"), std::string::npos) << rod.out;
  const auto zero = run("run " + kCable.string() + " -o " + (d / "zero.h5").string() + kCoarse +
                        " --set 'loads.F={type: moving_force, force_vector: [0, 0, 0], speed: 3.63418}'");
  EXPECT_NE(zero.out.find("its force is zero (loads.F.force_vector)"), std::string::npos) << zero.out;
  const auto late = run("run " + kScene.string() + " -o " + (d / "late.h5").string() + kFast +
                        " --set time.end=0.01 --set loads.mass.entry_time=1");
  EXPECT_EQ(late.code, 0) << late.out;
  EXPECT_NE(late.out.find("loads.mass.entry_time: load 'mass' can do nothing: it enters at t = 1 s, at or after "
                          "time.end = 0.01 s"),
            std::string::npos)
      << late.out;
  for (const std::string& loaded : {"run " + kScene.string() + " -o " + (d / "b2.h5").string() + kFast,
                                    "run " + kCable.string() + " -o " + (d / "r2.h5").string() + kCoarse +
                                        " --set gravity=0"}) {
    const auto r = run(loaded);
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(r.out.find("can do nothing"), std::string::npos) << r.out;
  }
}

// time.dt: auto with a load that starts almost at rest and accelerates almost not at all
// (speed and acceleration 1e-300): the step is ds over the load's largest speed on the rod,
// so the load crosses at most one cell per step (never the whole rod in one step).
TEST(Cli, AutoStepResolvesASlowAcceleratingLoad) {
  const fs::path d = scratch("slow-load");
  const std::string out = (d / "slow.h5").string();
  const auto r = run("run " + kCable.string() + " -o " + out + kCoarse +
                     " --set loads.F.speed=1e-300 --set loads.F.acceleration=1e-300 --set output.fields=[]");
  ASSERT_EQ(r.code, 0) << r.out;
  const Reader f(out);
  const auto sigma = f.sigma().values;
  ASSERT_GE(sigma.size(), 20u);  // at least L / ds = 20 steps
  for (std::size_t i = 1; i < sigma.size(); ++i) {
    if (std::isfinite(sigma[i]) && std::isfinite(sigma[i - 1])) {
      EXPECT_LE(sigma[i] - sigma[i - 1], 0.05 * (1.0 + 1e-9)) << "step " << i;
    }
  }
  EXPECT_NEAR(sigma.back(), 1.0, 1e-9);
  for (double y : f.probe("midspan").values) EXPECT_TRUE(std::isfinite(y));
}

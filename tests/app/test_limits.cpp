// The up-front limits of a run (traverse/setup/run_limits.hpp, docs/reliability.md "Limits") through
// the executable: extreme time steps, end times, entry times, speeds and accelerations either
// run exactly the steps they report or are refused with exit 2, each case as the documented
// limits say (expected_exit: from the case's numbers, not from the program); never exit 3;
// the memory estimate against the measured peak; a beam's default output rate (4 per period
// of its highest mode) and the output size `check` prints against the files written; the
// option parsers.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "process.hpp"
#include "traverse/setup/run_limits.hpp"
#include "traverse/output/reader.hpp"

using traverse::testing::scratch;

namespace fs = std::filesystem;
using traverse::testing::Child;

namespace {

const fs::path kBeam = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "beam" / "cantilever.yaml";
const fs::path kRod = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "rod" / "hanging_cable_F2_a0.5.yaml";
constexpr long kMaxSteps = 200;

struct Case {
  std::string label, log, out;
  std::vector<std::string> argv;
  Child child;
  bool beam = false;
  int expected = 0;  // the exit code the documented limits give this case
};

// The numbers of one case, and what the limits of docs/reliability.md ("Limits") and the
// documented time.dt / time.end autos make of them, stated here from the load's kinematics
// (x = v tau + a tau^2 / 2 from the entry end) and the beam's closed-form frequencies.
struct CaseNumbers {
  bool beam = false;
  double dt = 0.0, end = 0.0, entry = 0.0, v = 0.0, a = 0.0;  // dt, end: NaN for auto
};

// When the load has travelled the length L (or +inf if it stops before).
double exit_time(const CaseNumbers& c, double L) {
  if (c.a == 0.0) return c.v > 0.0 ? c.entry + L / c.v : INFINITY;
  if (c.a > 0.0) return c.entry + 2.0 * L / (c.v + std::hypot(c.v, std::sqrt(2.0 * c.a) * std::sqrt(L)));
  if (!(c.v * c.v >= 2.0 * -c.a * L)) return INFINITY;
  return c.entry + 2.0 * L / (c.v + std::sqrt(c.v * c.v + 2.0 * c.a * L));
}

int expected_exit(const CaseNumbers& c) {
  // The cantilever scene (L = 2 m, 11 nodes, 2 modes of the steel tube) and the hanging cable
  // (L = 1 m, ds = 0.1 m).
  const double L = c.beam ? 2.0 : 1.0, ds = c.beam ? 0.2 : 0.1;
  const double te = exit_time(c, L);
  const double at_exit = std::isfinite(te) ? std::abs(c.v + c.a * (te - c.entry)) : 0.0;
  if (std::max(c.v, at_exit) > 299792458.0) return 2;  // faster than light on the structure
  const double end = std::isnan(c.end) ? te : c.end;  // auto: when the load leaves
  if (!std::isfinite(end)) return 2;                   // auto, and the load never leaves
  double dt = c.dt;
  if (std::isnan(dt)) {
    // rod: ds / the largest speed while on the rod (before the end); beam: a twentieth of the
    // period of mode 2, at most ds / the largest speed.
    const double t_last = std::min(te, end);
    const double last = t_last > c.entry ? std::abs(c.v + c.a * (t_last - c.entry)) : 0.0;
    const double v_max = c.beam ? std::max(c.v, at_exit) : std::max(c.v, last);
    if (c.beam) {
      const double ro = 0.1, ri = 0.05, A = M_PI * (ro * ro - ri * ri);
      const double I = M_PI / 4 * (std::pow(ro, 4) - std::pow(ri, 4));
      const double beta2 = 4.694091132974174;  // second root of 1 + cos x cosh x = 0
      const double omega2 = beta2 * beta2 * std::sqrt(2.0e11 * I / (7850.0 * A * std::pow(L, 4)));
      dt = std::min(2.0 * M_PI / omega2 / 20.0, v_max > 0.0 ? ds / v_max : INFINITY);
    } else {
      if (!(v_max > 0.0)) return 2;
      dt = ds / v_max;
    }
  }
  const double steps = std::max(1.0, std::ceil(end / dt - 1e-6));
  return steps <= static_cast<double>(kMaxSteps) ? 0 : 2;
}

long first_number(const std::string& text, const std::string& pattern) {
  std::smatch m;
  return std::regex_search(text, m, std::regex(pattern)) ? std::stol(m[1].str()) : -1;
}

// Checks one finished case; returns its exit code (or -1 after a failure).
int check_case(const Case& c, int code) {
  const std::string log = traverse::testing::read_text(c.log);
  const std::string where = c.label + "\n" + log;
  EXPECT_EQ(code, c.expected) << where;
  if (code == 2) {
    EXPECT_FALSE(fs::exists(c.out)) << "exit 2 left an output file: " << where;
    EXPECT_NE(log.find("bad scene: "), std::string::npos) << where;
    EXPECT_TRUE(std::regex_search(log, std::regex(R"(: (time\.dt|time\.end|loads\.\w+\.\w+|mesh\.\w+): expected)")))
        << "the message names no key of the case: " << where;
    return 2;
  }
  if (code == 3) {
    const auto at = log.find("numerics failed: ");
    EXPECT_NE(at, std::string::npos) << where;
    if (at != std::string::npos) std::cout << "  exit 3: " << c.label << ": " << log.substr(at, 150) << "...\n";
    if (fs::exists(c.out)) {
      const std::string status = traverse::output::Reader(c.out).status();
      EXPECT_EQ(status.rfind("failed: ", 0), 0u) << "status '" << status << "': " << where;
    }
    return 3;
  }
  if (code != 0) {
    ADD_FAILURE() << "exit " << code << ": " << where;
    return -1;
  }
  // Completed: every step is in the file (output.every = 1), as many as reported, on the grid.
  const traverse::output::Reader f(c.out);
  EXPECT_EQ(f.status(), "complete") << where;
  const std::vector<double> t = f.time();
  const long written = static_cast<long>(f.steps_written());
  const long steps = written - 1;
  EXPECT_GE(steps, 1) << where;
  EXPECT_LE(steps, kMaxSteps) << where;
  if (c.beam) {
    // The beam reports its (sub)steps: the grid steps plus at most a split at each load event.
    EXPECT_EQ(first_number(log, R"(([0-9]+) output steps)"), written) << where;
    const long reported = first_number(log, R"(([0-9]+) steps of dt)");
    EXPECT_GE(reported, steps) << where;
    EXPECT_LE(reported, steps + 2) << where;
  } else {
    EXPECT_EQ(first_number(log, R"(([0-9]+) steps of dt)"), steps) << where;
    EXPECT_EQ(first_number(log, R"(([0-9]+) output steps)"), written) << where;
  }
  if (t.size() >= 2) {
    const double dt = t[1] - t[0];
    for (size_t k = 1; k < t.size(); ++k) {
      const double h = t[k] - t[k - 1];
      EXPECT_GT(h, 0.0) << "step " << k << ": " << where;
      if (k + 1 < t.size()) EXPECT_NEAR(h, dt, 1e-6 * dt) << "step " << k << ": " << where;
      else EXPECT_LE(h, dt * (1.0 + 1e-6)) << "last step: " << where;
    }
  }
  return 0;
}

}  // namespace

TEST(Limits, ExtremeTimesRunTheStepsTheyReportOrAreRefused) {
  const fs::path d = scratch("limits-property");
  const std::vector<std::string> dts = {"1e-300", "1e-3", "auto"}, ends = {"auto", "1e-3", "1e30"},
                                 entries = {"0", "1e30"}, speeds = {"1e-300", "1", "1e300"},
                                 accelerations = {"0", "1e300", "-0.5"};
  std::vector<Case> cases;
  for (const bool beam : {true, false})
    for (const auto& dt : dts)
      for (const auto& end : ends)
        for (const auto& entry : entries)
          for (const auto& v : speeds)
            for (const auto& a : accelerations) {
              Case c;
              c.beam = beam;
              const std::string load = beam ? "loads.mass." : "loads.F.";
              c.label = std::string(beam ? "beam" : "rod") + " dt=" + dt + " end=" + end + " entry_time=" + entry +
                        " speed=" + v + " acceleration=" + a;
              const std::string id = std::to_string(cases.size());
              c.out = (d / ("case" + id + ".h5")).string();
              c.log = (d / ("case" + id + ".log")).string();
              c.argv = {TRAVERSE_EXE, "run", (beam ? kBeam : kRod).string(), "-o", c.out, "--max-steps",
                        std::to_string(kMaxSteps), "--set", "output.every=1", "--set", "time.dt=" + dt, "--set",
                        "time.end=" + end, "--set", load + "entry_time=" + entry, "--set", load + "speed=" + v,
                        "--set", load + "acceleration=" + a};
              const std::vector<std::string> small =
                  beam ? std::vector<std::string>{"mesh.nodes=11", "beam.modes=2"}
                       : std::vector<std::string>{"mesh.ds=0.1", "output.fields=[]"};
              for (const auto& s : small) c.argv.insert(c.argv.end(), {"--set", s});
              const double auto_value = std::nan("");
              c.expected = expected_exit({beam, dt == "auto" ? auto_value : std::stod(dt),
                                          end == "auto" ? auto_value : std::stod(end), std::stod(entry), std::stod(v),
                                          std::stod(a)});
              cases.push_back(c);
            }
  // Four at a time: the runs mostly wait for MPI to start.
  int counts[4] = {0, 0, 0, 0};
  const size_t width = 4;
  for (size_t first = 0; first < cases.size(); first += width) {
    const size_t last = std::min(cases.size(), first + width);
    for (size_t i = first; i < last; ++i) cases[i].child = traverse::testing::spawn(cases[i].argv, cases[i].log);
    for (size_t i = first; i < last; ++i) {
      const int code = check_case(cases[i], traverse::testing::wait_exit(cases[i].child));
      if (code >= 0) ++counts[code];
    }
  }
  std::cout << "  " << cases.size() << " combinations: " << counts[0] << " ran the steps they reported, " << counts[2]
            << " refused (exit 2), " << counts[3] << " failed their numerics (exit 3, file marked failed)\n";
  EXPECT_EQ(counts[3], 0) << "no case of these numbers fails its numerics";
}

TEST(Limits, MemoryEstimateBoundsTheMeasuredPeak) {
  // The estimate `check` prints against the peak resident memory of the run (getrusage of the
  // child): within [0.9, 1.5] of it for a rod on the planar and the 3D path and for a beam.
  const fs::path d = scratch("limits-memory");
  struct Sized {
    std::string name, scene, args;
  };
  const std::vector<Sized> runs = {
      {"rod 20001 nodes, planar", kRod.string(), "--set mesh.ds=5e-5 --set time.dt=0.00275 --set time.end=0.0055"},
      {"rod 20001 nodes, 3D", kRod.string(),
       "--set mesh.ds=5e-5 --set time.dt=0.00275 --set time.end=0.0055 --set scheme.planar=off"},
      {"beam 500001 nodes", kBeam.string(),
       "--set mesh.nodes=500001 --set time.end=0.001 --set output.fields=[deflection,slope,bending_moment]"},
  };
  for (const auto& r : runs) {
    const auto check = traverse::testing::run_command(std::string(TRAVERSE_EXE) + " check " + r.scene + " " + r.args);
    ASSERT_EQ(check.code, 0) << check.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(check.out, m, std::regex(R"(memory estimate ([0-9.]+) (MiB|GiB) per rank)")))
        << check.out;
    const double estimate = std::stod(m[1].str()) * (m[2].str() == "GiB" ? 1024.0 : 1.0);  // MiB
    const std::string out = (d / "m.h5").string();
    std::vector<std::string> argv = {TRAVERSE_EXE, "run", r.scene, "-o", out, "--overwrite", "-q"};
    for (const auto& a : traverse::testing::split_args(r.args)) argv.push_back(a);
    const Child c = traverse::testing::spawn(argv, (d / "m.log").string());
    int status = 0;
    rusage ru{};
    ASSERT_EQ(wait4(c.pid, &status, 0, &ru), c.pid);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << traverse::testing::read_text((d / "m.log").string());
    const double measured = static_cast<double>(ru.ru_maxrss) / 1024.0;  // kB -> MiB
    std::cout << "  " << r.name << ": estimate " << estimate << " MiB, measured peak " << measured << " MiB (ratio "
              << estimate / measured << ")\n";
    EXPECT_GE(estimate, 0.9 * measured) << r.name;
    EXPECT_LE(estimate, 1.5 * measured) << r.name;
  }
}

TEST(Limits, SizesAndKeys) {
  using traverse::setup::parse_bytes;
  EXPECT_EQ(parse_bytes("4G"), 4.0 * 1024 * 1024 * 1024);
  EXPECT_EQ(parse_bytes("512M"), 512.0 * 1024 * 1024);
  EXPECT_EQ(parse_bytes("1.5KiB"), 1536.0);
  EXPECT_EQ(parse_bytes("2TB"), 2.0 * std::pow(1024.0, 4));
  EXPECT_EQ(parse_bytes("1000000"), 1e6);
  for (const char* bad : {"", "G", "-1G", "4X", "lots", "1e999", "nan", "0"}) EXPECT_LT(parse_bytes(bad), 0.0) << bad;
  EXPECT_EQ(traverse::setup::format_bytes(3.5 * 1024 * 1024 * 1024), "3.5 GiB");
  EXPECT_EQ(traverse::setup::format_bytes(512), "512 bytes");
  EXPECT_EQ(traverse::setup::format_bytes(1020.0 * 1024), "1020 KiB");
}

namespace {

// A size as `check` prints it (format_bytes) in bytes.
double bytes_of(const std::string& number, const std::string& unit) {
  const std::vector<std::string> units = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  for (size_t u = 0; u < units.size(); ++u)
    if (unit == units[u]) return std::stod(number) * std::pow(1024.0, static_cast<double>(u));
  ADD_FAILURE() << "unknown unit " << unit;
  return 0.0;
}

}  // namespace

TEST(Limits, BeamOutputEveryAutoKeepsFourOutputsPerPeriodOfTheHighestMode) {
  // A simply supported beam (closed-form frequencies omega_n = (n pi / L)^2 sqrt(E I / rho A))
  // with output.every left at its default: the outputs are the largest whole number of steps
  // apart that keeps at least 4 per period of the highest mode, and `check` says so.
  const fs::path d = scratch("limits-every");
  const double L = 10.0, E = 2.0e11, rho = 7850.0, b = 0.2, h = 0.3;
  for (const int modes : {3, 7}) {
    const fs::path scene = d / ("ss" + std::to_string(modes) + ".yaml");
    std::ofstream(scene) << "model: beam\nbeam:\n  length: 10.0\n  youngs_modulus: 2.0e11\n  density: 7850\n"
                            "  section: {type: rectangle, width: 0.2, height: 0.3}\n"
                            "  supports: simply-supported\n  modes: "
                         << modes
                         << "\nloads:\n  F: {type: moving_force, force: 1000, speed: 10}\n"
                            "output:\n  probes:\n    mid: {type: deflection, at: 5.0}\n";
    const double omega = std::pow(modes * M_PI / L, 2) * std::sqrt(E * b * h * h * h / 12.0 / (rho * b * h));
    const double period = 2.0 * M_PI / omega;
    const auto check = traverse::testing::run_command(std::string(TRAVERSE_EXE) + " check " + scene.string());
    ASSERT_EQ(check.code, 0) << check.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(check.out, m, std::regex(R"(dt = ([0-9.e+-]+) s to t)"))) << check.out;
    const double dt = std::stod(m[1].str());
    const long stride = static_cast<long>(std::floor(period / 4.0 / dt * (1.0 + 1e-9)));
    ASSERT_GE(stride, 2) << "the case should thin the output: " << check.out;
    EXPECT_NE(check.out.find("output.every: auto = " + std::to_string(stride) + " (4 outputs per period of mode " +
                             std::to_string(modes)),
              std::string::npos)
        << check.out;
    const long announced = first_number(check.out, R"(([0-9]+) output steps)");
    const std::string out = (d / ("ss" + std::to_string(modes) + ".h5")).string();
    const auto run = traverse::testing::run_command(std::string(TRAVERSE_EXE) + " run " + scene.string() + " -o " +
                                                    out + " --overwrite -q");
    ASSERT_EQ(run.code, 0) << run.out;
    const traverse::output::Reader f(out);
    const std::vector<double> t = f.time();
    ASSERT_GE(t.size(), 3u);
    EXPECT_EQ(static_cast<long>(f.steps_written()), announced) << check.out;
    for (size_t k = 1; k + 1 < t.size(); ++k) {
      EXPECT_NEAR(t[k] - t[k - 1], stride * dt, 1e-9 * stride * dt) << "output " << k;
      EXPECT_LE(t[k] - t[k - 1], period / 4.0 * (1.0 + 1e-9)) << "output " << k;
    }
  }
}

TEST(Limits, CheckEstimatesTheOutputFileSize) {
  // The sizes `check` prints beside the memory against the files the run writes: within 25 %
  // for beams and rods, with and without fields.
  const fs::path d = scratch("limits-output-size");
  const std::string cable = (fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "default.yaml").string();
  const std::vector<std::pair<std::string, std::string>> runs = {
      {kBeam.string(), ""},
      {kBeam.string(), "--set output.every=auto --set output.fields=[deflection,slope,bending_moment]"},
      {cable, ""},
      {cable, "--set output.fields=[r,R,kappa,n]"},
      {kRod.string(), "--set output.fields=[] --set mesh.ds=0.005"},
  };
  for (const auto& [scene, args] : runs) {
    const std::string label = scene + " " + args;
    const auto check = traverse::testing::run_command(std::string(TRAVERSE_EXE) + " check " + scene + " " + args);
    ASSERT_EQ(check.code, 0) << check.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(check.out, m,
                                  std::regex(R"(output about ([0-9.]+) (bytes|KiB|MiB|GiB) \(\+ ([0-9.]+) )"
                                             R"((bytes|KiB|MiB|GiB) \.xmf sidecar\))")))
        << check.out;
    const double h5 = bytes_of(m[1].str(), m[2].str()), xmf = bytes_of(m[3].str(), m[4].str());
    const fs::path out = d / "size.h5";
    const auto run = traverse::testing::run_command(std::string(TRAVERSE_EXE) + " run " + scene + " " + args +
                                                    " -o " + out.string() + " --overwrite -q");
    ASSERT_EQ(run.code, 0) << run.out;
    const double h5_real = static_cast<double>(fs::file_size(out));
    const double xmf_real = static_cast<double>(fs::file_size(d / "size.xmf"));
    std::cout << "  " << label << ": .h5 estimate " << h5 << ", written " << h5_real << "; .xmf estimate " << xmf
              << ", written " << xmf_real << "\n";
    EXPECT_GE(h5, 0.8 * h5_real) << label;
    EXPECT_LE(h5, 1.25 * h5_real) << label;
    EXPECT_GE(xmf, 0.8 * xmf_real) << label;
    EXPECT_LE(xmf, 1.25 * xmf_real) << label;
  }
}

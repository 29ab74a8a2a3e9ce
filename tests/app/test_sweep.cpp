// traverse sweep (docs/sweeps.md): the --vary parser (ranges without drift, lists, the
// cartesian product), the sweep in one process and on 2 ranks against separate `traverse run
// --set` runs (same index, the same numbers in every case file), bad options refused before
// any case runs, failing cases recorded while the others finish, ranks that share one queue
// (a signal to one rank ends the sweep).
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli.hpp"
#include "process.hpp"
#include "sweep.hpp"
#include "sweep_spec.hpp"
#include "traverse/output/reader.hpp"

using traverse::testing::children_of;
using traverse::testing::read_text;
using traverse::testing::scratch;

namespace fs = std::filesystem;
using traverse::app::parse_vary;
using traverse::app::UsageError;

namespace {

const std::string kExe = TRAVERSE_EXE;
const fs::path kCable = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "default.yaml";
const fs::path kBeam = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "beam" / "cantilever.yaml";
const fs::path kArch = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "arch" / "shallow_arch_v20.0.yaml";

std::string mpiexec(int ranks) {
  return std::string(TRAVERSE_MPIEXEC) + " --allow-run-as-root --oversubscribe -n " + std::to_string(ranks) + " ";
}

// The index as rows of fields (no quoted commas in these tests' values).
std::vector<std::vector<std::string>> read_csv(const fs::path& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> fields(1);
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) fields.emplace_back();
      else fields.back() += c;
    }
    rows.push_back(fields);
  }
  return rows;
}

std::size_t column(const std::vector<std::string>& header, const std::string& name) {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return i;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

}  // namespace

TEST(SweepSpec, RangesListsAndProduct) {
  const auto r = parse_vary("loads.F.speed=0.1:2.0:0.1");
  ASSERT_EQ(r.values.size(), 20u);
  EXPECT_EQ(r.values[2], "0.3");  // a + k step, with the decimals of the range: not 0.30000000000000004
  EXPECT_EQ(r.values.back(), "2.0");
  for (std::size_t k = 0; k < r.values.size(); ++k) EXPECT_DOUBLE_EQ(std::stod(r.values[k]), 0.1 * double(k + 1));
  const auto e = parse_vary("time.dt=1e-3:3e-3:1e-3");
  ASSERT_EQ(e.values.size(), 3u);
  EXPECT_DOUBLE_EQ(std::stod(e.values[2]), 3e-3);
  const auto down = parse_vary("a.b=1:0:-0.25");
  EXPECT_EQ(down.values, (std::vector<std::string>{"1.00", "0.75", "0.50", "0.25", "0.00"}));
  const auto mixed = parse_vary("output.fields=[r],[r, kappa],5,1:2:1");
  EXPECT_EQ(mixed.values, (std::vector<std::string>{"[r]", "[r, kappa]", "5", "1", "2"}));
  const auto cases = traverse::app::sweep_cases({parse_vary("a=1,2"), parse_vary("b=x,y,z")}, 100);
  ASSERT_EQ(cases.size(), 6u);
  EXPECT_EQ(cases[1], (std::vector<std::string>{"a=1", "b=y"}));  // the last option varies fastest
  EXPECT_EQ(cases[3], (std::vector<std::string>{"a=2", "b=x"}));
  EXPECT_THROW(traverse::app::sweep_cases({parse_vary("a=1,2"), parse_vary("a=3")}, 100), UsageError);
  // --with: varied together with the option before it.
  auto with = parse_vary("c=10,20", "--with");
  with.with_previous = true;
  const auto joined = traverse::app::sweep_cases({parse_vary("a=1,2"), with, parse_vary("b=x,y,z")}, 100);
  ASSERT_EQ(joined.size(), 6u);
  EXPECT_EQ(joined[4], (std::vector<std::string>{"a=2", "c=20", "b=y"}));
  auto short_with = parse_vary("c=10", "--with");
  short_with.with_previous = true;
  EXPECT_THROW(traverse::app::sweep_cases({parse_vary("a=1,2"), short_with}, 100), UsageError);
  EXPECT_THROW(traverse::app::sweep_cases({short_with}, 100), UsageError);
  EXPECT_THROW(traverse::app::sweep_cases({parse_vary("a=1:100:1"), parse_vary("b=1:100:1")}, 1000), UsageError);
  for (const char* bad : {"a.b", "=1", "a.b=", "a.b=1,,2", "a..b=1", "a.b=1:2", "a.b=1:2:0", "a.b=2:1:1", "a.b=1:x:1",
                          "a.b=0:1e9:1e-3"}) {
    try {
      parse_vary(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(e.message.find("--vary"), std::string::npos) << e.message;
      EXPECT_NE(e.message.find("expected"), std::string::npos) << e.message;
    }
  }
  EXPECT_THROW(traverse::app::parse_summary("midspan.y"), UsageError);
  EXPECT_THROW(traverse::app::parse_summary("midspan.w:min"), UsageError);
  EXPECT_EQ(traverse::app::parse_summary("midspan.y:min").component, 1);
}

TEST(Sweep, OneProcessAndRanksMatchSeparateRuns) {
  const fs::path d = scratch("sweep-ranks");
  const std::string common = " --set mesh.ds=0.04 --set output.fields=[r]";
  const std::string vary = " --vary loads.F.speed=2,3.5:4.5:1 --vary scheme.rho_inf=1,0.8 --summary midspan.y:min";
  const auto one = traverse::testing::run_command(kExe + " sweep " + kCable.string() + " -o " + (d / "np1").string() +
                                                  common + vary + " -q");
  ASSERT_EQ(one.code, 0) << one.out;
  const auto two = traverse::testing::run_command(mpiexec(2) + kExe + " sweep " + kCable.string() + " -o " +
                                                  (d / "np2").string() + common + vary + " -q");
  ASSERT_EQ(two.code, 0) << two.out;
  // 2 ranks again, not quiet: the header names them, the summary line gives the sweep's own
  // wall time.
  const auto t0 = std::chrono::steady_clock::now();
  const auto loud = traverse::testing::run_command(mpiexec(2) + kExe + " sweep " + kCable.string() + " -o " +
                                                   (d / "np2-loud").string() + common + vary);
  const double process_wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(loud.code, 0) << loud.out;
  EXPECT_NE(loud.out.find("6 cases on 2 rank(s)"), std::string::npos) << loud.out;
  const std::string done = "sweep done: 6 of 6 cases complete in ";
  const std::size_t at = loud.out.find(done);
  ASSERT_NE(at, std::string::npos) << loud.out;
  const double own_wall = std::stod(loud.out.substr(at + done.size()));
  const auto a = read_csv(d / "np1" / "index.csv"), b = read_csv(d / "np2" / "index.csv"),
             j = read_csv(d / "np2-loud" / "index.csv");
  ASSERT_EQ(a.size(), 7u);  // the header and 3 x 2 cases
  ASSERT_EQ(b.size(), a.size());
  ASSERT_EQ(j.size(), a.size());
  const auto& h = a[0];
  EXPECT_EQ(h, b[0]);
  EXPECT_EQ(h, j[0]);
  const std::size_t wall = column(h, "wall_s"), speed = column(h, "loads.F.speed"), rho = column(h, "scheme.rho_inf"),
                    out = column(h, "output"), status = column(h, "status"), summary = column(h, "midspan.y:min");
  for (std::size_t row = 1; row < a.size(); ++row) {
    ASSERT_EQ(a[row].size(), h.size());
    for (std::size_t c = 0; c < h.size(); ++c) {
      if (c == wall) continue;
      EXPECT_EQ(a[row][c], b[row][c]) << "row " << row << " column " << h[c];
      EXPECT_EQ(a[row][c], j[row][c]) << "2 ranks, not quiet: row " << row << " column " << h[c];
    }
    EXPECT_EQ(a[row][status], "complete");
    // Each case ran within the sweep's own time, which the process's wall time holds (the
    // printed times have 4 and 3 decimals).
    EXPECT_LE(std::stod(j[row][wall]), own_wall + 1e-3) << j[row][wall] << " s, sweep " << own_wall << " s";
    EXPECT_LE(own_wall, process_wall) << loud.out;
    // The case as a run of its own, with --set.
    const std::string single = (d / ("single_" + std::to_string(row - 1) + ".h5")).string();
    const auto r = traverse::testing::run_command(kExe + " run " + kCable.string() + " -o " + single + common +
                                                  " --set loads.F.speed=" + a[row][speed] +
                                                  " --set scheme.rho_inf=" + a[row][rho] + " -q");
    ASSERT_EQ(r.code, 0) << r.out;
    for (const char* dir : {"np1", "np2", "np2-loud"}) {
      std::string why;
      const double diff = traverse::testing::max_file_difference((d / dir / a[row][out]).string(), single, why);
      std::printf("case %zu (%s): %s vs the single run: max difference %g %s\n", row - 1, a[row][speed].c_str(), dir,
                  diff, why.c_str());
      EXPECT_EQ(diff, 0.0) << dir << " case " << row - 1 << ": " << why;
    }
    // The summary is the minimum of midspan y over the output steps of the case.
    const auto p = traverse::output::Reader(single).probe("midspan");
    double lowest = INFINITY;
    for (std::size_t s = 0; s < p.rows; ++s) lowest = std::min(lowest, p.values[s * p.components + 1]);
    EXPECT_EQ(std::stod(a[row][summary]), lowest) << "row " << row;
  }
  EXPECT_EQ(a[3][speed], "3.5");
  // The comparison sees a difference where there is one: rho_inf 1 against 0.8.
  std::string why;
  const double other = traverse::testing::max_file_difference((d / "np1" / a[1][out]).string(),
                                                              (d / "np1" / a[2][out]).string(), why);
  std::printf("case 0 vs case 1 (rho_inf %s vs %s): max difference %g\n", a[1][rho].c_str(), a[2][rho].c_str(), other);
  EXPECT_GT(other, 0.0);
}

TEST(Sweep, BadOptionsRefusedBeforeAnyCase) {
  const fs::path d = scratch("sweep-bad");
  struct Bad {
    std::string args, expect;
  };
  const std::vector<Bad> bad = {
      {"--vary loads.F.sped=1,2", "--vary loads.F.sped: expected a key of 'loads.F'"},
      {"--vary loads.G.speed=1", "--vary loads.G.speed: expected one of the names of 'loads'"},
      {"--vary mesh.ds.x=1", "--vary mesh.ds.x: expected 'mesh.ds' to be a section"},
      {"--vary loads.F.speed=1:2", "--vary loads.F.speed: expected a value or a range a:b:step"},
      {"--vary loads.F.speed", "--vary loads.F.speed: expected KEY.PATH=v1,v2,..."},
      {"--vary loads.F.speed=1 --vary loads.F.speed=2", "--vary loads.F.speed: expected each key once"},
      {"--vary output.file=x.h5", "--vary output.file: expected a scene key"},
      {"--vary loads.F.speed=1 --summary midspan:min", "--summary midspan:min: expected a component"},
      {"--vary loads.F.speed=1 --summary nowhere.y:min", "--summary nowhere.y:min: expected a probe of"},
      {"--vary loads.F.speed=1 --summary F_position.x:max",
       "--summary F_position.x:max: expected probe 'F_position' without a component (it is a scalar), found .x; write "
       "--summary F_position:max"},
      {"", "'sweep': expected at least one --vary"},
      {"--vary loads.F.speed=1 -j 2", "unknown option '-j'"},
  };
  for (const auto& b : bad) {
    const fs::path out = d / "out";
    const auto r = traverse::testing::run_command(kExe + " sweep " + kCable.string() + " -o " + out.string() + " " + b.args);
    EXPECT_EQ(r.code, 2) << b.args << "\n" << r.out;
    EXPECT_NE(r.out.find(b.expect), std::string::npos) << b.args << "\n" << r.out;
    EXPECT_FALSE(fs::exists(out)) << b.args << ": the sweep made its directory before refusing";
  }
  const auto no_dir = traverse::testing::run_command(kExe + " sweep " + kCable.string() + " --vary loads.F.speed=1");
  EXPECT_EQ(no_dir.code, 2) << no_dir.out;
  EXPECT_NE(no_dir.out.find("-o DIR"), std::string::npos) << no_dir.out;
}

TEST(Sweep, FailingCasesRecordedOthersFinish) {
  const fs::path d = scratch("sweep-failing");
  // RK4 with dt = 1e-3 is unstable for 10 modes of this beam (exit 3); dt = -1 is bad input.
  const std::string args = " --set beam.modes=10 --set loads.mass.speed=5 --set output.every=50"
                           " --vary time.dt=1e-5,1e-3,-1,2e-5 --summary tip:min -q";
  struct Variant {
    std::string name, launcher, options;
  };
  for (const Variant& v : {Variant{"np1", "", ""}, Variant{"np2", mpiexec(2), ""}}) {
    const std::string& ranks = v.name;
    const fs::path out = d / v.name;
    const auto r = traverse::testing::run_command(v.launcher + kExe + " sweep " + kBeam.string() + " -o " + out.string() +
                                                  args + v.options);
    EXPECT_EQ(r.code, 3) << ranks << ": the first failed case's exit code\n" << r.out;
    const auto rows = read_csv(out / "index.csv");
    ASSERT_EQ(rows.size(), 5u) << r.out;
    const auto& h = rows[0];
    const std::size_t status = column(h, "status"), code = column(h, "exit_code"), file = column(h, "output"),
                      summary = column(h, "tip:min"), message = column(h, "message");
    const std::vector<std::string> statuses = {"complete", "numerics failed", "bad input", "complete"};
    const std::vector<std::string> codes = {"0", "3", "2", "0"};
    for (std::size_t k = 0; k < 4; ++k) {
      const auto& row = rows[k + 1];
      EXPECT_EQ(row[status], statuses[k]) << ranks << ", case " << k;
      EXPECT_EQ(row[code], codes[k]) << ranks << ", case " << k;
      EXPECT_EQ(row[summary].empty(), k == 1 || k == 2) << "a summary only for complete cases";
      if (k == 0 || k == 3) {
        EXPECT_EQ(traverse::output::Reader((out / row[file]).string()).status(), "complete");
        EXPECT_LT(std::stod(row[summary]), 0.0);
      }
    }
    EXPECT_EQ(traverse::output::Reader((out / rows[2][file]).string()).status().rfind("failed: ", 0), 0u)
        << "the numerics failure keeps its file, marked failed";
    EXPECT_NE(rows[2][message].find("time.dt"), std::string::npos) << rows[2][message];
    EXPECT_TRUE(rows[3][file].empty()) << "no file for a bad-input case";
    EXPECT_NE(rows[3][message].find("time.dt: expected"), std::string::npos) << rows[3][message];
  }
  // The same sweep again refuses to replace its files without --overwrite.
  const auto again = traverse::testing::run_command(kExe + " sweep " + kBeam.string() + " -o " + (d / "np1").string() + args);
  EXPECT_EQ(again.code, 2) << again.out;
  EXPECT_NE(again.out.find("--overwrite"), std::string::npos) << again.out;
}

// On 2 ranks the ranks share one queue: SIGTERM to one rank interrupts its case at a time step,
// that rank records every case left in the queue as not run, so the other rank ends after the
// case it is running (completed): no rank starts another case.
TEST(Sweep, RanksShareTheQueueAndASignalToOneEndsTheSweep) {
  const fs::path d = scratch("sweep-ranks-signal");
  const auto c = traverse::testing::spawn(
      traverse::testing::split_args(mpiexec(2) + kExe + " sweep " + kCable.string() + " -o " + (d / "out").string() +
                                    " --set mesh.ds=0.05 --set time.dt=1e-4 --set time.end=4 --set output.fields=[]"
                                    " --vary loads.F.speed=1,2,3,4 -q"),
      (d / "out.log").string());
  ASSERT_TRUE(traverse::testing::wait_for_steps(c, (d / "out" / "case_0000.h5").string(), 100)) << read_text(c.log);
  ASSERT_TRUE(traverse::testing::wait_for_steps(c, (d / "out" / "case_0001.h5").string(), 100)) << read_text(c.log);
  const auto ranks = children_of(c.pid);
  ASSERT_EQ(ranks.size(), 2u) << "the launcher's children: the two ranks";
  kill(ranks[0], SIGTERM);
  EXPECT_EQ(traverse::testing::wait_exit(c), 128 + SIGTERM) << read_text(c.log);
  const auto rows = read_csv(d / "out" / "index.csv");
  ASSERT_EQ(rows.size(), 5u) << read_text(c.log);
  const std::size_t status = column(rows[0], "status"), code = column(rows[0], "exit_code");
  std::vector<std::string> first_two{rows[1][status], rows[2][status]};
  std::sort(first_two.begin(), first_two.end());
  EXPECT_EQ(first_two, (std::vector<std::string>{"complete", "interrupted"})) << read_text(c.log);
  for (std::size_t k = 0; k < 2; ++k)
    EXPECT_EQ(rows[k + 1][code], rows[k + 1][status] == "complete" ? "0" : std::to_string(128 + SIGTERM));
  for (std::size_t k = 2; k < 4; ++k) {
    EXPECT_EQ(rows[k + 1][status], "not run") << "case " << k;
    EXPECT_EQ(rows[k + 1][code], "-1") << "case " << k;
    EXPECT_FALSE(fs::exists(d / "out" / ("case_000" + std::to_string(k) + ".h5"))) << "case " << k << " started";
  }
}

// A sweep whose cases solve through Tpetra (KLU2): on 2 ranks, each case on one rank, the
// same files as in one process.
TEST(Sweep, CasesOnTpetraMatchOneProcess) {
  const fs::path d = scratch("sweep-tpetra");
  const std::string args = " --set mesh.ds=0.05 --set 'solver.Linear Solver=KLU2' --vary loads.F.speed=10,20,30 -q";
  for (const char* name : {"one", "np2"}) {
    const auto r = traverse::testing::run_command((std::string(name) == "np2" ? mpiexec(2) : std::string()) + kExe +
                                                  " sweep " + kArch.string() + " -o " + (d / name).string() + args);
    ASSERT_EQ(r.code, 0) << name << "\n" << r.out;
  }
  const auto a = read_csv(d / "one" / "index.csv"), b = read_csv(d / "np2" / "index.csv");
  ASSERT_EQ(a.size(), 4u);
  ASSERT_EQ(b.size(), a.size());
  const std::size_t status = column(a[0], "status"), out = column(a[0], "output");
  for (std::size_t row = 1; row < a.size(); ++row) {
    EXPECT_EQ(b[row][status], "complete") << "case " << row - 1;
    std::string why;
    const double diff = traverse::testing::max_file_difference((d / "one" / a[row][out]).string(),
                                                               (d / "np2" / b[row][out]).string(), why);
    EXPECT_EQ(diff, 0.0) << "case " << row - 1 << ": " << why;
  }
}

TEST(Sweep, BeamSummaryIsThePeakOverEveryTimeStep) {
  // A beam run records each probe's extremes over every time step (output::ProbeExtremes):
  // a run that writes every 7th step holds the extremes of the series written at every step,
  // and a sweep's summary of such a run is that peak, not the peak of the steps it wrote.
  const fs::path d = scratch("sweep-peaks");
  const fs::path train = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "beam" / "axle_train.yaml";
  const std::string common = " --set beam.modes=6 --set time.dt=1e-3 --set mesh.nodes=21 --set loads.train.speed=60 -q";
  for (const char* every : {"1", "7"}) {
    const auto r = traverse::testing::run_command(kExe + " run " + train.string() + " -o " +
                                                  (d / (std::string("every") + every + ".h5")).string() + common +
                                                  " --set output.every=" + every);
    ASSERT_EQ(r.code, 0) << r.out;
  }
  const traverse::output::Reader all((d / "every1.h5").string()), sparse((d / "every7.h5").string());
  ASSERT_GT(all.probe_names().size(), 2u);
  const std::vector<double> times = all.time();
  double true_peak = 0.0, written_peak = 0.0;
  for (const auto& name : all.probe_names()) {
    const auto p = all.probe(name), q = sparse.probe(name);
    const auto ea = all.probe_extremes(name), es = sparse.probe_extremes(name);
    ASSERT_TRUE(ea && es) << name;
    for (std::size_t c = 0; c < p.components; ++c) {
      double lo = NAN, hi = NAN, t_lo = NAN, t_hi = NAN;
      for (std::size_t s = 0; s < p.rows; ++s) {
        const double v = p.values[s * p.components + c];
        if (std::isnan(v)) continue;
        if (!(v >= lo)) lo = v, t_lo = times[s];
        if (!(v <= hi)) hi = v, t_hi = times[s];
      }
      EXPECT_EQ(ea->min[c], lo) << name;
      EXPECT_EQ(ea->max[c], hi) << name;
      EXPECT_EQ(ea->time_of_min[c], t_lo) << name;
      EXPECT_EQ(ea->time_of_max[c], t_hi) << name;
      EXPECT_EQ(es->min[c], lo) << name << " (every 7th step written)";
      EXPECT_EQ(es->max[c], hi) << name << " (every 7th step written)";
      EXPECT_EQ(es->time_of_max[c], t_hi) << name << " (every 7th step written)";
      if (name != "deck") continue;
      true_peak = std::max(std::abs(lo), std::abs(hi));
      for (std::size_t s = 0; s < q.rows; ++s) written_peak = std::max(written_peak, std::abs(q.values[s]));
    }
  }
  std::printf("deck: peak over every step %.17g m/s^2, over the steps of the every-7th file %.17g\n", true_peak,
              written_peak);
  EXPECT_LE(written_peak, true_peak);
  const auto sw = traverse::testing::run_command(kExe + " sweep " + train.string() + " -o " + (d / "sweep").string() +
                                                 common + " --set output.every=7 --vary loads.train.speed=60" +
                                                 " --summary deck:absmax");
  ASSERT_EQ(sw.code, 0) << sw.out;
  const auto rows = read_csv(d / "sweep" / "index.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(std::stod(rows[1][column(rows[0], "deck:absmax")]), true_peak);
}

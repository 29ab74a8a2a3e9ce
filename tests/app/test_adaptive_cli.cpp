// Adaptive time stepping (time.adaptive, docs/adaptive.md) through the executable: bad
// controls refused with exit 2 naming the key; the output times of an adaptive run are those
// of the fixed-dt run and its error against a refined fixed-dt run falls with the tolerance;
// 1 and 2 ranks take the same steps; a snap through of the undamped shallow arch is passed with
// rejected steps; the beam's integrators and the rod's and the beam's coupled mass follow the
// tolerance.
// (Restart of an adaptive run: test_interrupt_restart.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <regex>
#include <tuple>
#include <vector>

#include "process.hpp"
#include "traverse/setup/step_control.hpp"

namespace fs = std::filesystem;
using namespace traverse::testing;
using traverse::output::Reader;

namespace {

const std::string kExe = TRAVERSE_EXE;
const std::string kCable = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/default.yaml";
const std::string kArch = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/arch/shallow_arch_v0.5.yaml";
const std::string kMpi = std::string(TRAVERSE_MPIEXEC) + " --allow-run-as-root --oversubscribe -n 2 ";

// The adaptive counters the run wrote to its output file (root attributes steps_accepted,
// steps_rejected, steps_failed, dt_largest); a file without them fails the test.
struct Counts {
  long accepted = -1, rejected = -1, failed = -1;
  double largest_dt = -1.0;
};
Counts counts(const std::string& file) {
  const Reader r(file);
  Counts c;
  for (const char* name : {"steps_accepted", "steps_rejected", "steps_failed", "dt_largest"})
    if (!r.has_attribute(name)) {
      ADD_FAILURE() << file << " has no attribute " << name;
      return c;
    }
  c.accepted = std::stol(r.attribute("steps_accepted"));
  c.rejected = std::stol(r.attribute("steps_rejected"));
  c.failed = std::stol(r.attribute("steps_failed"));
  c.largest_dt = std::stod(r.attribute("dt_largest"));
  return c;
}

/// Largest |difference| of the midspan probe's vertical component (y) of two runs.
double midspan_difference(const std::string& a, const std::string& b) {
  const auto pa = Reader(a).probe("midspan"), pb = Reader(b).probe("midspan");
  double d = 0.0;
  for (size_t i = 0; i < std::min(pa.rows, pb.rows); ++i) d = std::max(d, std::abs(pa.values[3 * i + 1] - pb.values[3 * i + 1]));
  return d;
}

// `traverse check` warns where the measured work-precision found fixed steps cheaper at equal
// error (docs/adaptive.md "Work and precision"): loads at constant speed on an unformed rod (the
// cable), a coupled mass without friction (the robot); not on an arch (a snap to follow), not
// with friction (a mass that can stick), not without time.adaptive. The scene stays valid (exit 0).
TEST(AdaptiveCli, CheckWarnsWhereFixedStepsAreCheaper) {
  const std::string src = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/";
  const std::string adaptive = " --set time.adaptive.tolerance=1e-3";
  const std::vector<std::tuple<std::string, std::string>> cases = {
      {kCable + adaptive, "loads at constant speed"},
      {src + "rod/coupled_inspection_robot.yaml" + adaptive, "a coupled mass without friction"},
      {kArch + adaptive, ""},
      {src + "rod/coupled_inspection_robot.yaml --set loads.robot.friction=0.2" + adaptive, ""},
      {kCable, ""},
  };
  for (const auto& [args, warning] : cases) {
    const RunResult r = run_command(kExe + " check " + args);
    EXPECT_EQ(r.code, 0) << args << "\n" << r.out;
    if (warning.empty()) {
      EXPECT_EQ(r.out.find("time.adaptive:"), std::string::npos) << args << ": no warning expected\n" << r.out;
    } else {
      EXPECT_NE(r.out.find("warning: "), std::string::npos) << args << "\n" << r.out;
      EXPECT_NE(r.out.find(warning), std::string::npos) << args << "\n" << r.out;
      EXPECT_NE(r.out.find("docs/adaptive.md"), std::string::npos) << args << "\n" << r.out;
    }
  }
}

TEST(AdaptiveCli, BadControlsExitWith2NamingTheKey) {
  const fs::path d = scratch("adaptive-bad");
  const std::string out = (d / "x.h5").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--set time.adaptive.tolerance=0", "time.adaptive.tolerance"},
      {"--set time.adaptive.tolerance=-1e-3", "time.adaptive.tolerance"},
      {"--set time.adaptive.tolerance=.nan", "time.adaptive.tolerance"},
      {"--set time.adaptive.tolerance=0.2", "time.adaptive.tolerance"},
      {"--set time.adaptive.dt_min=1e-3", "time.adaptive.tolerance"},  // required
      {"--set time.adaptive.tolerance=1e-3 --set time.adaptive.dt_min=1 --set time.adaptive.dt_max=0.1",
       "time.adaptive.dt_min"},
      {"--set time.adaptive.tolerance=1e-3 --set time.adaptive.dt_max=-1", "time.adaptive.dt_max"},
      {"--set time.adaptive.tolerance=1e-3 --set time.adaptive.growth=1", "time.adaptive.growth"},
      {"--set time.adaptive.tolerance=1e-3 --set time.adaptive.shrink=0", "time.adaptive.shrink"},
      {"--set time.adaptive.tolerance=1e-3 --set time.adaptive.on=[u]", "time.adaptive.absolute_u"},
      {"--set time.adaptive.tolerance=1e-3 --set time.adaptive.on=[]", "time.adaptive.on"},
      {"--set time.adaptive.tolerance=1e-3 --set time.adaptive.on=[speed]", "time.adaptive.on"},
  };
  for (const auto& [args, key] : cases) {
    const RunResult r = run_command(kExe + " run " + kCable + " -o " + out + " --overwrite -q " + args);
    std::cout << "  " << args << " -> exit " << r.code << ": " << r.out.substr(0, r.out.find('\n')) << "\n";
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(key), std::string::npos) << args << ": the message should name " << key << "\n" << r.out;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
}

// A restart keeps whether the run is adaptive: either change is refused with exit 2 saying so.
TEST(AdaptiveCli, RestartKeepsAdaptiveOrFixedSteps) {
  const fs::path d = scratch("adaptive-restart-kind");
  const std::string fixed = (d / "fixed.h5").string(), adaptive = (d / "adaptive.h5").string();
  const std::string base = kExe + " run " + kCable + " --overwrite -q --set mesh.ds=0.05 ";
  ASSERT_EQ(run_command(base + "-o " + fixed).code, 0);
  ASSERT_EQ(run_command(base + "-o " + adaptive + " --set time.adaptive.tolerance=1e-3").code, 0);
  const RunResult a = run_command(kExe + " run --restart " + fixed + " -q --set time.adaptive.tolerance=1e-3");
  std::cout << "  fixed run restarted adaptive: exit " << a.code << ": " << a.out.substr(0, a.out.find('\n')) << "\n";
  EXPECT_EQ(a.code, 2);
  EXPECT_NE(a.out.find("took fixed steps"), std::string::npos) << a.out;
  // The adaptive run's stored scene has the section; a scene file without it is the change.
  const RunResult b = run_command(kExe + " run --restart " + adaptive + " " + kCable + " -q --set mesh.ds=0.05");
  std::cout << "  adaptive run restarted fixed: exit " << b.code << ": " << b.out.substr(0, b.out.find('\n')) << "\n";
  EXPECT_EQ(b.code, 2);
  EXPECT_NE(b.out.find("was adaptive (time.adaptive)"), std::string::npos) << b.out;
}

// The hanging cable at ds = 0.02: the adaptive runs write at the fixed run's output times;
// their midspan trace error against a fixed-dt run at ds / (64 v) falls in proportion to the
// tolerance (the local error per step held at tol (tol / 1e-3)^(1/2)): over the two decades as
// tol^q, asserted 0.8 < q < 1.25, at least 5 times per decade (measured q = 1.06).
TEST(AdaptiveCli, OutputTimesAreTheFixedRunsAndTheErrorFallsWithTheTolerance) {
  const fs::path d = scratch("adaptive-cable");
  const std::string base = kExe + " run " + kCable + " --overwrite --set mesh.ds=0.02 ";
  const double dt = 0.02 / 3.63418;
  char ref_args[128];
  std::snprintf(ref_args, sizeof ref_args, "--set time.dt=%.17g --set output.every=64 -q", dt / 64.0);
  const std::string ref = (d / "ref.h5").string(), fixed = (d / "fixed.h5").string();
  ASSERT_EQ(run_command(base + "-o " + ref + " " + ref_args).code, 0);
  ASSERT_EQ(run_command(base + "-o " + fixed + " -q").code, 0);
  const auto t_fixed = Reader(fixed).time();
  std::vector<double> errors;
  for (const char* tol : {"1e-2", "1e-3", "1e-4"}) {
    const std::string out = (d / (std::string("ad") + tol + ".h5")).string();
    const RunResult r = run_command(base + "-o " + out + " --set time.adaptive.tolerance=" + tol);
    ASSERT_EQ(r.code, 0) << r.out;
    const Counts c = counts(out);
    ASSERT_GT(c.accepted, 0) << r.out;
    const auto t = Reader(out).time();
    ASSERT_EQ(t.size(), t_fixed.size());
    double dtime = 0.0;
    for (size_t i = 0; i < t.size(); ++i) dtime = std::max(dtime, std::abs(t[i] - t_fixed[i]));
    EXPECT_LE(dtime, 1e-12);
    errors.push_back(midspan_difference(out, ref));
    std::cout << "  tolerance " << tol << ": " << c.accepted << " accepted, " << c.rejected << " rejected, midspan error "
              << errors.back() << " m; output times differ by at most " << dtime << " s\n";
  }
  std::cout << "  fixed dt = ds / v: midspan error " << midspan_difference(fixed, ref) << " m\n";
  EXPECT_LT(errors[1], 0.2 * errors[0]);
  EXPECT_LT(errors[2], 0.2 * errors[1]);
  const double q = std::log10(errors[0] / errors[2]) / 2.0;
  std::cout << "  error ~ tol^" << q << " over two decades\n";
  EXPECT_GT(q, 0.8);
  EXPECT_LT(q, 1.25);
}

// The same on an extensible cable that stretches (E A = 200 N: strains of about 1 %): the
// estimate controls the nodes' positions and frames, which the stretch moves, and the error
// against a refined fixed-dt run falls with the tolerance as on the inextensible cable (above;
// measured 5.0e-4, 4.9e-5, 2.7e-6 m at 1e-2, 1e-3, 1e-4), below the fixed step ds / v's from
// 1e-3 on.
TEST(AdaptiveCli, StretchingCableFollowsTheTolerance) {
  const fs::path d = scratch("adaptive-extensible");
  const std::string base = kExe + " run " + kCable +
                           " --overwrite --set mesh.ds=0.02 --set rod.model=extensible --set rod.axial_stiffness=200 ";
  const std::string ref = (d / "ref.h5").string(), fixed = (d / "fixed.h5").string();
  ASSERT_EQ(run_command(base + "-o " + fixed + " -q").code, 0);
  const auto t_fixed = Reader(fixed).time();
  ASSERT_GE(t_fixed.size(), 2u);
  char ref_args[128];
  std::snprintf(ref_args, sizeof ref_args, "--set time.dt=%.17g --set output.every=64 -q", (t_fixed[1] - t_fixed[0]) / 64.0);
  ASSERT_EQ(run_command(base + "-o " + ref + " " + ref_args).code, 0);
  std::vector<double> errors;
  for (const char* tol : {"1e-2", "1e-3", "1e-4"}) {
    const std::string out = (d / (std::string("ad") + tol + ".h5")).string();
    const RunResult r = run_command(base + "-o " + out + " --set time.adaptive.tolerance=" + tol);
    ASSERT_EQ(r.code, 0) << r.out;
    ASSERT_EQ(Reader(out).time().size(), t_fixed.size());
    errors.push_back(midspan_difference(out, ref));
    std::cout << "  extensible, tolerance " << tol << ": " << counts(out).accepted << " accepted, midspan error "
              << errors.back() << " m\n";
  }
  const double e_fixed = midspan_difference(fixed, ref);
  std::cout << "  fixed dt = ds / v: midspan error " << e_fixed << " m\n";
  EXPECT_LT(errors[1], 0.5 * errors[0]);
  EXPECT_LT(errors[2], 0.5 * errors[1]);
  EXPECT_LT(errors[1], e_fixed);
}

TEST(AdaptiveCli, OneAndTwoRanksTakeTheSameSteps) {
  const fs::path d = scratch("adaptive-ranks");
  const std::string a = (d / "np1.h5").string(), b = (d / "np2.h5").string();
  const std::string args = " run " + kCable + " --overwrite --set mesh.ds=0.02 --set time.adaptive.tolerance=1e-3 "
                           "--set output.fields=[r,u,omega,kappa,n] -o ";
  const RunResult r1 = run_command(kExe + args + a), r2 = run_command(kMpi + kExe + args + b);
  ASSERT_EQ(r1.code, 0) << r1.out;
  ASSERT_EQ(r2.code, 0) << r2.out;
  const Counts c1 = counts(a), c2 = counts(b);
  std::cout << "  1 rank: " << c1.accepted << " accepted, " << c1.rejected << " rejected; 2 ranks: " << c2.accepted
            << " accepted, " << c2.rejected << " rejected\n";
  EXPECT_EQ(c1.accepted, c2.accepted);
  EXPECT_EQ(c1.rejected, c2.rejected);
  EXPECT_GT(c1.accepted, 0);
  std::string why;
  const double diff = max_file_difference(a, b, why);
  std::cout << "  1 vs 2 ranks: max |difference| = " << diff << " (" << why << ")\n";
  EXPECT_LE(diff, 1e-9) << why;
}

// An arch scene on 2 ranks: the formation's statics take the 2-rank default (GMRES + ILUT; the
// filled-in SCHWARZ default failed there, "no Euler pitchfork found"), the start loaded with the
// load, adaptive steps: the same steps and outputs as on 1 rank.
TEST(AdaptiveCli, LoadedArchOnOneAndTwoRanks) {
  const fs::path d = scratch("adaptive-arch-ranks");
  const std::string a = (d / "np1.h5").string(), b = (d / "np2.h5").string();
  const std::string args = " run " + kArch + " --overwrite --set mesh.ds=0.05 --set scheme.rho_inf=1 --set time.end=0.2"
                           " --set time.dt=0.01 --set time.adaptive.tolerance=1e-3 --set initial_state.loaded=true"
                           " --set output.fields=[r,n] -o ";
  const RunResult r1 = run_command(kExe + args + a), r2 = run_command(kMpi + kExe + args + b);
  ASSERT_EQ(r1.code, 0) << r1.out;
  ASSERT_EQ(r2.code, 0) << r2.out;
  EXPECT_NE(Reader(b).attribute("initial_state").find("in equilibrium with the load"), std::string::npos)
      << Reader(b).attribute("initial_state");
  const Counts c1 = counts(a), c2 = counts(b);
  EXPECT_EQ(c1.accepted, c2.accepted);
  EXPECT_EQ(c1.rejected, c2.rejected);
  std::string why;
  const double diff = max_file_difference(a, b, why);
  std::cout << "  arch, 1 vs 2 ranks: " << c1.accepted << " and " << c2.accepted << " steps, max |difference| = " << diff
            << " (" << why << ")\n";
  EXPECT_LE(diff, 1e-9) << why;
}

// The undamped shallow arch at v = 0.5 m/s (ds = 0.02): the snap through is passed (exit 0),
// with rejected steps, and the right end turns through its initial inclination.
TEST(AdaptiveCli, UndampedSnapThroughIsPassedWithRejectedSteps) {
  const fs::path d = scratch("adaptive-snap");
  const std::string out = (d / "snap.h5").string();
  const RunResult r = run_command(kExe + " run " + kArch + " -o " + out +
                                  " --overwrite --set mesh.ds=0.02 --set scheme.rho_inf=1 --set time.adaptive.tolerance=1e-3");
  ASSERT_EQ(r.code, 0) << r.out;
  const Counts c = counts(out);
  std::cout << "  " << c.accepted << " accepted, " << c.rejected << " rejected, " << c.failed << " failed\n";
  EXPECT_GT(c.rejected, 0);
  const auto d3 = Reader(out).probe("end_tangent");
  const double a0 = std::atan2(d3.values[1], d3.values[2]);
  double turned = 0.0;
  for (size_t i = 0; i < d3.rows; ++i)
    turned = std::max(turned, std::abs(std::remainder(std::atan2(d3.values[3 * i + 1], d3.values[3 * i + 2]) - a0, 2 * M_PI)));
  std::cout << "  right end: initial inclination " << std::abs(a0) << " rad, largest rotation " << turned << " rad\n";
  EXPECT_GT(turned, std::abs(a0));
}

// The undamped shallow arch under the slow load (0.02 m/s, ds = 0.01, rho_inf 1), outputs every
// ds / (64 v) = 7.8 ms (0.16 mm of load travel): the snap, the load position at the first output
// where the right end's tangent points up (d3 . j > 0), at tolerance 1e-3 within 5 mm of the
// fixed step ds / (256 v)'s (the converged value at this output spacing: ds / (1024 v) gives the
// same 0.3144 m), and in fewer steps than twice the fixed ds / (64 v) run's 2 176 (docs/adaptive.md).
TEST(AdaptiveCli, UndampedSlowArchSnapsWhereFixedStepsConverge) {
  const fs::path d = scratch("adaptive-slow-snap");
  const std::string base = kExe + " run " + std::string(TRAVERSE_SOURCE_DIR) +
                           "/inputs/arch/shallow_arch_v0.02.yaml --overwrite -q --set mesh.ds=0.01 "
                           "--set scheme.rho_inf=1 --set time.end=17 --set output.fields=[] ";
  auto snap = [](const std::string& file) {
    const Reader r(file);
    const auto d3 = r.probe("end_tangent");
    const auto sigma = r.sigma();
    for (size_t i = 0; i < d3.rows; ++i)
      if (d3.values[3 * i + 1] > 0.0) return sigma.values[i];
    return std::nan("");
  };
  const std::string fixed = (d / "fixed.h5").string(), adaptive = (d / "adaptive.h5").string();
  ASSERT_EQ(run_command(base + "-o " + fixed + " --set time.dt=" + std::to_string(0.5 / 256) + " --set output.every=4").code,
            0);
  const RunResult r = run_command(base + "-o " + adaptive + " --set time.dt=" + std::to_string(0.5 / 64) +
                                  " --set output.every=1 --set time.adaptive.tolerance=1e-3");
  ASSERT_EQ(r.code, 0) << r.out;
  const Counts c = counts(adaptive);
  const double sf = snap(fixed), sa = snap(adaptive);
  std::cout << "  snap: fixed ds / (256 v) " << sf << " m, adaptive 1e-3 " << sa << " m (" << c.accepted << " accepted, "
            << c.rejected << " rejected)\n";
  EXPECT_LT(std::abs(sa - sf), 0.005);
  EXPECT_LT(c.accepted + c.rejected, 2 * 2176);
}

// The cantilever beam (3 modes, outputs every 1e-4 s): with Newmark the error of the tip
// trace against a fixed-dt RK4 run at dt = 1e-6 s falls with the tolerance; with RK4 it stays
// at the fixed run's level.
TEST(AdaptiveCli, BeamIntegratorsFollowTheTolerance) {
  const fs::path d = scratch("adaptive-beam");
  const std::string beam = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/beam/cantilever.yaml";
  const std::string base = kExe + " run " + beam + " --overwrite ";
  const std::string ref = (d / "ref.h5").string();
  ASSERT_EQ(run_command(base + "-o " + ref + " -q --set time.dt=1e-6 --set output.every=100").code, 0);
  auto tip_error = [&](const std::string& f) {
    const auto a = Reader(f).probe("tip"), b = Reader(ref).probe("tip");
    double e = 0.0, amp = 0.0;
    for (size_t i = 0; i < b.rows; ++i) {
      e = std::max(e, std::abs(a.values[i] - b.values[i]));
      amp = std::max(amp, std::abs(b.values[i]));
    }
    return e / amp;
  };
  std::vector<double> newmark;
  for (const char* tol : {"1e-3", "1e-7"}) {
    const std::string out = (d / (std::string("newmark") + tol + ".h5")).string();
    const RunResult r = run_command(base + "-o " + out + " --set beam.integrator=newmark --set time.adaptive.tolerance=" + tol);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_GT(counts(out).accepted, 0) << r.out;
    newmark.push_back(tip_error(out));
    std::cout << "  newmark, tolerance " << tol << ": relative tip error " << newmark.back() << "\n";
  }
  EXPECT_LT(newmark[1], 0.2 * newmark[0]);
  const std::string rk = (d / "rk4.h5").string();
  const RunResult r = run_command(base + "-o " + rk + " --set time.adaptive.tolerance=1e-5");
  ASSERT_EQ(r.code, 0) << r.out;
  const double e = tip_error(rk);
  std::cout << "  rk4, tolerance 1e-5: relative tip error " << e << "\n";
  EXPECT_LT(e, 1e-6);
}

// The rod's coupled mass (the bead on the cable, ds = 0.05): the adaptive runs end at the same
// event; against tolerance 1e-4, the event time's error falls with the tolerance, and 1e-3 is
// closer than the fixed-dt run (dt = ds / v).
TEST(AdaptiveCli, CoupledMassRunsEndAtTheConvergedEvent) {
  const fs::path d = scratch("adaptive-coupled");
  const std::string scene = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/rod/coupled_bead_cable.yaml";
  const std::string base = kExe + " run " + scene + " --overwrite --set mesh.ds=0.05 ";
  std::vector<double> te;
  for (const char* tol : {"", "1e-2", "1e-3", "1e-4"}) {
    const std::string out = (d / (std::string("bead") + tol + ".h5")).string();
    const std::string extra = *tol ? std::string(" --set time.adaptive.tolerance=") + tol : std::string();
    const RunResult r = run_command(base + "-o " + out + extra);
    ASSERT_EQ(r.code, 0) << r.out;
    if (*tol) {
      EXPECT_GT(counts(out).accepted, 0) << r.out;
    }
    const auto ev = Reader(out).events();
    ASSERT_EQ(ev.size(), 1u) << out;
    EXPECT_EQ(ev[0].reason, "left_rod_at_L");
    te.push_back(ev[0].time);
    std::printf("  %s: the bead leaves at t = %.9f s, %d steps\n", *tol ? tol : "fixed dt", ev[0].time,
                *tol ? static_cast<int>(counts(out).accepted) : -1);
  }
  const double e_fixed = std::abs(te[0] - te[3]), e2 = std::abs(te[1] - te[3]), e3 = std::abs(te[2] - te[3]);
  std::printf("  against 1e-4: fixed %.3e s, 1e-2 %.3e s, 1e-3 %.3e s\n", e_fixed, e2, e3);
  EXPECT_LT(e3, 0.1 * e_fixed);
  EXPECT_LT(e3, 0.1 * e2);
}

// The node crossings the steps land on: a load moving right from s = 0, one moving left from
// s = L entering later, one accelerating, a coupled mass (never), a load past the far end.
TEST(AdaptiveCli, NextNodeCrossing) {
  using traverse::setup::next_node_crossing;
  traverse::scene::MovingLoadSpec right;
  right.speed = 2.0;  // ds = 0.1: a node every 0.05 s
  const double ds = 0.1, L = 1.0;
  EXPECT_NEAR(next_node_crossing({right}, 0.0, ds, L), 0.05, 1e-15);
  EXPECT_NEAR(next_node_crossing({right}, 0.05 + 1e-12, ds, L), 0.10, 1e-15);  // on a node: the next one
  EXPECT_NEAR(next_node_crossing({right}, 0.07, ds, L), 0.10, 1e-15);
  EXPECT_NEAR(next_node_crossing({right}, 0.49, ds, L), 0.50, 1e-15);  // leaving at L
  EXPECT_TRUE(std::isinf(next_node_crossing({right}, 0.51, ds, L)));  // gone
  traverse::scene::MovingLoadSpec left = right;
  left.entry = traverse::scene::Entry::right;
  left.start = L;
  left.entry_time = 0.3;
  EXPECT_NEAR(next_node_crossing({left}, 0.0, ds, L), 0.3, 1e-15);  // it appears
  EXPECT_NEAR(next_node_crossing({left}, 0.31, ds, L), 0.35, 1e-15);
  EXPECT_NEAR(next_node_crossing({right, left}, 0.31, ds, L), 0.35, 1e-15);
  EXPECT_NEAR(next_node_crossing({right, left}, 0.26, ds, L), 0.3, 1e-15);
  traverse::scene::MovingLoadSpec accelerating;
  accelerating.speed = 0.0;
  accelerating.acceleration = 2.0;  // s = t^2: nodes at t = sqrt(0.1 k)
  EXPECT_NEAR(next_node_crossing({accelerating}, 0.4, ds, L), std::sqrt(0.2), 1e-14);
  traverse::scene::MovingLoadSpec coupled = right;
  coupled.coupled = true;
  EXPECT_TRUE(std::isinf(next_node_crossing({coupled}, 0.0, ds, L)));
}

// time.adaptive.land_on_nodes (default true): the steps end where the load reaches a node, where
// its force on the nodes has a kink in time. The cable at ds = 0.02 with outputs every 10 node
// crossings: with landing no step is longer than ds / v, without it the steps grow past it;
// against fixed dt / 64 at tolerance 1e-2 the midspan height's error is 1.9e-4 m in 68 steps
// with landing against 4.1e-3 m in 32 without.
TEST(AdaptiveCli, StepsLandOnTheLoadsNodeCrossings) {
  const fs::path d = scratch("adaptive-land");
  const double crossing = 0.02 / 3.63418;  // ds / v of the default scene's load
  const std::string base = kExe + " run " + kCable + " --overwrite --set mesh.ds=0.02 ";
  const std::string ref = (d / "ref.h5").string();
  char dt_ref[64], dt[64];
  std::snprintf(dt_ref, sizeof dt_ref, "%.17g", crossing / 64);
  std::snprintf(dt, sizeof dt, "%.17g", crossing);
  ASSERT_EQ(run_command(base + "-o " + ref + " -q --set time.dt=" + dt_ref + " --set output.every=640").code, 0);
  double error[2] = {0.0, 0.0};
  for (const bool land : {false, true}) {
    const std::string out = (d / (land ? "land.h5" : "free.h5")).string();
    const RunResult r = run_command(base + "-o " + out + " --set time.dt=" + dt + " --set output.every=10" +
                                    " --set time.adaptive.tolerance=1e-2 --set time.adaptive.land_on_nodes=" +
                                    (land ? "true" : "false"));
    ASSERT_EQ(r.code, 0) << r.out;
    const auto t = Reader(out).time(), tr = Reader(ref).time();
    ASSERT_EQ(t.size(), tr.size());
    for (size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t[i], tr[i], 1e-12);
    error[land] = midspan_difference(out, ref);
    std::printf("  land_on_nodes %s: %ld steps, largest dt %.4g s (ds / v = %.4g s), midspan error %.3e m\n",
                land ? "true" : "false", counts(out).accepted, counts(out).largest_dt, crossing, error[land]);
    if (land) {
      EXPECT_LE(counts(out).largest_dt, crossing * (1.0 + 1e-9)) << r.out;
    } else {
      EXPECT_GT(counts(out).largest_dt, 2.0 * crossing) << r.out;
    }
  }
  EXPECT_LT(error[1], 0.2 * error[0]);
}

// The beam's coupled mass (inputs/beam/coupled_bead.yaml, RK4 by step doubling): the output
// times are the fixed run's, the bead's position and the deflection under it against a fixed
// run at dt / 64 fall with the tolerance (measured 1.98e-7, 2.28e-8, 6.5e-10 m at 1e-4, 1e-6,
// 1e-8), and the bead leaves at x = L at the reference's time (9.0e-11, 5e-12, 1e-13 s off).
TEST(AdaptiveCli, BeamCoupledMassFollowsTheTolerance) {
  const fs::path d = scratch("adaptive-beam-coupled");
  const std::string scene = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/beam/coupled_bead.yaml";
  const std::string base = kExe + " run " + scene + " --overwrite --set time.dt=2.5e-4 ";
  const std::string ref = (d / "ref.h5").string();
  ASSERT_EQ(run_command(base + "-o " + ref + " -q --set time.dt=3.90625e-6 --set output.every=640").code, 0);
  const Reader r(ref);
  const auto tr = r.time();
  const auto xr = r.probe("bead_position"), wr = r.probe("bead_deflection");
  const double te = r.events().at(0).time;
  std::vector<double> errors, event_errors;
  for (const char* tol : {"1e-4", "1e-6", "1e-8"}) {
    const std::string out = (d / (std::string("bead") + tol + ".h5")).string();
    const RunResult run = run_command(base + "-o " + out + " --set time.adaptive.tolerance=" + tol);
    ASSERT_EQ(run.code, 0) << run.out;
    EXPECT_GT(counts(out).accepted, 0) << run.out;
    const Reader a(out);
    const auto t = a.time();
    const auto x = a.probe("bead_position"), w = a.probe("bead_deflection");
    ASSERT_EQ(t.size(), tr.size()) << out;
    double e = 0.0, et = 0.0;
    for (size_t i = 0; i + 1 < t.size(); ++i) {  // the last row is the event, at its own time
      et = std::max(et, std::abs(t[i] - tr[i]));
      e = std::max({e, std::abs(x.values[i] - xr.values[i]), std::abs(w.values[i] - wr.values[i])});
    }
    const auto ev = a.events();
    ASSERT_EQ(ev.size(), 1u) << out;
    EXPECT_EQ(ev[0].reason, "left_beam_at_L");
    errors.push_back(e);
    event_errors.push_back(std::abs(ev[0].time - te));
    std::printf("  tolerance %s: %ld steps, max error %.3e m, output times differ by %.1e s, leaves %.2e s off\n", tol,
                counts(out).accepted, e, et, event_errors.back());
    EXPECT_LT(et, 1e-12);
  }
  EXPECT_LT(errors[1], 0.3 * errors[0]);
  EXPECT_LT(errors[2], 0.3 * errors[1]);
  EXPECT_LT(errors[2], 1e-8);
  EXPECT_LT(event_errors[2], 1e-9);
}

// The progress line of an adaptive run shows the proposed step and the rejections: the beam's
// coupled mass at tolerance 1e-6, a report at every step (output.progress_interval = 0).
TEST(AdaptiveCli, ProgressShowsTheStepAndTheRejections) {
  const fs::path d = scratch("adaptive-progress");
  const std::string scene = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/beam/coupled_bead.yaml";
  const RunResult r = run_command(kExe + " run " + scene + " -o " + (d / "bead.h5").string() +
                                  " --overwrite --progress --set time.adaptive.tolerance=1e-6"
                                  " --set output.progress_interval=0");
  ASSERT_EQ(r.code, 0) << r.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex("  t = [^\n]* steps/s, dt = [0-9.e+-]+ s, ([0-9]+) rejected, about")))
      << r.out;
  std::cout << "  " << m[0] << "\n";
}

}  // namespace

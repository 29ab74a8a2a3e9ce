// Clean stop on SIGINT/SIGTERM and restart from the output file, with the real traverse
// executable: a rod run (1 and 2 ranks) and a beam run are stopped at a random output step
// (SIGINT, or SIGKILL), every written step is checked against an uninterrupted run, then
// `traverse run --restart` finishes the run and the whole file must equal the uninterrupted
// one to 1e-12. docs/reliability.md describes the design.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <iostream>
#include <random>

#include "process.hpp"

namespace fs = std::filesystem;
using namespace traverse::testing;
using traverse::output::Reader;

namespace {

const std::string kExe = TRAVERSE_EXE;
const std::string kCable = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/default.yaml";
const std::string kBeam = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/beam/cantilever.yaml";
// Cable: 51 nodes, 50 time steps, every field.
// A restart point after every output step (--restart-interval 0, which also flushes every
// output step), so that a stop mid-run leaves a recent point to restart from.
const std::string kRodArgs = " --set mesh.ds=0.02 --set output.fields=[r,R,u,omega,kappa,n,m] --restart-interval 0 -q";
// Output steps flushed one by one, so that a test sees them in the file while a short run
// goes on, however fast it is.
const std::string kFlushEveryStep = " --set output.flush_interval=0";
// Cantilever: 3 modes, 200 output steps.
const std::string kBeamArgs = " --set time.dt=2e-5 --set output.every=5 --set output.fields=[deflection,slope,bending_moment] -q";

std::vector<std::string> command(int ranks, const std::string& args) {
  std::vector<std::string> a;
  if (ranks > 1) a = {TRAVERSE_MPIEXEC, "--allow-run-as-root", "--oversubscribe", "-n", std::to_string(ranks)};
  a.push_back(kExe);
  for (const auto& s : split_args(args)) a.push_back(s);
  return a;
}

int run_to_end(int ranks, const std::string& args, const std::string& log) {
  return wait_exit(spawn(command(ranks, args), log));
}

long random_step(long lo, long hi) {
  std::random_device rd;
  return std::uniform_int_distribution<long>(lo, hi)(rd);
}

enum class Stop { sigint_process, sigint_one_rank, sigint_mpiexec, sigkill };

// Starts `args`, stops it after `at` output steps the way `how` says, returns the exit code.
int run_and_stop(int ranks, const std::string& args, long at, Stop how, const std::string& log) {
  const auto a = split_args(args);
  std::string file;
  for (size_t i = 0; i + 1 < a.size(); ++i)
    if (a[i] == "-o" || a[i] == "--restart") file = a[i + 1];
  const Child c = spawn(command(ranks, args), log);
  if (!wait_for_steps(c, file, at)) return wait_exit(c) + 1000;  // ended before the stop
  const std::vector<pid_t> ranks_pids = ranks > 1 ? children_of(c.pid) : std::vector<pid_t>{c.pid};
  switch (how) {
    case Stop::sigint_process:
    case Stop::sigint_mpiexec:
      kill(c.pid, SIGINT);
      break;
    case Stop::sigint_one_rank:
      kill(ranks_pids.back(), SIGINT);
      break;
    case Stop::sigkill:
      for (pid_t p : ranks_pids) kill(p, SIGKILL);
      break;
  }
  return wait_exit(c);
}

// The common scenario: reference run, stopped run, checks, restart, comparison.
void stop_and_restart(const std::string& name, int ranks, const std::string& scene, const std::string& args,
                      long lo, long hi, Stop how, double tolerance = 1e-12) {
  const fs::path d = scratch(name);
  const std::string ref = (d / "reference.h5").string(), out = (d / "run.h5").string();
  ASSERT_EQ(run_to_end(ranks, "run " + scene + " -o " + ref + args, (d / "reference.log").string()), 0)
      << read_text((d / "reference.log").string());
  const long total = static_cast<long>(Reader(ref).steps_written());
  // At most half-way: the signal must find steps left to stop. (The coupled adaptive run has 20
  // output steps of about 10 ms; a stop drawn at step 18 let it complete before the test's
  // SIGINT, sent after it had read the file, arrived.)
  const long at = random_step(lo, std::max(lo, std::min(hi, total / 2)));
  const auto t0 = std::chrono::steady_clock::now();
  const int code = run_and_stop(ranks, "run " + scene + " -o " + out + args, at, how, (d / "stopped.log").string());
  const std::string log = read_text((d / "stopped.log").string());
  ASSERT_LT(code, 1000) << "the run ended before output step " << at << "\n" << log;
  Reader stopped(out);
  const long kept = static_cast<long>(stopped.steps_written());
  const std::string status = stopped.status();
  std::cout << "  " << name << ": stopped after output step >= " << at << " of " << total << ": exit " << code
            << ", " << kept << " steps kept, status '" << status << "'\n";
  EXPECT_GE(kept, at);
  EXPECT_LT(kept, total);
  if (how == Stop::sigkill) {
    EXPECT_EQ(code, 128 + SIGKILL);
    EXPECT_EQ(status, "running");
  } else {
    if (how == Stop::sigint_mpiexec) {
      EXPECT_NE(code, 0);  // mpiexec's own code; the ranks got SIGTERM from it
    } else {
      EXPECT_EQ(code, 130) << log;
      EXPECT_NE(log.find("interrupted at t = "), std::string::npos) << log;
    }
    EXPECT_EQ(status.rfind("interrupted at t = ", 0), 0u) << status;
  }
  std::string why;
  EXPECT_EQ(max_file_difference(ref, out, why, static_cast<std::size_t>(kept)), 0.0)
      << "written steps differ from the uninterrupted run: " << why;
  // Restart with the scene stored in the file, then compare everything.
  const int rc = run_to_end(ranks, "run --restart " + out + " -q", (d / "restart.log").string());
  ASSERT_EQ(rc, 0) << read_text((d / "restart.log").string());
  EXPECT_EQ(Reader(out).status(), "complete");
  EXPECT_FALSE(fs::exists(out + ".before-restart"));
  const double diff = max_file_difference(ref, out, why);
  std::cout << "  " << name << ": restarted run vs uninterrupted: max |difference| = " << diff << " (" << why
            << "), " << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s\n";
  EXPECT_LE(diff, tolerance) << why;
}

}  // namespace

// Adaptive time stepping (docs/adaptive.md): the restart point holds the controller (its step,
// levels, displacements and counters), so the restarted run takes the same steps: bit for bit.
TEST(InterruptRestart, RodAdaptiveSigintThenRestartBitForBit) {
  stop_and_restart("rod-adaptive-sigint", 1, kCable, kRodArgs + " --set time.adaptive.tolerance=1e-3", 3, 40,
                   Stop::sigint_process, 0.0);
}

TEST(InterruptRestart, RodAdaptiveTwoRanksSigkillThenRestartBitForBit) {
  stop_and_restart("rod-adaptive-np2-sigkill", 2, kCable, kRodArgs + " --set time.adaptive.tolerance=1e-3", 3, 40,
                   Stop::sigkill, 0.0);
}

// With Newton's secant guess (solver key 'Initial Guess', docs/solver.md) the next step's
// guess depends on the last step's secant yv, which the restart point stores: bit for bit.
TEST(InterruptRestart, RodSecantGuessSigintThenRestartBitForBit) {
  stop_and_restart("rod-secant-sigint", 1, kCable, kRodArgs + " --set 'solver.Initial Guess=Secant'", 3, 40,
                   Stop::sigint_process, 0.0);
}

// A shearable rod with Kelvin-Voigt viscosity (docs/rod.md): the strain rate's history (the n
// slot of yt) and kappa_t are part of the restart point, so the restarted run is the
// uninterrupted one bit for bit, on the 3D and the planar path, and with a carried ys.
TEST(InterruptRestart, ShearableDampedRodSigintThenRestartBitForBit) {
  const std::string strain = " --set rod.model=shearable --set 'rod.damping={axial: 5, shear: 5, bending: 1.0e-5, "
                             "torsion: 1.0e-5}' --set output.fields=[r,R,u,omega,kappa,n,m,v]";
  stop_and_restart("rod-shearable-3d-sigint", 1, kCable, kRodArgs + strain + " --set scheme.planar=off", 3, 40,
                   Stop::sigint_process, 0.0);
  stop_and_restart("rod-shearable-planar-sigint", 1, kCable, kRodArgs + strain, 3, 40, Stop::sigint_process, 0.0);
  // With a carried spatial history the carried kappa_s's rate is part of the point too.
  stop_and_restart("rod-shearable-carried-sigint", 1, kCable, kRodArgs + strain + " --set scheme.rho_inf_space=0.8", 3,
                   40, Stop::sigint_process, 0.0);
}

// Adaptive steps on a damped shearable rod: the controller and the strain rate's history.
TEST(InterruptRestart, ShearableAdaptiveSigintThenRestartBitForBit) {
  stop_and_restart("rod-shearable-adaptive-sigint", 1, kCable,
                   kRodArgs + " --set rod.model=shearable --set 'rod.damping={axial: 5, shear: 5}'"
                              " --set time.adaptive.tolerance=1e-3",
                   3, 40, Stop::sigint_process, 0.0);
}

TEST(InterruptRestart, RodSigintThenRestart) {
  stop_and_restart("rod-sigint", 1, kCable, kRodArgs, 3, 40, Stop::sigint_process);
}

TEST(InterruptRestart, RodSigkillThenRestart) {
  stop_and_restart("rod-sigkill", 1, kCable, kRodArgs, 3, 40, Stop::sigkill);
}

// What makes a kill -9 inside a flush harmless (docs/reliability.md): while the run goes on,
// the file is longer than anything its superblock can record (a hole of at least 64 MiB past
// the end of allocation, no disk space), and cut back to its true size when it is closed.
// The output is flushed after every output step (output.flush_interval = 0), so the file is
// seen running after 3 of its 101 output steps however fast the run is.
TEST(InterruptRestart, RunningOutputIsPaddedPastItsAllocationAndClosedToSize) {
  const fs::path d = scratch("padding");
  const std::string out = (d / "run.h5").string();
  const Child c = spawn(command(1, "run " + kCable + " -o " + out +
                                       " --set mesh.ds=0.02 --set time.dt=1e-5 --set output.every=275"
                                       " --set output.flush_interval=0 -q"),
                        (d / "run.log").string());
  ASSERT_TRUE(wait_for_steps(c, out, 3)) << read_text((d / "run.log").string());
  struct stat running {};
  ASSERT_EQ(stat(out.c_str(), &running), 0);
  ASSERT_EQ(wait_exit(c), 0) << read_text((d / "run.log").string());
  struct stat closed {};
  ASSERT_EQ(stat(out.c_str(), &closed), 0);
  std::cout << "  running: " << running.st_size << " bytes (" << 512 * running.st_blocks << " on disk); closed: "
            << closed.st_size << " bytes\n";
  EXPECT_GE(running.st_size, 64 << 20);
  EXPECT_LT(512 * static_cast<long long>(running.st_blocks), 16 << 20);
  EXPECT_LT(closed.st_size, 16 << 20);
  EXPECT_EQ(Reader(out).status(), "complete");
}

TEST(InterruptRestart, RodTwoRanksSigintToOneRankThenRestart) {
  stop_and_restart("rod-np2-sigint", 2, kCable, kRodArgs, 3, 40, Stop::sigint_one_rank);
}

// SIGINT to mpiexec: Open MPI's mpirun forwards it to the ranks as SIGTERM. On a loaded
// machine the forwarding took longer than a short run had left (with 50, 500 and, beside a
// second test suite, 10000 time steps with 60 % left), so this run has 20000 (dt = ds / (400 v),
// 100 output steps), flushed after every output step (output.flush_interval = 0): the signal,
// sent at output step 3 .. 25, finds three quarters of the run left.
TEST(InterruptRestart, RodTwoRanksSigintToMpiexecThenRestart) {
  stop_and_restart("rod-np2-mpiexec", 2, kCable,
                   " --set mesh.ds=0.02 --set time.dt=1.375e-5 --set output.every=200 --set output.fields=[r,n]"
                   " --set output.flush_interval=0 --restart-interval 0 -q",
                   3, 25, Stop::sigint_mpiexec);
}

// The default restart cadence (output.restart_interval = 60 s): a run of a few seconds (27500
// steps, 101 output steps) has only the restart point of its start when it is killed; its
// output steps are flushed after each one (output.flush_interval = 0). The restart recomputes
// from t = 0 and ends bit for bit equal to the uninterrupted run.
TEST(InterruptRestart, RodSigkillAtTheDefaultCadenceRestartsFromTheStart) {
  stop_and_restart("rod-sigkill-cadence", 1, kCable,
                   " --set mesh.ds=0.02 --set time.dt=1e-5 --set output.every=275 --set output.fields=[r,n]"
                   " --set output.flush_interval=0 -q", 3,
                   40, Stop::sigkill);
}

TEST(InterruptRestart, RodTwoRanksSigkillThenRestart) {
  stop_and_restart("rod-np2-sigkill", 2, kCable, kRodArgs, 3, 40, Stop::sigkill);
}

// The beam run takes well under the output's 1 s flush cadence: it must flush every step for
// the test to see output steps in the file while the run goes on.
TEST(InterruptRestart, BeamSigintThenRestart) {
  stop_and_restart("beam-sigint", 1, kBeam, kBeamArgs + kFlushEveryStep, 5, 150, Stop::sigint_process);
}

TEST(InterruptRestart, BeamSigkillThenRestart) {
  stop_and_restart("beam-sigkill", 1, kBeam, kBeamArgs + kFlushEveryStep, 5, 150, Stop::sigkill);
}

// A restart that was itself killed while copying leaves OUT.h5.before-restart (the file
// being restarted) and a partial OUT.h5: the next restart must read the former. That state
// is made here directly (killing a restart inside its short copy phase is not reliable).
TEST(InterruptRestart, KilledRestartIsRestartedFromTheSavedFile) {
  const fs::path d = scratch("rod-restart-killed");
  const std::string ref = (d / "reference.h5").string(), out = (d / "run.h5").string();
  ASSERT_EQ(run_to_end(1, "run " + kCable + " -o " + ref + kRodArgs, (d / "ref.log").string()), 0);
  ASSERT_EQ(run_and_stop(1, "run " + kCable + " -o " + out + kRodArgs, 20, Stop::sigkill, (d / "a.log").string()),
            128 + SIGKILL);
  fs::rename(out, out + ".before-restart");
  std::ofstream(out) << "a partial copy";  // not even HDF5

  ASSERT_EQ(run_to_end(1, "run --restart " + out + " -q", (d / "c.log").string()), 0) << read_text((d / "c.log").string());
  std::string why;
  const double diff = max_file_difference(ref, out, why);
  std::cout << "  twice restarted run vs uninterrupted: max |difference| = " << diff << "\n";
  EXPECT_LE(diff, 1e-12) << why;
  EXPECT_FALSE(fs::exists(out + ".before-restart"));
}

TEST(InterruptRestart, BadRestartsExitWithCode2AndKeepTheFile) {
  const fs::path d = scratch("restart-bad");
  const std::string out = (d / "run.h5").string();
  ASSERT_EQ(run_to_end(1, "run " + kCable + " -o " + out + kRodArgs, (d / "run.log").string()), 0);
  struct Case {
    std::string args, expect;
  };
  const std::vector<Case> cases{
      {"run --restart " + (d / "missing.h5").string(), "cannot read it as a traverse output file"},
      {"run --restart " + kCable, "cannot read it as a traverse output file"},
      {"run --restart " + out + " -o " + (d / "other.h5").string(), "not allowed with --restart"},
      {"run --restart " + out + " --overwrite", "not allowed with --restart"},
      {"run --restart " + out + " --set output.fields=[r]", "a restart must keep output.fields"},
      {"run --restart " + out + " --set time.dt=1e-3", "a restart keeps the time step"},
      {"run --restart " + out + " --set mesh.ds=0.05", "the scene needs 21 x 72"},
      {"run --restart " + out + " --set loads.F.speed=-3", "loads.F.speed"},
      {"run " + kCable + " --restart-interval -1", "--restart-interval: expected a number of seconds"},
  };
  for (const auto& c : cases) {
    const std::string log = (d / "bad.log").string();
    const int code = run_to_end(1, c.args, log);
    const std::string text = read_text(log);
    EXPECT_EQ(code, 2) << c.args << "\n" << text;
    EXPECT_NE(text.find(c.expect), std::string::npos) << c.args << "\n" << text;
    EXPECT_EQ(Reader(out).status(), "complete") << c.args;
    EXPECT_FALSE(fs::exists(out + ".before-restart")) << c.args;
  }
}

// Bad input the data-driven suite (tests/app/bad_input) cannot express: exit 2, a message
// naming the argument or key, and no output file.
TEST(BadInputBeyondTheSuite, ReadOnlyFolderAndMoreRanksThanNodes) {
  const fs::path d = scratch("bad-extra");
  struct Case {
    int ranks;
    std::string args, expect, output;
  };
  const std::vector<Case> cases{
      // /sys is a read-only file system, also for root (permission bits would not stop root).
      {1, "run " + kCable + " -o /sys/traverse-test.h5 -q", "bad output path", "/sys/traverse-test.h5"},
      {4, "run " + kCable + " -o " + (d / "np4.h5").string() + " --set mesh.ds=0.5 -q",
       "cannot split 3 nodes over 4 ranks", (d / "np4.h5").string()},
  };
  for (const auto& c : cases) {
    const std::string log = (d / "case.log").string();
    const int code = run_to_end(c.ranks, c.args, log);
    const std::string text = read_text(log);
    std::cout << "  " << c.args << " (" << c.ranks << " ranks): exit " << code << "\n";
    EXPECT_NE(code, 0) << text;
    if (c.ranks == 1) {
      EXPECT_EQ(code, 2) << text;  // under mpiexec: its own non-zero code
    }
    EXPECT_NE(text.find(c.expect), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(c.output)) << c.output;
  }
}

// A beam run with a coupled mass (docs/beam.md "Coupled mass"): interrupted, then restarted by
// re-integrating from t = 0 (the output steps in the file checked against the replay); the
// result, events table included, equals the uninterrupted run.
TEST(InterruptRestart, CoupledBeamSigintThenRestart) {
  const std::string scene = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/beam/coupled_bead.yaml";
  stop_and_restart("coupled-beam-sigint", 1, scene,
                   " --set time.dt=5e-6 --set output.every=50 -q" + kFlushEveryStep, 5, 1000,
                   Stop::sigint_process);
  const std::string out = std::string(TRAVERSE_BINARY_DIR) + "/test-scratch/coupled-beam-sigint/run.h5";
  const auto ev = Reader(out).events();
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].reason, "left_beam_at_L");
}

// The same with adaptive steps (docs/adaptive.md "Beam module"): the replay takes the same
// steps, so the restarted run equals the uninterrupted one bit for bit.
TEST(InterruptRestart, CoupledBeamAdaptiveSigintThenRestart) {
  const std::string scene = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/beam/coupled_bead.yaml";
  stop_and_restart("coupled-beam-adaptive-sigint", 1, scene,
                   " --set time.dt=1e-4 --set output.every=5 --set time.adaptive.tolerance=1e-10 -q" +
                       kFlushEveryStep,
                   5, 1000,
                   Stop::sigint_process, 0.0);
  const auto ev = Reader(std::string(TRAVERSE_BINARY_DIR) + "/test-scratch/coupled-beam-adaptive-sigint/run.h5").events();
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].reason, "left_beam_at_L");
}

// A rod run with a coupled mass (docs/rod.md "Coupled mass"): the restart point holds the mass's
// state (position, speed, works), the centreline, the last contact and, adaptive, both
// controllers, so the restarted run continues from it and equals the uninterrupted one bit for
// bit, the event (the bead leaving the cable) included: fixed dt stopped by SIGINT on 1 rank and
// by SIGKILL on 2 ranks, adaptive by SIGINT. A sprung mass's point adds its body's state.
void coupled_rod_restart(const std::string& name, int ranks, const std::string& args, Stop how,
                         const std::string& file = "coupled_bead_cable.yaml") {
  const std::string scene = std::string(TRAVERSE_SOURCE_DIR) + "/inputs/rod/" + file;
  stop_and_restart(name, ranks, scene, " --set mesh.ds=0.05 --restart-interval 0 -q" + args, 5, 300, how, 0.0);
  const std::string out = std::string(TRAVERSE_BINARY_DIR) + "/test-scratch/" + name + "/run.h5";
  const auto ev = Reader(out).events(), ref = Reader(std::string(TRAVERSE_BINARY_DIR) + "/test-scratch/" + name +
                                                     "/reference.h5").events();
  ASSERT_EQ(ev.size(), ref.size());
  if (file == "coupled_bead_cable.yaml") {
    ASSERT_EQ(ev.size(), 1u);
    EXPECT_EQ(ev[0].reason, "left_rod_at_L");
  }
  for (std::size_t k = 0; k < ev.size(); ++k) {
    EXPECT_EQ(ev[k].reason, ref[k].reason);
    EXPECT_EQ(ev[k].time, ref[k].time);
    EXPECT_EQ(ev[k].position, ref[k].position);
  }
}

TEST(InterruptRestart, CoupledRodSigintThenRestart) {
  coupled_rod_restart("coupled-rod-sigint", 1, " --set time.dt=1e-3", Stop::sigint_process);
}

TEST(InterruptRestart, CoupledRodTwoRanksSigkillThenRestart) {
  coupled_rod_restart("coupled-rod-np2-sigkill", 2, " --set time.dt=1e-3", Stop::sigkill);
}

TEST(InterruptRestart, SprungRodTwoRanksSigkillThenRestart) {
  coupled_rod_restart("sprung-rod-np2-sigkill", 2, " --set time.dt=1e-3", Stop::sigkill, "sprung_cabin_cable.yaml");
}

TEST(InterruptRestart, CoupledRodAdaptiveSigintThenRestart) {
  coupled_rod_restart("coupled-rod-adaptive-sigint", 1, " --set time.adaptive.tolerance=1e-4 --set output.every=1",
                      Stop::sigint_process);
}

namespace {

// Whether process `pid` catches SIGINT (its handler is installed: /proc/PID/status, SigCgt).
bool catches_sigint(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (SIGINT - 1)) & 1ULL;
  return false;
}

}  // namespace

// A signal during the set-up stops the run there too: the static initial state polls for it
// at every Newton iteration (over the ranks), so the run ends at the first iteration after
// the signal (130, naming the static solve) with nothing written. The signal is sent once
// the process (each rank) has its handler and before the static solve can have ended: the
// run is 10001 nodes, its static start tens of Newton iterations.
TEST(InterruptRestart, SigintDuringTheStaticStartStopsThere) {
  for (int ranks : {1, 2}) {
    const fs::path d = scratch("setup-sigint-np" + std::to_string(ranks));
    const std::string out = (d / "run.h5").string(), log = (d / "run.log").string();
    const Child c = spawn(command(ranks, "run " + kCable + " -o " + out + " --set mesh.ds=1e-4 -q"), log);
    std::vector<pid_t> pids;
    for (int tries = 0; tries < 60000; ++tries) {  // up to 5 minutes
      pids = ranks > 1 ? children_of(c.pid) : std::vector<pid_t>{c.pid};
      if (static_cast<int>(pids.size()) == ranks && std::all_of(pids.begin(), pids.end(), catches_sigint)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_EQ(static_cast<int>(pids.size()), ranks);
    kill(pids.back(), SIGINT);
    const int code = wait_exit(c);
    const std::string text = read_text(log);
    std::cout << "  " << ranks << " rank(s): exit " << code << ": " << text.substr(0, text.find('\n')) << "\n";
    if (ranks == 1) {
      EXPECT_EQ(code, 130) << text;
    } else {
      EXPECT_NE(code, 0) << text;  // mpiexec's own code for a rank that ended with 130
    }
    EXPECT_NE(text.find("stopped during the static solve (Newton iteration"), std::string::npos) << text;
    EXPECT_FALSE(fs::exists(out)) << "nothing is written before the time loop";
  }
}

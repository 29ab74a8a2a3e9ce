// Crash safety: a writer (output_kill_writer, 1 and 2 ranks through mpiexec) is killed with
// SIGKILL after a few steps; every step up to steps_written must then read back intact, and
// write_sidecar (`traverse xdmf`) must describe all of them. With a flush after every step
// nothing reported is lost; with the wall-time cadence at most the last interval's steps.
// This program does not use MPI itself; it reads with the serial Reader.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "sample_run.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/output/sidecar.hpp"
#include "xdmf_check.hpp"

using namespace traverse::output;
namespace fs = std::filesystem;

namespace {

struct Killed {
  std::vector<pid_t> rank_pids;
  long last_step = -1;
  long last_flushed = 0;  // steps in the file when the last step was reported
  std::string log;
};

/// Starts `mpiexec -n ranks output_kill_writer path` in its own process group, waits until
/// rank 0 reports step `kill_after`, then SIGKILLs every rank and the group.
Killed run_and_kill(int ranks, const std::string& path, long kill_after, const std::string& pause_ms,
                    const std::string& flush_s) {
  Killed k;
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
  const pid_t child = fork();
  if (child < 0) throw std::runtime_error("fork failed");
  if (child == 0) {
    setpgid(0, 0);
    dup2(fds[1], STDOUT_FILENO);
    close(fds[0]);
    close(fds[1]);
    const std::string n = std::to_string(ranks);
    execl(TRAVERSE_MPIEXEC, TRAVERSE_MPIEXEC, "-n", n.c_str(), "--oversubscribe",
          OUTPUT_KILL_WRITER, path.c_str(), "100000", pause_ms.c_str(), flush_s.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  setpgid(child, child);
  close(fds[1]);
  FILE* in = fdopen(fds[0], "r");
  char line[256];
  while (std::fgets(line, sizeof line, in) != nullptr) {
    k.log += line;
    long v = 0, f = 0;
    if (std::sscanf(line, "pid %ld", &v) == 1) k.rank_pids.push_back(static_cast<pid_t>(v));
    if (std::sscanf(line, "step %ld flushed %ld", &v, &f) == 2) {
      k.last_step = v;
      k.last_flushed = f;
      if (v >= kill_after) break;
    }
  }
  for (pid_t p : k.rank_pids) kill(p, SIGKILL);
  kill(-child, SIGKILL);
  fclose(in);
  int status = 0;
  waitpid(child, &status, 0);
  // The ranks are gone once signal 0 cannot reach them.
  for (int i = 0; i < 100; ++i) {
    bool alive = false;
    for (pid_t p : k.rank_pids) alive = alive || kill(p, 0) == 0;
    if (!alive) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return k;
}

/// flush_s "0": a flush after every step; otherwise the Writer's wall-time cadence.
void check_killed_file(int ranks, const std::string& flush_s, long kill_after, long pause_ms) {
  const fs::path dir = fs::path(TRAVERSE_BINARY_DIR) / "tests" / "output" / "scratch" /
                       ("kill_np" + std::to_string(ranks) + "_flush" + flush_s);
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "killed.h5").string();
  const Killed k = run_and_kill(ranks, path, kill_after, std::to_string(pause_ms), flush_s);
  ASSERT_EQ(k.last_step, kill_after) << "writer output:\n" << k.log;
  ASSERT_EQ(k.rank_pids.size(), static_cast<std::size_t>(ranks));
  for (pid_t p : k.rank_pids) EXPECT_NE(kill(p, 0), 0) << "rank process " << p << " survived";

  std::size_t steps = 0;
  {
    Reader r(path);
    steps = r.steps_written();
    std::printf("np%d flush %s s: killed after step %ld was reported (%ld then in the file); status '%s', "
                "steps_written %zu\n",
                ranks, flush_s.c_str(), k.last_step, k.last_flushed, r.status().c_str(), steps);
    EXPECT_EQ(r.status(), "running");
    // Killed in the pause after step kill_after or at the latest during the next step.
    EXPECT_LE(steps, static_cast<std::size_t>(kill_after + 2));
    if (flush_s == "0") {
      // Every reported step is in the file.
      EXPECT_GE(steps, static_cast<std::size_t>(kill_after + 1));
    } else {
      // What was announced stays; at most one flush interval of steps is lost (a step takes
      // at least pause_ms).
      EXPECT_GE(steps, static_cast<std::size_t>(k.last_flushed));
      EXPECT_GT(k.last_flushed, 0) << "no timed flush happened before the kill";
      const double interval = std::stod(flush_s);
      const auto lost_bound = static_cast<std::size_t>(interval * 1000.0 / static_cast<double>(pause_ms)) + 2;
      EXPECT_LE(static_cast<std::size_t>(kill_after + 1) - std::min<std::size_t>(steps, kill_after + 1), lost_bound);
    }
    std::size_t compared = 0, mismatches = 0;
    auto same = [&](double a, double b) {
      ++compared;
      if (a != b) ++mismatches;
    };
    const auto t = r.time();
    ASSERT_EQ(t.size(), steps);
    const Series sig = r.sigma();
    const char* probe_names[2] = {"midspan_w", "reaction"};
    const char* field_names[3] = {"w", "r", "strain"};
    for (std::size_t s = 0; s < steps; ++s) {
      same(t[s], sample::time(s));
      for (std::size_t j = 0; j < sample::loads; ++j) same(sig.values[s * sample::loads + j], sample::sigma(s, j));
      for (std::size_t p = 0; p < 2; ++p) {
        const Series ps = r.probe(probe_names[p]);
        for (std::size_t c = 0; c < ps.components; ++c) same(ps.values[s * ps.components + c], sample::probe(p, s, c));
      }
      for (std::size_t f = 0; f < 3; ++f) {
        const auto v = r.field(field_names[f], s);
        const std::size_t nc = sample::field_components[f];
        ASSERT_EQ(v.size(), sample::nodes * nc);
        for (std::size_t i = 0; i < sample::nodes; ++i)
          for (std::size_t c = 0; c < nc; ++c) same(v[i * nc + c], sample::field(f, s, i, c));
      }
    }
    EXPECT_EQ(mismatches, 0u);
    std::printf("np%d: %zu values of %zu steps compared, %zu mismatches\n", ranks, compared, steps, mismatches);
  }
  // The sidecar the run left is intact (replaced atomically) but may lag behind the file.
  const auto left = test::check_xdmf((dir / "killed.xmf").string(), path);
  for (const auto& p : left.problems) ADD_FAILURE() << "sidecar left by the run: " << p;
  EXPECT_LE(left.grids, steps);
  // `traverse xdmf` describes every step of the killed run, from the views it had flushed.
  const SidecarResult sc = write_sidecar(path);
  EXPECT_EQ(sc.steps, steps);
  EXPECT_EQ(sc.views_created, 0u);
  const auto rep = test::check_xdmf((dir / "killed.xmf").string(), path);
  for (const auto& p : rep.problems) ADD_FAILURE() << p;
  EXPECT_EQ(rep.grids, steps);
  std::printf("np%d: sidecar left by the run had %zu steps, rewritten: %zu\n", ranks, left.grids, rep.grids);
}

}  // namespace

TEST(OutputKill, OneRankFlushEveryStep) { check_killed_file(1, "0", 3, 150); }
TEST(OutputKill, TwoRanksFlushEveryStep) { check_killed_file(2, "0", 3, 150); }
// Rank 0's clock decides the flushes of both ranks.
TEST(OutputKill, TwoRanksFlushOnWallTime) { check_killed_file(2, "0.5", 14, 100); }

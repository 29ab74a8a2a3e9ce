#pragma once
// Helpers for tests that drive the real traverse executable as a separate process:
// start it (optionally under mpiexec), watch its output file, signal it, wait for it, and
// compare two output files step by step. Header-only; the one process helper of every test
// that runs the executable (tests/app, tests/validation, tests/stress).
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "traverse/output/reader.hpp"

namespace traverse::testing {

namespace fs = std::filesystem;

/// Splits a command line at spaces; single quotes group (no escapes), as in the shell.
inline std::vector<std::string> split_args(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  bool quoted = false, have = false;
  for (char ch : s) {
    if (ch == '\'') {
      quoted = !quoted;
      have = true;
    } else if (ch == ' ' && !quoted) {
      if (have) out.push_back(cur);
      cur.clear();
      have = false;
    } else {
      cur += ch;
      have = true;
    }
  }
  if (have) out.push_back(cur);
  return out;
}

/// What a finished command gave: its exit code (-1 if it did not exit normally) and its
/// standard output and error together.
struct RunResult {
  int code = -1;
  std::string out;
};

/// Runs `command` through the shell with stderr merged into stdout, and waits for it.
inline RunResult run_command(const std::string& command) {
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) return {-1, "popen failed"};
  RunResult r;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p)) r.out.append(buf, n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// A started process: its pid, the file its stdout+stderr go to.
struct Child {
  pid_t pid = -1;
  std::string log;
};

/// Starts `argv` (argv[0] searched in PATH) with stdout and stderr to `log`.
inline Child spawn(const std::vector<std::string>& argv, const std::string& log) {
  Child c;
  c.log = log;
  c.pid = fork();
  if (c.pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    std::vector<char*> a;
    for (const auto& s : argv) a.push_back(const_cast<char*>(s.c_str()));
    a.push_back(nullptr);
    execvp(a[0], a.data());
    _exit(127);
  }
  return c;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Waits for the child; returns its exit code, or 128 + signal if a signal ended it.
inline int wait_exit(const Child& c) {
  int status = 0;
  while (waitpid(c.pid, &status, 0) < 0) {
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

/// steps_written of a file being written, or -1 while it cannot be read.
inline long steps_in(const std::string& path) {
  try {
    return static_cast<long>(traverse::output::Reader(path).steps_written());
  } catch (...) {
    return -1;
  }
}

/// Polls `path` until it holds at least `steps` output steps or the child ended (false) or
/// `timeout_s` passed (false).
inline bool wait_for_steps(const Child& c, const std::string& path, long steps, double timeout_s = 600.0) {
  const auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < timeout_s) {
    if (steps_in(path) >= steps) return true;
    int status = 0;
    if (waitpid(c.pid, &status, WNOHANG) == c.pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

/// The pids of the direct children of `parent` (the ranks under mpiexec).
inline std::vector<pid_t> children_of(pid_t parent) {
  std::vector<pid_t> out;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.empty() || !std::all_of(name.begin(), name.end(), ::isdigit)) continue;
    std::ifstream st(e.path() / "stat");
    std::string line;
    if (!std::getline(st, line)) continue;
    const auto close = line.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(line.substr(close + 2));
    char state;
    long ppid = 0;
    rest >> state >> ppid;
    if (ppid == parent) out.push_back(static_cast<pid_t>(std::stol(name)));
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// Largest |a - b| over every time, sigma, probe and field value of two output files,
/// which must have the same steps_written, probes and fields (NaN must match NaN).
/// Returns +inf on a structural mismatch and describes it in `why`.
inline double max_file_difference(const std::string& a_path, const std::string& b_path, std::string& why,
                                  std::size_t steps = static_cast<std::size_t>(-1)) {
  using traverse::output::Reader;
  const Reader a(a_path), b(b_path);
  const std::size_t n = std::min(steps, a.steps_written());
  if (n > b.steps_written()) {
    why = "steps_written " + std::to_string(a.steps_written()) + " vs " + std::to_string(b.steps_written());
    return INFINITY;
  }
  if (steps == static_cast<std::size_t>(-1) && a.steps_written() != b.steps_written()) {
    why = "steps_written " + std::to_string(a.steps_written()) + " vs " + std::to_string(b.steps_written());
    return INFINITY;
  }
  double worst = 0.0;
  auto cmp = [&](const std::vector<double>& x, const std::vector<double>& y, std::size_t count, const std::string& what) {
    for (std::size_t i = 0; i < count; ++i) {
      if (std::isnan(x[i]) && std::isnan(y[i])) continue;
      const double d = std::abs(x[i] - y[i]);
      if (!(d <= worst)) {
        worst = std::isnan(d) ? INFINITY : d;
        why = what + " entry " + std::to_string(i);
      }
    }
  };
  cmp(a.time(), b.time(), n, "time");
  const auto sa = a.sigma(), sb = b.sigma();
  cmp(sa.values, sb.values, n * sa.components, "sigma");
  const auto pa = a.probe_names(), pb = b.probe_names();
  if (pa != pb) {
    why = "probe names differ";
    return INFINITY;
  }
  for (const auto& p : pa) {
    const auto x = a.probe(p), y = b.probe(p);
    cmp(x.values, y.values, n * x.components, "probe " + p);
  }
  const auto fa = a.field_names(), fb = b.field_names();
  if (fa != fb) {
    why = "field names differ";
    return INFINITY;
  }
  for (const auto& f : fa)
    for (std::size_t s = 0; s < n; ++s) {
      const auto x = a.field(f, s), y = b.field(f, s);
      cmp(x, y, x.size(), "field " + f + " step " + std::to_string(s));
    }
  return worst;
}

/// An empty scratch directory for a test: BUILD/test-scratch/<name>, cleared first.
inline fs::path scratch(const std::string& name) {
  const fs::path d = fs::path(TRAVERSE_BINARY_DIR) / "test-scratch" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace traverse::testing

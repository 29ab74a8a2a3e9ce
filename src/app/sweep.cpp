// traverse sweep: plan (everything checked up front), run the cases of this rank, gather their
// records on rank 0, write the index.
#include "sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include "interrupt.hpp"
#include "traverse/setup/memory_limit.hpp"
#include "mpi_session.hpp"
#include "run.hpp"
#include "traverse/setup/run_limits.hpp"
#include "traverse/core/comm.hpp"
#include "traverse/output/output_error.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxCases = 100000;

struct CaseRecord {
  int code = -1;                 ///< exit code of the case as a run (0 complete); -1 not run
  std::string status = "not run";
  std::string message;
  double wall = 0.0;             ///< seconds
  double summary = std::nan("");
};

// The probes of a (dynamic) run of `sc` with their component counts.
std::vector<std::pair<std::string, int>> probes_of(const scene::Scene& sc) {
  std::vector<std::pair<std::string, int>> out;
  const bool beam = sc.model == scene::Model::Beam;
  for (const auto& p : sc.output.probes) out.emplace_back(p.name, beam ? 1 : 3);
  for (const auto& l : sc.loads) {
    out.emplace_back(l.name + "_position", 1);
    if (beam) out.emplace_back(l.name + "_deflection", 1);
    if (!l.suspended()) continue;  // sprung_mass, vehicle: run_beam_vehicles.cpp
    out.emplace_back(l.name + "_body_displacement", 1);
    out.emplace_back(l.name + "_body_acceleration", 1);
    if (l.type == scene::LoadType::vehicle) out.emplace_back(l.name + "_pitch", 1);
    out.emplace_back(l.name + "_contact_force", static_cast<int>(l.axle_offsets.size()));
  }
  return out;
}

void check_summary(const scene::Scene& sc, const SummarySpec& s) {
  if (!s.given()) return;
  if (sc.model == scene::Model::Rod && sc.continuation.enabled)
    throw UsageError{"--summary " + s.text + ": expected a scene with time stepping; " + sc.file +
                     " is a continuation (statics) scene"};
  const auto probes = probes_of(sc);
  std::string names;
  for (const auto& [name, components] : probes) {
    names += (names.empty() ? "" : ", ") + name;
    if (name != s.probe) continue;
    if (components > 1 && s.component < 0)
      throw UsageError{"--summary " + s.text + ": expected a component of probe '" + name + "' (" + name + ".x, " + name +
                       ".y or " + name + ".z), found none"};
    if (components == 1 && s.component >= 0)
      throw UsageError{"--summary " + s.text + ": expected probe '" + name + "' without a component (it is a scalar), found ." +
                       std::string(1, char('x' + s.component)) + "; write --summary " + name +
                       s.text.substr(s.text.rfind(':'))};
    return;
  }
  throw UsageError{"--summary " + s.text + ": expected a probe of " + sc.file + " {" + names + "}, found '" + s.probe + "'"};
}

std::string case_name(std::size_t k, std::size_t n) {
  std::string digits = std::to_string(k);
  const std::size_t width = std::max<std::size_t>(4, std::to_string(n - 1).size());
  return "case_" + std::string(width - std::min(width, digits.size()), '0') + digits + ".h5";
}

// The scene of case `c` (the sweep's --set overrides, then the case's --vary assignments).
scene::Scene case_scene(const CommandLine& cl, const SweepCase& c) {
  std::vector<std::string> overrides = cl.overrides;
  overrides.insert(overrides.end(), c.assignments.begin(), c.assignments.end());
  return scene::load_scene(cl.scene, overrides);
}

// A rough cost of a case (SweepCase::cost).
double case_cost(const scene::Scene& sc) {
  if (sc.model == scene::Model::Rod && sc.continuation.enabled) return 1.0;
  const bool beam = sc.model == scene::Model::Beam;
  const setup::TimePlan plan = beam ? setup::beam_time_plan(sc) : setup::rod_time_plan(sc);
  const double steps = plan.steps;
  const double per_step = beam ? sc.beam.modes + double(sc.mesh.nodes) / std::max(1, plan.every) : sc.mesh.nodes;
  const double cost = steps * per_step;
  return std::isfinite(cost) && cost > 0.0 ? cost : 0.0;
}

fs::path index_path(const CommandLine& cl) { return fs::path(cl.output) / "index.csv"; }

// Rank 0 makes the directory and refuses to replace files without --overwrite; every rank
// learns the outcome (an OutputError, exit 2, on every rank).
void prepare_directory(const CommandLine& cl, const std::vector<SweepCase>& cases, MPI_Comm comm) {
  std::string error;
  if (comm_rank(comm) == 0) {
    std::error_code ec;
    fs::create_directories(cl.output, ec);
    if (ec || !fs::is_directory(cl.output)) {
      error = "-o " + cl.output + ": expected a directory for the sweep's files, cannot make it (" + ec.message() + ")";
    } else if (!cl.overwrite) {
      std::vector<std::string> paths{index_path(cl).string()};
      for (const auto& c : cases) paths.push_back(c.output);
      for (const auto& p : paths)
        if (fs::exists(p)) {
          error = p + ": exists (use --overwrite to replace the index and the case files)";
          break;
        }
    }
  }
  int length = static_cast<int>(error.size());
  par::bcast(&length, 1, MPI_INT, 0, comm);
  error.resize(static_cast<std::size_t>(length));
  par::bcast(error.data(), length, MPI_CHAR, 0, comm);
  if (!error.empty()) throw output::OutputError(error);
}

}  // namespace

// The summary of a case's probe: min, max and absmax from its extremes over every time step
// when the run recorded them (beam runs), else from the output steps.
double case_summary(const std::string& path, const SummarySpec& s) {
  using R = SummarySpec::Reduction;
  const output::Reader r(path);
  const std::size_t c = static_cast<std::size_t>(std::max(0, s.component));
  const std::optional<output::ProbeExtremes> e =
      s.reduction == R::min || s.reduction == R::max || s.reduction == R::absmax ? r.probe_extremes(s.probe)
                                                                                  : std::nullopt;
  if (e && c < e->min.size())
    return s.reduction == R::min ? e->min[c]
         : s.reduction == R::max ? e->max[c]
                                 : std::max(std::abs(e->min[c]), std::abs(e->max[c]));
  const output::Series series = r.probe(s.probe);
  std::vector<double> values;
  for (std::size_t row = 0; row < series.rows; ++row) values.push_back(series.values[row * series.components + c]);
  return reduce(values, s.reduction);
}

namespace {

std::string case_text(std::size_t k, const SweepCase& c) {
  std::string t = "case " + std::to_string(k) + ":";
  for (const auto& a : c.assignments) t += " " + a;
  return t;
}

// The cases by decreasing estimated cost (equal costs in case order).
std::vector<std::size_t> by_cost(const std::vector<SweepCase>& cases) {
  std::vector<std::size_t> order(cases.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return cases[a].cost > cases[b].cost; });
  return order;
}

// Runs one case on `comm` (MPI_COMM_SELF) with
// `limits` (sweep_limits); every outcome becomes the record (an interrupted case also sets
// `interrupted`).
CaseRecord run_case(const CommandLine& cl, const setup::RunLimits& limits, std::size_t k, const SweepCase& c, MPI_Comm comm,
                    int& interrupted) {
  CaseRecord r;
  const auto t0 = std::chrono::steady_clock::now();
  auto fail = [&](int code, const std::string& status, const std::string& message) {
    r.code = code;
    r.status = status;
    r.message = message;
  };
  try {
    // A file of an earlier sweep (there is one only with --overwrite) must not pass for this case's.
    std::error_code ignored;
    fs::remove(c.output, ignored);
    fs::remove(fs::path(c.output).replace_extension(".xmf"), ignored);
    const scene::Scene sc = case_scene(cl, c);
    RunOptions opt;
    opt.output = c.output;
    opt.overwrite = true;  // checked up front (prepare_directory)
    opt.quiet = true;
    opt.invocation = cl.invocation + " [" + case_text(k, c) + "]";
    opt.restart_interval = sc.output.restart_interval;
    opt.limits = limits;
    run_scene(sc, opt, comm);
    fail(kSuccess, "complete", "");
    if (cl.summary.given()) r.summary = case_summary(c.output, cl.summary);
  } catch (const UsageError& e) {
    fail(kBadInput, "bad input", e.message);
  } catch (const scene::SceneError& e) {
    fail(kBadInput, "bad input", e.what());
  } catch (const output::OutputError& e) {
    fail(kBadInput, "bad output path", e.what());
  } catch (const Interrupted& e) {
    output::set_file_status(e.output(), e.status(), comm);
    fail(128 + e.signal(), "interrupted", e.what());
    interrupted = e.signal();
  } catch (const NumericsError& e) {
    fail(kNumericsFailed, "numerics failed", e.what());
  } catch (const std::exception& e) {
    fail(kOtherError, "error", e.what());
  }
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch == '\n' ? ' ' : ch);
  return q + "\"";
}

std::string number_text(double v) {
  if (std::isnan(v)) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string wall_text(double seconds) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", seconds);
  return buf;
}

// One index row (without the newline).
std::string index_row(std::size_t k, const SweepCase& c, const CaseRecord& r, bool summary) {
  std::string row = std::to_string(k);
  for (const auto& a : c.assignments) row += "," + csv_field(a.substr(a.find('=') + 1));
  const bool file = r.code >= 0 && r.code != kBadInput && fs::exists(c.output);  // none for bad input, not run
  row += "," + csv_field(file ? fs::path(c.output).filename().string() : "") + "," + csv_field(r.status) + "," +
         std::to_string(r.code) + "," + wall_text(r.wall);
  if (summary) row += "," + number_text(r.summary);
  return row + "," + csv_field(r.message);
}

// The text of every rank, concatenated on rank 0 (empty elsewhere).
std::string gather_text(const std::string& mine, MPI_Comm comm) {
  if (par::alone(comm)) return mine;
  const int size = comm_size(comm), rank = comm_rank(comm);
  int length = static_cast<int>(mine.size());
  std::vector<int> lengths(static_cast<std::size_t>(size)), offsets(static_cast<std::size_t>(size));
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, comm);
  int total = 0;
  for (int i = 0; i < size; ++i) offsets[static_cast<std::size_t>(i)] = total, total += lengths[static_cast<std::size_t>(i)];
  std::string all(rank == 0 ? static_cast<std::size_t>(total) : 0u, ' ');
  MPI_Gatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR, 0, comm);
  return all;
}

// Writes the index through a temporary file, so that a reader never sees half of one.
void write_index(const CommandLine& cl, const std::vector<std::string>& rows) {
  const fs::path path = index_path(cl), tmp = path.string() + ".part";
  {
    std::ofstream out(tmp);
    out << "case";
    for (const auto& v : cl.vary) out << "," << csv_field(v.key);
    out << ",output,status,exit_code,wall_s";
    if (cl.summary.given()) out << "," << csv_field(cl.summary.text);
    out << ",message\n";
    for (const auto& r : rows) out << r << "\n";
    if (!out) throw output::OutputError(tmp.string() + ": cannot write the sweep index");
  }
  fs::rename(tmp, path);
}

// The limits of every case: the memory limit shared by the sweep's ranks on each host (a case
// runs on MPI_COMM_SELF, which alone would see the whole host), unless --max-memory says.
setup::RunLimits sweep_limits(const setup::RunLimits& given, MPI_Comm comm) {
  setup::RunLimits l = given;
  if (l.max_memory > 0.0) return l;
  const setup::MemoryLimit m = setup::memory_limit(given, comm);
  if (m.bytes > 0.0) {
    l.max_memory = m.bytes;
    l.memory_source = m.source + ", for each of the sweep's ranks";
  }
  return l;
}

}  // namespace

SweepPlan plan_sweep(const CommandLine& cl) {
  const scene::Scene base = scene::load_scene(cl.scene, cl.overrides);
  for (const auto& v : cl.vary) {
    const std::string option = v.with_previous ? "--with " : "--vary ";
    if (v.key == "output.file")
      throw UsageError{option + "output.file: expected a scene key; the sweep names the output files (-o DIR)"};
    const std::string problem = scene::key_problem(base.tree, scene::scene_schema(), v.key);
    if (!problem.empty()) throw UsageError{option + v.key + ": " + problem + " (scene " + cl.scene + ")"};
  }
  check_summary(base, cl.summary);
  const auto assignments = sweep_cases(cl.vary, kMaxCases);
  SweepPlan plan;
  for (std::size_t k = 0; k < assignments.size(); ++k) {
    SweepCase c{assignments[k], (fs::path(cl.output) / case_name(k, assignments.size())).string(), 0.0};
    try {
      const scene::Scene sc = case_scene(cl, c);
      c.cost = case_cost(sc);
    } catch (const std::exception&) {
      // bad input (or a model that cannot be built): recorded as that case's failure when it runs
      c.cost = 0.0;
    }
    plan.cases.push_back(std::move(c));
  }
  return plan;
}

namespace {

// What one case ended with: its exit code (-1: not run, after an interrupt) and index row.
struct CaseResult {
  std::size_t k = 0;
  int code = -1;
  std::string row;
};

// Runs the cases `next` hands out (none left: nullopt), each on `case_comm`.
std::vector<CaseResult> run_cases(const CommandLine& cl, const SweepPlan& plan, const setup::RunLimits& limits,
                                  const std::function<std::optional<std::size_t>()>& next, MPI_Comm case_comm) {
  std::vector<CaseResult> mine;
  int interrupted = 0;
  while (const auto taken = next()) {
    const std::size_t k = *taken;
    const SweepCase& c = plan.cases[k];
    CaseRecord r;
    if (!interrupted && !local_interrupt_signal()) r = run_case(cl, limits, k, c, case_comm, interrupted);
    if (!cl.quiet)
      std::printf("%s -> %s%s (%.3f s)\n", case_text(k, c).c_str(), r.status.c_str(),
                  r.code == 0 && cl.summary.given() ? (", " + cl.summary.text + " = " + number_text(r.summary)).c_str() : "",
                  r.wall);
    std::fflush(stdout);
    mine.push_back({k, r.code, index_row(k, c, r, cl.summary.given())});
  }
  return mine;
}

// Results as text, to rank 0: a "case \t code \t row" line each (a row holds
// no newline: csv_field).
std::string pack(const std::vector<CaseResult>& results) {
  std::string text;
  for (const CaseResult& r : results) text += std::to_string(r.k) + "\t" + std::to_string(r.code) + "\t" + r.row + "\n";
  return text;
}

// The results of every case, assembled where the index is written.
struct Results {
  explicit Results(std::size_t n) : rows(n), codes(n, -1), reported(n, false) {}
  void add(const CaseResult& r) {
    rows[r.k] = r.row;
    codes[r.k] = r.code;
    reported[r.k] = true;
  }
  // The lines of pack() for which `accept(case)` holds.
  void add_packed(const std::string& text, const std::function<bool(std::size_t)>& accept) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      const auto a = line.find('\t'), b = line.find('\t', a + 1);
      if (a == std::string::npos || b == std::string::npos) continue;
      const std::size_t k = std::stoul(line.substr(0, a));
      if (k < rows.size() && accept(k)) add({k, std::stoi(line.substr(a + 1, b - a - 1)), line.substr(b + 1)});
    }
  }
  std::vector<std::string> rows;
  std::vector<int> codes;
  std::vector<bool> reported;
};

using Clock = std::chrono::steady_clock;

// The end of a sweep, where the index is written: the cases not reported recorded as not run
// (no process took them, after a signal), the index, the summary line (with the sweep's own wall
// time since `start`, the process's start-up and MPI's excluded), the exit code (0 when every
// case completed, else that of the first case, in case order, that did not).
int finish_sweep(const CommandLine& cl, const SweepPlan& plan, Results& results, Clock::time_point start) {
  for (std::size_t k = 0; k < plan.cases.size(); ++k)
    if (!results.reported[k]) results.add({k, -1, index_row(k, plan.cases[k], CaseRecord{}, cl.summary.given())});
  std::size_t complete = 0;
  int code = kSuccess;
  for (int c : results.codes) {
    if (c == 0) ++complete;
    else if (code == kSuccess) code = c < 0 ? kOtherError : c;
  }
  write_index(cl, results.rows);
  if (!cl.quiet || complete != results.codes.size())
    std::printf("sweep done: %zu of %zu cases complete in %.3f s -> %s\n", complete, results.codes.size(),
                std::chrono::duration<double>(Clock::now() - start).count(), index_path(cl).string().c_str());
  return code;
}

// The cases handed out one at a time, the most costly first, from a counter on rank 0 that
// every rank increments atomically (MPI one-sided MPI_Fetch_and_op): each rank takes the next
// case when it is free, so a slow or busy rank gets fewer cases.
class CaseQueue {
 public:
  CaseQueue(std::vector<std::size_t> order, MPI_Comm comm) : order_(std::move(order)) {
    const MPI_Aint bytes = comm_rank(comm) == 0 ? static_cast<MPI_Aint>(sizeof(long)) : 0;
    MPI_Win_allocate(bytes, sizeof(long), MPI_INFO_NULL, comm, &next_, &window_);
    if (comm_rank(comm) == 0) *next_ = 0;
    MPI_Barrier(comm);  // nobody takes a case before the counter is set
  }
  CaseQueue(const CaseQueue&) = delete;
  CaseQueue& operator=(const CaseQueue&) = delete;
  /// Collective: each rank arrives when the queue is empty.
  ~CaseQueue() { MPI_Win_free(&window_); }

  /// The next case; nullopt when every one is taken.
  std::optional<std::size_t> take() {
    const long one = 1;
    long i = 0;
    MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, window_);
    MPI_Fetch_and_op(&one, &i, MPI_LONG, 0, 0, MPI_SUM, window_);
    MPI_Win_unlock(0, window_);
    if (i < 0 || static_cast<std::size_t>(i) >= order_.size()) return std::nullopt;
    return order_[static_cast<std::size_t>(i)];
  }

 private:
  std::vector<std::size_t> order_;
  MPI_Win window_ = MPI_WIN_NULL;
  long* next_ = nullptr;  ///< rank 0: the next position in order_
};

}  // namespace

int run_sweep(const CommandLine& cl, const SweepPlan& plan, MPI_Comm comm) {
  const Clock::time_point start = Clock::now();
  const std::vector<SweepCase>& cases = plan.cases;
  prepare_directory(cl, cases, comm);
  const int size = comm_size(comm), rank = comm_rank(comm);
  const setup::RunLimits limits = sweep_limits(cl.limits, comm);
  if (rank == 0 && !cl.quiet)
    std::printf("sweep of %s: %zu cases on %d rank(s) -> %s\n", cl.scene.c_str(), cases.size(), size, cl.output.c_str());
  // One rank: the cases in order. Ranks: from the shared queue. Each case alone, on MPI_COMM_SELF.
  std::vector<CaseResult> mine;
  if (size == 1) {
    std::size_t k = 0;
    mine = run_cases(
        cl, plan, limits, [&]() -> std::optional<std::size_t> { return k < cases.size() ? std::optional(k++) : std::nullopt; },
        MPI_COMM_SELF);
  } else {
    CaseQueue queue(by_cost(cases), comm);
    mine = run_cases(cl, plan, limits, [&] { return queue.take(); }, MPI_COMM_SELF);
  }
  const std::string all = gather_text(pack(mine), comm);
  if (rank != 0) return kSuccess;
  Results results(cases.size());
  results.add_packed(all, [](std::size_t) { return true; });
  return finish_sweep(cl, plan, results, start);
}

}  // namespace traverse::app

// Rod benchmarks (not tests: no assertions on time; they print tables and append CSV rows).
//
//   bench_rod accuracy [--force F] [--solvers KLU2,GMRES+SCHWARZ,...] [--csv FILE]
//       Hanging cable (scene rod, L = 1, clamped / sliding along k, static initial state under
//       gravity, F moving at alpha v1 = 0.5 * 7.2684 m/s, dt = ds / v) for ds = 0.04 .. 0.0025:
//       run time (time-stepping only) and error of the midspan-height history against the
//       ds = 0.00125 run (same ranks, first solver), at the times of the ds = 0.04 grid.
//   bench_rod cost --nodes N [--solver S] [--steps K] [--csv FILE] [--label TEXT] [--mem]
//       Per-step and per-Newton-iteration cost of the same scene at N nodes, the cost of one
//       block-tridiagonal LU (12x12 blocks) of the same size measured in the same run (the
//       floor), their ratio, linear (Belos) iterations, and peak memory (getrusage maxrss,
//       summed over ranks, taken before the floor allocates its own storage: the static
//       initial state solved over the ranks, the set-up and the steps) per node, and the
//       largest rank's peak [MiB]. One N per process so that maxrss
//       belongs to that N. --mem: also print resident memory per phase (kB per node, rank 0)
//       to stderr.
//
//   bench_rod planar [--nodes N] [--solver S] [--steps K] [--force F] [--csv FILE] [--label TEXT]
//       Planar fast path against the 3D path on the same hanging cable (N nodes, default 101 =
//       the scene's ds = 0.01; K steps, default the whole crossing of the load): the planar
//       detection's verdict, then both steppers advanced alternately step by step in this one
//       process (so both see the same machine load), each step timed; per path: run time,
//       per-Newton time split into assembly (kernels + W/f fill), linear set-up (factorisation or
//       preconditioner) and the rest (solve, Newton), the floor of the path's block size (one
//       block-tridiagonal LU with 12 x 12 blocks for 3D, 6 x 6 planar, same nodes, this process)
//       and the ratio per Newton iteration / floor, and the ratio 3D / planar; finally the
//       largest difference of the two final states (y, R; yt scaled by gt dt).
//
// Solver names: auto (the default: block-tridiagonal LU, direct on any number of ranks), KLU2,
// GMRES+BLOCK_TRIDIAGONAL, GMRES+SCHWARZ, GMRES+ILUT, GMRES+RILUK, with optional suffixes
// ":modified" (Jacobian Reuse = modified Newton) and ":stratimikos-klu2" (KLU2 through
// Stratimikos' own Amesos2 adapter).
#include <malloc.h>
#include <sys/resource.h>

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_Core.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "block_tridiagonal_lu.hpp"
#include "traverse/rod/planar.hpp"
#include "reference_statics.hpp"
#include "traverse/rod/static_load_steps.hpp"
#include "traverse/solver/distributed_stepper.hpp"
#include "traverse/solver/static_start.hpp"

using namespace traverse;
using Clock = std::chrono::steady_clock;

namespace {

// The smoke runs' own checks (a failed check: exit 1): the floor's residual and the agreement
// of the planar and the 3D path's final states (max |dy|, |dR|, gt dt |dyt|).
constexpr double kFloorResidual = 1e-9;
constexpr double kPathAgreement = 1e-8;

constexpr double kV1 = 7.2684;  // first-resonance speed of the hanging cable [m/s]
constexpr double kAlpha = 0.5;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

Teuchos::RCP<const Teuchos::Comm<int>> comm() { return Tpetra::getDefaultComm(); }
bool root() { return comm()->getRank() == 0; }

/// Memory sampling (bench_rod cost --mem): VmRSS and VmHWM of this process [kB] from
/// /proc/self/status (0 where it is not available).
struct MemSample {
  long rss_kb = 0, hwm_kb = 0;
};
MemSample mem_sample() {
  MemSample m;
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) m.rss_kb = std::stol(line.substr(6));
    if (line.rfind("VmHWM:", 0) == 0) m.hwm_kb = std::stol(line.substr(6));
  }
  return m;
}
bool g_mem = false;  ///< --mem: print a memory line per phase to stderr (rank 0)
int g_mem_nodes = 1;
MemSample g_mem_last;
/// One line per phase: resident memory now, its change since the last phase and the peak so
/// far, in kB per node (rank 0's process only).
void mem_phase(const char* phase) {
  if (!g_mem || !root()) return;
  const MemSample m = mem_sample();
  const double n = g_mem_nodes;
  std::fprintf(stderr, "# mem %-34s rss %8.2f  delta %+8.2f  peak %8.2f  kB/node\n", phase, m.rss_kb / n,
               (m.rss_kb - g_mem_last.rss_kb) / n, m.hwm_kb / n);
  g_mem_last = m;
}

Teuchos::ParameterList solver_params(const std::string& full) {
  Teuchos::ParameterList p;
  p.set("Verbose", false);
  std::string name = full;
  std::string opts;
  if (auto c = full.find(':'); c != std::string::npos) {
    name = full.substr(0, c);
    opts = full.substr(c);
  }
  if (name == "KLU2") {
    p.set("Linear Solver", "KLU2");
  } else if (name == "auto") {
    p.set("Linear Solver", "auto");  // the time-step default: the block-tridiagonal LU, direct
  } else if (name.rfind("GMRES+", 0) == 0) {
    p.set("Linear Solver", "GMRES");
    p.set("Preconditioner", name.substr(6));
  } else {
    throw std::invalid_argument("bench_rod: unknown solver " + full);
  }
  if (opts.find(":modified") != std::string::npos) p.set("Jacobian Reuse", true);
  if (opts.find(":stratimikos-klu2") != std::string::npos) p.set("Direct Solver Path", "Stratimikos");
  return p;
}

struct Scene {
  rod::RodModel model;
  std::vector<Vec3> force_vectors;  ///< fixed-frame vector of each point force (planar check)
  rod::RodState initial;
  int first_node = 0;  ///< global index of initial.nodes.front() (a piece: this rank's nodes and ghosts)
  double v = 0.0, dt = 0.0, t_end = 0.0;
  int steps = 0;
  int static_iterations = 0;
  double static_seconds = 0.0;
};

/// The hanging cable with F [N] at alpha v1, N cells, dt = ds / v. `pieces`: the static
/// initial state solved over the ranks (solver::solve_static_start, as `traverse run` does),
/// each rank keeping its nodes and ghosts; otherwise the serial solve of the whole rod.
Scene hanging_cable(int N, double F, bool pieces = false) {
  Scene s;
  rod::RodModel& m = s.model;
  m.props = rod::RodProperties::scene_rod();  // r = 5 mm, E = 250 MPa, nu = 0.25, rho = 1500
  m.num_cells = N;
  m.length = 1.0;
  m.left = rod::EndCondition::make_clamped();
  m.right = rod::EndCondition::make_sliding(Vec3::UnitZ());
  m.loads.gravity = Vec3(0.0, -9.8, 0.0);
  s.v = kAlpha * kV1;
  const double v = s.v;
  const Vec3 force(0.0, -F, 0.0);
  m.loads.point_forces.push_back({[force](double) { return force; }, [v](double t) { return v * t; }});
  s.force_vectors.push_back(force);
  s.dt = m.ds() / v;
  s.t_end = m.length / v;
  s.steps = static_cast<int>(std::ceil(s.t_end / s.dt - 1e-9));

  rod::StaticModel sm;
  sm.props = m.props;
  sm.num_cells = N;
  sm.length = m.length;
  sm.left.type = rod::EndCondition::Type::clamped;
  sm.right.type = rod::EndCondition::Type::sliding;
  sm.right.axis = Vec3::UnitZ();
  sm.right.position = Vec3(0.0, 0.0, m.length);
  sm.gravity = m.loads.gravity;
  sm.point_forces.push_back({force, 0.0});  // the load sits on the left end at t = 0
  if (pieces) {
    const auto t0 = Clock::now();
    const solver::StaticStart st = solver::solve_static_start(sm, comm());
    s.static_seconds = seconds_since(t0);
    if (!st.report.converged) throw std::runtime_error("bench_rod: static initial state failed: " + st.report.message);
    mem_phase("static: solved over the ranks");
    s.static_iterations = st.report.iterations;
    s.initial = solver::dynamic_state_piece(sm, st, s.first_node);
    mem_phase("static: dynamic initial state");
    return s;
  }
  auto nodes = rod::straight_static_state(sm);
  mem_phase("static: straight state");
  const auto t0 = Clock::now();
  const auto rep = rod::serial_load_steps(sm, nodes);
  s.static_seconds = seconds_since(t0);
  if (!rep.converged) throw std::runtime_error("bench_rod: static initial state failed: " + rep.message);
  mem_phase("static: solved");
  s.static_iterations = rep.iterations;
  s.initial = rod::dynamic_state_from_static(sm, nodes);
  mem_phase("static: dynamic initial state");
  return s;
}

/// Height (fixed j component) of the centreline at s = L/2 (linear between nodes).
double midspan_height(const rod::RodState& st) {
  const std::vector<Vec3> r = rod::centreline_in_space(st);
  const int N = st.num_cells();
  const double x = 0.5 * N;
  const int j = std::min(static_cast<int>(std::floor(x)), N - 1);
  const double xi = x - j;
  return (1.0 - xi) * r[static_cast<size_t>(j)](1) + xi * r[static_cast<size_t>(j + 1)](1);
}

struct History {
  std::vector<double> t, h;
  double step_seconds = 0.0, setup_seconds = 0.0;
  long newton = 0, linear = 0, substeps = 0;
  std::string resolved;
};

History run_history(int N, double F, const std::string& solver) {
  Scene sc = hanging_cable(N, F);
  History H;
  const auto t0 = Clock::now();
  solver::DistributedStepper st(sc.model, comm(), solver_params(solver));
  st.set_state(sc.initial);
  H.setup_seconds = seconds_since(t0);
  H.resolved = st.resolved_linear_solver();
  H.t.push_back(0.0);
  H.h.push_back(midspan_height(st.gather_state()));
  for (int i = 1; i <= sc.steps; ++i) {
    const double h = i == sc.steps ? sc.t_end - st.time() : sc.dt;
    if (h <= 0.0) break;
    comm()->barrier();
    const auto ts = Clock::now();
    const auto rep = st.step(h);
    H.step_seconds += seconds_since(ts);
    H.newton += rep.newton_iterations;
    H.linear += rep.linear_iterations;
    H.substeps += rep.substeps;
    H.t.push_back(st.time());
    H.h.push_back(midspan_height(st.gather_state()));  // gathering is not timed
  }
  return H;
}

/// max over the reference grid times t_k (those of `coarse`) of |a(t_k) - b(t_k)|: every run
/// contains the coarse grid's times exactly (dt halves with ds), matched to 1e-9 s.
double history_error(const History& a, const History& ref, const std::vector<double>& times) {
  auto at = [](const History& H, double t) {
    for (size_t k = 0; k < H.t.size(); ++k)
      if (std::abs(H.t[k] - t) < 1e-9) return H.h[k];
    throw std::runtime_error("bench_rod: time not on the grid");
  };
  double e = 0.0;
  for (double t : times) e = std::max(e, std::abs(at(a, t) - at(ref, t)));
  return e;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep))
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string arg(int argc, char** argv, const char* key, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], key) == 0) return argv[i + 1];
  return fallback;
}

void append_csv(const std::string& file, const std::string& header, const std::string& row) {
  if (file.empty() || !root()) return;
  const bool fresh = !std::ifstream(file).good();
  std::ofstream out(file, std::ios::app);
  if (fresh) out << header << "\n";
  out << row << "\n";
}

int accuracy(int argc, char** argv) {
  const double F = std::stod(arg(argc, argv, "--force", "2"));
  const int ranks = comm()->getSize();
  const std::string default_solvers =
      ranks == 1 ? "auto,KLU2,GMRES+SCHWARZ,GMRES+ILUT" : "auto,GMRES+BLOCK_TRIDIAGONAL,GMRES+SCHWARZ,GMRES+ILUT";
  const auto solvers = split(arg(argc, argv, "--solvers", default_solvers), ',');
  const std::string csv = arg(argc, argv, "--csv", "");
  const std::vector<int> Ns = {25, 50, 100, 200, 400};  // ds = 0.04 .. 0.0025
  const int Nref = 800;                                 // ds = 0.00125

  const History ref = run_history(Nref, F, solvers.front());
  const History coarse_grid = run_history(Ns.front(), F, solvers.front());
  const std::vector<double> times = coarse_grid.t;
  if (root())
    std::printf("# hanging cable, F = %g N, alpha = %g, %d rank(s); reference: ds = %g with %s "
                "(%.2f s, %ld Newton its)\n"
                "%-16s %8s %6s %10s %10s %8s %10s %10s %12s\n",
                F, kAlpha, ranks, 1.0 / Nref, solvers.front().c_str(), ref.step_seconds, ref.newton, "solver",
                "ds", "steps", "run [s]", "setup [s]", "Newton", "Newton/st", "lin/Newton", "max|dh| [m]");
  std::map<int, History> finest;  // per N of the first solver (Richardson estimate)
  for (const auto& s : solvers) {
    for (int N : Ns) {
      const History H = run_history(N, F, s);
      const double err = history_error(H, ref, times);
      const double per_step = H.substeps ? double(H.newton) / H.substeps : 0.0;
      const double lin = H.newton ? double(H.linear) / H.newton : 0.0;
      if (root())
        std::printf("%-16s %8.5f %6ld %10.4f %10.4f %8ld %10.2f %10.1f %12.4e\n", s.c_str(), 1.0 / N, H.substeps,
                    H.step_seconds, H.setup_seconds, H.newton, per_step, lin, err);
      append_csv(csv, "force,ranks,solver,ds,nodes,steps,run_seconds,setup_seconds,newton,linear,error,reference_ds",
                 std::to_string(F) + "," + std::to_string(ranks) + "," + s + "," + std::to_string(1.0 / N) + "," +
                     std::to_string(N + 1) + "," + std::to_string(H.substeps) + "," + std::to_string(H.step_seconds) +
                     "," + std::to_string(H.setup_seconds) + "," + std::to_string(H.newton) + "," +
                     std::to_string(H.linear) + "," + std::to_string(err) + "," + std::to_string(1.0 / Nref));
      if (&s == &solvers.front()) finest[N] = H;
    }
  }
  // Observed order from the last three ds of the first solver and the reference's own error
  // estimated by Richardson extrapolation (e_ref ~ |h_ref - h_{2 ds_ref}| / (2^p - 1)).
  const double e1 = history_error(finest[100], finest[200], times);
  const double e2 = history_error(finest[200], finest[400], times);
  const double p = std::log2(e1 / e2);
  const double e3 = history_error(finest[400], ref, times);
  if (root())
    std::printf("# observed order (ds 0.01/0.005/0.0025, %s): %.2f; Richardson estimate of the reference's own "
                "error: %.2e m (errors below about that are not resolved)\n",
                solvers.front().c_str(), p, e3 / (std::pow(2.0, p) - 1.0));
  return 0;
}

int cost(int argc, char** argv) {
  const int nodes = std::stoi(arg(argc, argv, "--nodes", "1001"));
  const std::string solver = arg(argc, argv, "--solver", comm()->getSize() == 1 ? "KLU2" : "GMRES+SCHWARZ");
  const std::string csv = arg(argc, argv, "--csv", "");
  const std::string label = arg(argc, argv, "--label", "");
  int steps = std::stoi(arg(argc, argv, "--steps", "0"));
  const double F = std::stod(arg(argc, argv, "--force", "2"));
  const int N = nodes - 1;
  g_mem = std::find_if(argv, argv + argc, [](const char* a) { return std::strcmp(a, "--mem") == 0; }) != argv + argc;
  g_mem_nodes = nodes;
  mem_phase("start");
  Scene sc = hanging_cable(N, F, true);
  const auto t0 = Clock::now();
  auto stepper = std::make_unique<solver::DistributedStepper>(sc.model, comm(), solver_params(solver));
  solver::DistributedStepper& st = *stepper;
  mem_phase("stepper constructed");
  st.set_state(sc.initial, sc.first_node);
  std::vector<rod::RodNode>().swap(sc.initial.nodes);  // the stepper holds its own copy
  const double setup = seconds_since(t0);
  mem_phase("state set");
  // One warm-up step (first factorisations, first preconditioner), then timed steps.
  st.step(sc.dt);
  mem_phase("warm-up step");
  const solver::ReuseCounters c0 = st.reuse_counters();
  if (steps <= 0) steps = nodes <= 2000 ? 40 : nodes <= 20000 ? 12 : 5;
  // The machine is shared: per step, the median of the step times (per Newton iteration:
  // the median over steps of step time / its Newton iterations) is reported, which a burst
  // of load on a few steps does not move; the mean goes to the CSV as well.
  long newton = 0, linear = 0;
  std::vector<double> per_step_times, per_newton_times;
  comm()->barrier();
  const auto ts = Clock::now();
  for (int i = 0; i < steps; ++i) {
    const auto t1 = Clock::now();
    const auto rep = st.step(sc.dt);
    const double el_local = seconds_since(t1);
    double el = el_local;
    Teuchos::reduceAll(*comm(), Teuchos::REDUCE_MAX, 1, &el_local, &el);
    per_step_times.push_back(el);
    per_newton_times.push_back(el / std::max(1, rep.newton_iterations));
    newton += rep.newton_iterations;
    linear += rep.linear_iterations;
  }
  comm()->barrier();
  const double run = seconds_since(ts);
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  const solver::ReuseCounters c1 = st.reuse_counters();
  mem_phase("timed steps");
  // Peak memory of the rod run (static state, set-up, steps), taken before the floor below
  // allocates its own block storage.
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  double kb = static_cast<double>(ru.ru_maxrss), kb_sum = 0.0, kb_max = 0.0;
  Teuchos::reduceAll(*comm(), Teuchos::REDUCE_SUM, 1, &kb, &kb_sum);
  Teuchos::reduceAll(*comm(), Teuchos::REDUCE_MAX, 1, &kb, &kb_max);
  if (g_mem) {  // diagnostics: how much of the resident memory is free heap kept by malloc
    malloc_trim(0);
    mem_phase("after malloc_trim (diagnostic)");
  }
  // The rod's memory is released before the floor allocates its own (at 10^6 nodes both
  // together would not fit).
  const std::string resolved = st.resolved_linear_solver();
  stepper.reset();
  mem_phase("stepper released");

  // Floor: one block-tridiagonal LU of the same size (N + 1 blocks of 12x12), rank 0 only.
  double floor = 0.0, floor_res = 0.0;
  if (root()) {  // median of five timings
    std::vector<double> f;
    for (int k = 0; k < 5; ++k) f.push_back(bench::time_block_tridiagonal(nodes, 0.1, &floor_res));
    std::sort(f.begin(), f.end());
    floor = f[2];
  }
  Teuchos::broadcast(*comm(), 0, &floor);
  mem_phase("floor timed");

  const double per_step = median(per_step_times), per_newton = median(per_newton_times);
  const double mean_step = run / steps;
  const double assembly = (c1.assembly_seconds - c0.assembly_seconds) / std::max(1L, newton);
  const double lin_setup = (c1.linear_setup_seconds - c0.linear_setup_seconds) / std::max(1L, newton);
  if (root()) {
    std::printf("%-28s %2d %9d %4d %10.3e %10.3e %6.2f %10.3e %7.2f %9.3e %9.3e %8.1f %8.2f %9.1f %s\n",
                solver.c_str(), comm()->getSize(), nodes, steps, per_step, per_newton, double(newton) / steps, floor,
                per_newton / floor, assembly, lin_setup, newton ? double(linear) / newton : 0.0,
                kb_sum / 1024.0 / nodes * 1024.0, kb_max / 1024.0, resolved.c_str());
    std::fflush(stdout);
  }
  append_csv(csv,
             "label,solver,ranks,nodes,steps,step_seconds,newton_seconds,newton_per_step,floor_seconds,ratio,"
             "assembly_seconds_per_newton,linear_setup_seconds_per_newton,linear_per_newton,maxrss_kb_total,"
             "kb_per_node,setup_seconds,static_seconds,mean_step_seconds,maxrss_kb_rank_max",
             label + "," + solver + "," + std::to_string(comm()->getSize()) + "," + std::to_string(nodes) + "," +
                 std::to_string(steps) + "," + std::to_string(per_step) + "," + std::to_string(per_newton) + "," +
                 std::to_string(double(newton) / steps) + "," + std::to_string(floor) + "," +
                 std::to_string(per_newton / floor) + "," + std::to_string(assembly) + "," +
                 std::to_string(lin_setup) + "," + std::to_string(newton ? double(linear) / newton : 0.0) + "," +
                 std::to_string(kb_sum) + "," + std::to_string(kb_sum / nodes) + "," + std::to_string(setup) + "," +
                 std::to_string(sc.static_seconds) + "," + std::to_string(mean_step) + "," + std::to_string(kb_max));
  // The run's own checks: every step converged (a failed step throws) with Newton iterations,
  // and the floor solved its system (max |A x - b| at rounding of its O(1) entries).
  bool ok = true;
  if (!(floor_res <= kFloorResidual) && root()) {
    std::fprintf(stderr, "bench_rod cost: the floor's residual max |A x - b| = %.3e exceeds %.0e\n", floor_res,
                 kFloorResidual);
    ok = false;
  }
  if (newton < steps) {
    std::fprintf(stderr, "bench_rod cost: %ld Newton iterations in %d steps\n", newton, steps);
    ok = false;
  }
  return ok ? 0 : 1;
}

int planar(int argc, char** argv) {
  const int nodes = std::stoi(arg(argc, argv, "--nodes", "101"));
  const std::string solver = arg(argc, argv, "--solver", comm()->getSize() == 1 ? "KLU2" : "GMRES+SCHWARZ");
  const std::string csv = arg(argc, argv, "--csv", "");
  const std::string label = arg(argc, argv, "--label", "");
  const double F = std::stod(arg(argc, argv, "--force", "2"));
  Scene sc = hanging_cable(nodes - 1, F);
  int steps = std::stoi(arg(argc, argv, "--steps", "0"));
  if (steps <= 0) steps = sc.steps;
  const rod::PlanarCheck chk = rod::check_planar(sc.model, sc.initial, sc.force_vectors);
  if (!chk.planar) throw std::runtime_error("the cable is not planar: " + chk.reason);

  solver::DistributedStepper s3(sc.model, comm(), solver_params(solver));
  s3.set_state(sc.initial);
  solver::DistributedStepper s2(sc.model, comm(), solver_params(solver));
  s2.set_state(sc.initial);
  s2.set_planar(&chk.symmetry);
  if (root())
    std::printf("# hanging cable, F = %g N, %d nodes, %d steps of dt = %g s, %s, %d rank(s)\n"
                "# planar check: planar, %s\n# paths: %s | %s\n",
                F, nodes, steps, sc.dt, solver.c_str(), comm()->getSize(), chk.symmetry.describe().c_str(),
                s3.path_description().c_str(), s2.path_description().c_str());

  struct Path {
    solver::DistributedStepper* st = nullptr;
    double seconds = 0.0;
    long newton = 0, linear = 0;
    std::vector<double> per_newton;
  };
  Path P[2];
  P[0].st = &s3;
  P[1].st = &s2;
  for (int i = 0; i < steps; ++i) {
    const double h = i + 1 == sc.steps ? sc.t_end - s3.time() : sc.dt;
    if (h <= 0.0) break;
    for (Path& p : P) {  // alternately, so that both paths see the same machine load
      comm()->barrier();
      const auto t1 = Clock::now();
      const auto rep = p.st->step(h);
      const double local = seconds_since(t1);
      double el = local;
      Teuchos::reduceAll(*comm(), Teuchos::REDUCE_MAX, 1, &local, &el);
      p.seconds += el;
      p.newton += rep.newton_iterations;
      p.linear += rep.linear_iterations;
      p.per_newton.push_back(el / std::max(1, rep.newton_iterations));
    }
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  // Agreement of the final states.
  const rod::RodState a = s3.gather_state(), b = s2.gather_state();
  double dy = 0.0, dR = 0.0, dyt = 0.0;
  const double gtdt = sc.model.alpha.gt * sc.dt;
  for (size_t j = 0; j < a.nodes.size(); ++j) {
    dy = std::max(dy, (a.nodes[j].y - b.nodes[j].y).cwiseAbs().maxCoeff());
    dR = std::max(dR, (a.nodes[j].R - b.nodes[j].R).cwiseAbs().maxCoeff());
    dyt = std::max(dyt, gtdt * (a.nodes[j].yt - b.nodes[j].yt).cwiseAbs().maxCoeff());
  }
  // The floors of the two block sizes (12 x 12, 6 x 6 blocks; carried ys: 24, 12), medians of five.
  auto floor_of = [&](int b) {
    std::vector<double> f;
    for (int k = 0; k < 5; ++k)
      f.push_back(b == 6    ? bench::time_block_tridiagonal<6>(nodes, 0.1)
                  : b == 12 ? bench::time_block_tridiagonal<12>(nodes, 0.1)
                            : bench::time_block_tridiagonal<24>(nodes, 0.1));
    return median(f);
  };
  const char* names[2] = {"3D", "planar"};
  double per_newton[2], run[2], floors[2];
  for (int k = 0; k < 2; ++k) {
    floors[k] = root() ? floor_of(P[k].st->unknowns_per_node()) : 0.0;
    Teuchos::broadcast(*comm(), 0, &floors[k]);
  }
  if (root())
    std::printf("%-7s %4s %10s %8s %10s %10s %10s %10s %10s %8s %10s %7s %7s\n", "path", "p", "run [s]", "Newton",
                "s/Newton", "median", "asm/N", "linset/N", "rest/N", "lin/N", "floor [s]", "ratio", "r.med");
  for (int k = 0; k < 2; ++k) {
    const Path& p = P[k];
    const solver::ReuseCounters c = p.st->reuse_counters();
    const double nN = static_cast<double>(std::max(1L, p.newton));
    per_newton[k] = p.seconds / nN;
    run[k] = p.seconds;
    const double asmN = c.assembly_seconds / nN, linN = c.linear_setup_seconds / nN;
    if (root())
      std::printf("%-7s %4d %10.4f %8ld %10.3e %10.3e %10.3e %10.3e %10.3e %8.1f %10.3e %7.2f %7.2f\n", names[k],
                  p.st->unknowns_per_node(), p.seconds, p.newton, per_newton[k], median(p.per_newton), asmN, linN,
                  per_newton[k] - asmN - linN, double(p.linear) / nN, floors[k], per_newton[k] / floors[k],
                  median(p.per_newton) / floors[k]);
    append_csv(csv,
               "label,solver,ranks,nodes,steps,path,unknowns_per_node,run_seconds,newton,newton_seconds,"
               "median_newton_seconds,assembly_seconds_per_newton,linear_setup_seconds_per_newton,linear_per_newton,"
               "floor_seconds,ratio,median_ratio",
               label + "," + solver + "," + std::to_string(comm()->getSize()) + "," + std::to_string(nodes) + "," +
                   std::to_string(steps) + "," + names[k] + "," + std::to_string(p.st->unknowns_per_node()) + "," +
                   std::to_string(p.seconds) + "," + std::to_string(p.newton) + "," + std::to_string(per_newton[k]) +
                   "," + std::to_string(median(p.per_newton)) + "," + std::to_string(asmN) + "," +
                   std::to_string(linN) + "," + std::to_string(double(p.linear) / nN) + "," +
                   std::to_string(floors[k]) + "," + std::to_string(per_newton[k] / floors[k]) + "," +
                   std::to_string(median(p.per_newton) / floors[k]));
  }
  if (root())
    std::printf("# ratio = s/Newton / floor (one block-tridiagonal LU of the path's block size, same nodes; r.med: "
                "the median s/Newton)\n# speed-up 3D / planar: run time %.2fx, per Newton iteration %.2fx\n"
                "# final states differ by max|dy| %.2e, max|dR| %.2e, max gt dt |dyt| %.2e\n",
                run[0] / run[1], per_newton[0] / per_newton[1], dy, dR, dyt);
  // The run's own check: both paths solve the same planar problem, so their final states
  // agree to the Newton tolerance's level, far below the motion (the cable moves ~0.1 m).
  if (!(std::max({dy, dR, dyt}) <= kPathAgreement)) {
    if (root())
      std::fprintf(stderr, "bench_rod planar: the paths' final states differ by %.3e > %.0e\n",
                   std::max({dy, dR, dyt}), kPathAgreement);
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Tpetra::ScopeGuard guard(&argc, &argv);
  const std::string mode = argc > 1 ? argv[1] : "";
  try {
    if (mode == "accuracy") return accuracy(argc, argv);
    if (mode == "cost") return cost(argc, argv);
    if (mode == "planar") return planar(argc, argv);
    if (mode == "cost-header") {
      std::printf("%-28s %2s %9s %4s %10s %10s %6s %10s %7s %9s %9s %8s %8s %9s %s\n", "solver", "rk", "nodes", "st",
                  "s/step", "s/Newton", "N/st", "floor [s]", "ratio", "asm/N", "linset/N", "lin/N", "kB/node",
                  "rank MiB", "resolved");
      return 0;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_rod: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr, "usage: bench_rod accuracy|cost|cost-header|planar [options] (see the source's header)\n");
  return 2;
}

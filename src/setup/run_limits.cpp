#include "traverse/setup/run_limits.hpp"

#include "traverse/setup/rod_setup.hpp"
#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/solver/rod_stepper.hpp"
#include "traverse/solver/solver_parameters.hpp"
#include "traverse/solver/static_continuation.hpp"
#include "traverse/solver/static_start.hpp"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "traverse/beam/uniform_modes.hpp"
#include "traverse/rod/alpha_parameters.hpp"

namespace traverse::setup {

namespace {

using scene::format_number;

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// A count: every digit up to 10^15, else as fmt.
std::string count(double v) {
  if (!(std::abs(v) < 1e15)) return fmt(v);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f", v);
  return buf;
}

std::string ranks_text(int ranks) { return std::to_string(ranks) + (ranks == 1 ? " rank" : " ranks"); }

// Whether the scene sets the mesh by mesh.ds (else by mesh.nodes, or the default 101 nodes).
bool mesh_by_ds(const scene::Scene& sc) { return sc.has("mesh.ds"); }

// The mesh key the scene gives.
std::string mesh_key(const scene::Scene& sc) { return mesh_by_ds(sc) ? "mesh.ds" : "mesh.nodes"; }

std::string mesh_text(const scene::Scene& sc) {
  const std::string model = sc.model == scene::Model::Beam ? "beam" : "rod";
  return std::to_string(sc.mesh.nodes) + " nodes (" +
         (mesh_by_ds(sc) ? "mesh.ds = " + fmt(sc.mesh.ds) + " m over " + model + ".length = " + fmt(sc.length()) + " m"
                         : "mesh.nodes") +
         ")";
}

// The end time of a run whose time.end is auto: when the last load leaves; its keys.
double auto_end(const scene::Scene& sc, TimePlan& p) {
  const scene::MovingLoadSpec* last = nullptr;
  double t_end = 0.0;
  for (const auto& l : sc.loads) {
    const double te = l.exit_time(sc.length());
    if (std::isfinite(te) && (!last || te > t_end)) {
      t_end = te;
      last = &l;
    }
  }
  if (!last) {
    p.end_text = "time.end: auto (no load leaves the structure)";
    p.end_keys = {"time.end"};
    return 0.0;
  }
  const std::string k = "loads." + last->name + ".";
  p.end_text = "time.end: auto = when load '" + last->name + "' leaves, t = " + fmt(t_end) + " s (" + k +
               "entry_time = " + fmt(last->entry_time) + " s, speed = " + fmt(last->speed) + " m/s";
  if (last->acceleration != 0.0) p.end_text += ", acceleration = " + fmt(last->acceleration) + " m/s^2";
  p.end_text += ", from " + fmt(last->start) + " m)";
  const double distance = last->direction() > 0 ? sc.length() - last->start : last->start;
  // A load that starts at the far end, or whose entry time is most of the end time, is decided
  // by its start or its entry time; otherwise by its motion.
  if (!(distance > 0.0)) p.end_keys.push_back(k + "start");
  p.entry_dominated = distance > 0.0 && last->entry_time > 0.0 && last->entry_time >= 0.5 * t_end;
  if (p.entry_dominated) p.end_keys.push_back(k + "entry_time");
  p.end_keys.push_back(k + "speed");
  if (last->acceleration != 0.0) p.end_keys.push_back(k + "acceleration");
  p.end_keys.push_back(k + "entry_time");
  p.end_keys.push_back(k + "start");
  return t_end;
}

double fixed_end(const scene::Scene& sc, TimePlan& p) {
  if (sc.time.end_at_event) {  // a coupled_mass with time.end: auto
    p.end_text = "time.end: auto (the coupled mass's first event), at the latest time.auto_limit = " +
                 fmt(sc.time.end) + " s";
    p.end_keys = {"time.auto_limit", "time.end"};
    return sc.time.end;
  }
  p.end_text = "time.end = " + fmt(sc.time.end) + " s";
  p.end_keys = {"time.end"};
  return sc.time.end;
}

std::vector<std::string> joined(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// The program itself: MPI, Kokkos, Trilinos and the executable (peak resident memory of a run
// on a 2-node rod, Open MPI 4.1); each model's figures per node come from its module.
constexpr double kProgramBytes = 64.0 * 1024 * 1024;

// The time stepping's memory factor of the scene's linear solver (LinearSolverChoice::
// memory_factor; a Stratimikos list counts as GMRES) and its name.
double rod_solver_factor(const scene::Scene& sc, int ranks, std::string& name) {
  solver::LinearSolverChoice c;
  try {
    c = solver::LinearSolverChoice::resolve(solver::validated_solver_parameters(sc.solver_parameters()), ranks,
                                            solver::LinearSolverChoice::Use::time_step);
  } catch (const std::invalid_argument&) {
    name = "a refused linear solver (counted as GMRES)";  // the run itself reports it (exit 2)
    return 1.4;
  }
  name = c.resolved;
  const auto& given = sc.solver_parameters();
  if (given.isSublist("Stratimikos") && given.sublist("Stratimikos").numParams() > 0) {
    name += " (a Stratimikos list: counted as GMRES)";
    return 1.4;
  }
  return c.memory_factor();
}

int rod_unknowns_3d(const scene::Scene& sc) {
  const auto& s = sc.scheme;
  const rod::AlphaParameters a = s.explicit_parameters ? rod::AlphaParameters{s.as, s.bs, s.gs, s.at, s.bt, s.gt}
                                                       : rod::AlphaParameters::from_rho_inf(s.rho_inf, s.rho_inf_space);
  return a.box_in_space() ? 12 : 24;
}

double owned_nodes(const scene::Scene& sc, int ranks) {
  return std::ceil(static_cast<double>(sc.mesh.nodes) / std::max(1, ranks));
}

std::string kb(double bytes) { return fmt(bytes / 1000.0) + " kB"; }

}  // namespace

std::string load_magnitude_key(const scene::Scene& sc, const scene::MovingLoadSpec& l) {
  for (const char* k : {"force", "force_vector", "mass", "mass_fraction"})
    if (sc.has("loads." + l.name + "." + k)) return "loads." + l.name + "." + k;
  return "loads." + l.name;
}

std::string format_bytes(double b) {
  if (!std::isfinite(b)) return fmt(b) + " bytes";
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (u < 6 && std::abs(b) >= 1024.0) {
    b /= 1024.0;
    ++u;
  }
  char buf[48];
  // Three significant digits; 1000 to 1023 of a unit in full (not 1.02e+03).
  std::snprintf(buf, sizeof buf, u == 0 || std::abs(b) >= 999.5 ? "%.0f %s" : "%.3g %s", b, units[u]);
  return buf;
}

double parse_bytes(const std::string& text) {
  std::string t = text;
  auto ends_with = [&](const std::string& suf) {
    if (t.size() > suf.size() && t.compare(t.size() - suf.size(), suf.size(), suf) == 0) {
      t.resize(t.size() - suf.size());
      return true;
    }
    return false;
  };
  if (!ends_with("iB")) ends_with("B");
  double scale = 1.0;
  if (!t.empty()) {
    const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(t.back())));
    const std::string units = "KMGTP";
    const auto pos = units.find(c);
    if (pos != std::string::npos) {
      scale = std::pow(1024.0, static_cast<double>(pos + 1));
      t.pop_back();
    }
  }
  if (t.empty() || !(std::isdigit(static_cast<unsigned char>(t[0])) || t[0] == '.')) return -1.0;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (*end != '\0' || !std::isfinite(v) || !(v > 0.0)) return -1.0;
  const double bytes = v * scale;
  return std::isfinite(bytes) ? bytes : -1.0;
}

std::string deciding_key(const scene::Scene& sc, const std::vector<std::string>& keys) {
  for (const auto& k : keys) {
    const auto it = sc.tree.marks.find(k);
    if (it != sc.tree.marks.end() && it->second.first < 0) return k;
  }
  return keys.empty() ? std::string() : keys.front();
}

TimePlan rod_time_plan(const scene::Scene& sc) {
  TimePlan p;
  p.dt = sc.time.dt;
  if (sc.time.dt_auto) {
    const double end = sc.time.end_auto ? -1.0 : sc.time.end;
    const scene::MovingLoadSpec* fast = nullptr;
    for (const auto& l : sc.loads)
      if (!fast || l.fastest_speed(sc.length(), end) > fast->fastest_speed(sc.length(), end)) fast = &l;
    const double v = fast ? fast->fastest_speed(sc.length(), end) : 0.0;
    const std::string k = fast ? "loads." + fast->name + ".speed" : "loads";
    const bool accelerates = fast && v > fast->speed;
    p.dt_text = "time.dt: auto = mesh.ds / " +
                (accelerates ? "(the fastest speed of load '" + fast->name + "' on the rod)" : k) + " = " +
                fmt(sc.mesh.ds) + " m / " + fmt(v) + " m/s = " + fmt(p.dt) + " s";
    p.dt_keys = {k, mesh_key(sc)};
    if (accelerates) p.dt_keys.insert(p.dt_keys.begin() + 1, "loads." + fast->name + ".acceleration");
  } else {
    p.dt_text = "time.dt = " + fmt(p.dt) + " s";
    p.dt_keys = {"time.dt"};
  }
  p.t_end = sc.time.end_auto ? auto_end(sc, p) : fixed_end(sc, p);
  p.steps = grid_step_count(p.t_end, p.dt, 1e-6);
  p.every = sc.output.every;
  p.every_text = sc.output.every_auto ? "output.every: auto = 1 (every time step)"
                                      : "output.every = " + std::to_string(p.every);
  return p;
}

beam::Support beam_support(scene::Supports s) {
  using S = scene::Supports;
  switch (s) {
    case S::simply_supported: return beam::Support::SimplySupported;
    case S::clamped_free: return beam::Support::ClampedFree;
    case S::clamped_clamped: return beam::Support::ClampedClamped;
    case S::clamped_pinned: return beam::Support::ClampedPinned;
    default: throw std::logic_error("beam_support: unknown supports");
  }
}

namespace {

/// The period of the fastest motion of a beam run: its highest mode, or an axle on a stiffer
/// suspension; `what` says which, `keys` its keys.
double fastest_period(const scene::Scene& sc, std::string& what, std::vector<std::string>& keys) {
  const auto& b = sc.beam;
  const double EI = b.youngs_modulus * b.section.I1, rhoA = b.density * b.section.area;
  const beam::UniformModes modes(beam_support(b.supports), b.modes, b.length, EI, rhoA);
  const double omega_max = modes.circular_frequencies().maxCoeff();
  double period = 2.0 * constants::pi / omega_max;
  what = "mode " + std::to_string(b.modes) + " (beam.modes; " + fmt(omega_max) + " rad/s)";
  keys = {"beam.modes", "beam.youngs_modulus", "beam.density", "beam.section"};
  for (const auto& l : sc.loads)  // a suspension faster than the highest mode
    for (std::size_t a = 0; a < l.axle_stiffness.size(); ++a) {
      const double m = l.wheel_masses[a] > 0.0 ? std::min(l.wheel_masses[a], l.mass) : l.mass;
      const double omega = std::sqrt(l.axle_stiffness[a] / m), T = 2.0 * constants::pi / omega;
      if (!(T < period)) continue;
      period = T;
      what = "axle " + std::to_string(a + 1) + " of '" + l.name + "' on its suspension (" + fmt(omega) + " rad/s)";
      keys = {"loads." + l.name + ".stiffness", "loads." + l.name + ".mass"};
    }
  return period;
}

}  // namespace

TimePlan beam_time_plan(const scene::Scene& sc) {
  TimePlan p;
  const auto& b = sc.beam;
  std::string fastest;
  std::vector<std::string> fastest_keys;
  const double period = fastest_period(sc, fastest, fastest_keys);
  double v_max = 0.0;
  const scene::MovingLoadSpec* fast = nullptr;
  for (const auto& l : sc.loads) {
    const double te = l.exit_time(b.length);
    const double v = std::max(l.speed, std::abs(l.velocity(std::isfinite(te) ? te : l.entry_time)));
    if (!fast || v > v_max) fast = &l;
    v_max = std::max(v_max, v);
  }
  if (sc.time.dt_auto) {
    p.dt = period / 20.0;
    p.dt_text = "time.dt: auto = a twentieth of the period of " + fastest + " = " + fmt(p.dt) + " s";
    p.dt_keys = fastest_keys;
    p.dt_from_modes = true;
    if (v_max > 0.0 && !(p.dt <= sc.mesh.ds / v_max)) {
      p.dt = sc.mesh.ds / v_max;
      const std::string k = "loads." + fast->name;
      p.dt_text = "time.dt: auto = mesh.ds / (the fastest speed of load '" + fast->name + "') = " + fmt(sc.mesh.ds) +
                  " m / " + fmt(v_max) + " m/s = " + fmt(p.dt) + " s";
      p.dt_keys = {k + ".speed", k + ".acceleration", mesh_key(sc)};
      p.dt_from_modes = false;
    }
  } else {
    p.dt = sc.time.dt;
    p.dt_text = "time.dt = " + fmt(p.dt) + " s";
    p.dt_keys = {"time.dt"};
  }
  p.t_end = sc.time.end_auto ? auto_end(sc, p) : fixed_end(sc, p);
  p.steps = grid_step_count(p.t_end, p.dt, beam::BeamSimulation::kGridJoin);
  if (sc.output.every_auto) {
    // The largest stride that keeps kBeamOutputsPerPeriod outputs per fastest period (a
    // relative 1e-9 forgives the rounding of dt = period / 20).
    const double stride = std::floor(period / kBeamOutputsPerPeriod / p.dt * (1.0 + 1e-9));
    p.every = std::isfinite(stride) ? static_cast<int>(std::clamp(stride, 1.0, 1e9)) : 1;
    p.every_text = "output.every: auto = " + std::to_string(p.every) + " (" + fmt(kBeamOutputsPerPeriod) +
                   " outputs per period of " + fastest + ")";
  } else {
    p.every = sc.output.every;
    p.every_text = "output.every = " + std::to_string(p.every);
  }
  return p;
}

std::string OutputSize::text() const {
  return "about " + format_bytes(h5) + " (+ " + format_bytes(xmf) + " .xmf sidecar)";
}

OutputSize output_size(const scene::Scene& sc, const TimePlan& plan) {
  const bool beam = sc.model == scene::Model::Beam;
  const double steps = plan.output_steps(), nodes = sc.mesh.nodes;
  // Values per node and output step: the fields stored, and the sidecar's copies of its
  // arrays (/xdmf: the geometry and each field but the beam's deflection).
  double stored = beam ? 4.0 : 0.0, copied = beam ? 3.0 : 0.0, arrays = beam ? 1.0 : 0.0;
  for (const auto f : sc.output.fields) {
    const double n = f == scene::Field::R ? 9.0 : (f == scene::Field::deflection || f == scene::Field::slope ||
                                                   f == scene::Field::bending_moment || f == scene::Field::stretch ||
                                                   f == scene::Field::axial_force) ? 1.0 : 3.0;
    if (f == scene::Field::deflection) continue;  // the beam always writes it
    stored += n;
    copied += n;
    arrays += f == scene::Field::R ? 3.0 : 1.0;  // the rod's R: three director arrays
  }
  // Probe series, each at least a chunk of 8192 values (a point's three components share
  // one): time, sigma, the probes, per load its position (and the beam's deflection under it).
  const double scalars = 2.0 + static_cast<double>(sc.loads.size()) * (beam ? 2.0 : 1.0);
  double series = scalars * 8.0 * std::max(steps, 8192.0);
  for (const auto& pr : sc.output.probes)
    series += pr.type == scene::ProbeType::point ? 24.0 * std::max(steps, 8192.0 / 3.0) : 8.0 * std::max(steps, 8192.0);
  OutputSize o;
  // Each sidecar array of each step is a dataset of its own: about 400 bytes of HDF5
  // metadata; a rod's restart points keep two states of about 70 values per node; the mesh
  // (s, positions, segments) about 6 values per node.
  o.h5 = steps * (8.0 * nodes * (stored + copied) + 400.0 * arrays) + series +
         (beam ? 0.0 : 2.0 * 8.0 * 70.0 * nodes) + 8.0 * 6.0 * nodes;
  // The sidecar's text per step: the grids, their time and points, and one line per array.
  o.xmf = steps * ((sc.loads.empty() ? 600.0 : 1270.0) + 380.0 * arrays);
  return o;
}

void check_time_plan(const scene::Scene& sc, TimePlan& p, long max_steps) {
  if (!(p.dt > 0.0) || !std::isfinite(p.dt))
    scene::fail_at(sc, deciding_key(sc, joined(p.dt_keys, p.end_keys)),
                   "a time step that is a positive finite number of seconds", p.dt_text);
  if (!(p.t_end > 0.0) || !std::isfinite(p.t_end))
    scene::fail_at(sc, deciding_key(sc, joined(p.end_keys, p.dt_keys)),
                   "an end time that is a positive finite number of seconds", p.end_text);
  // The step count: a load's entry time, a given end time, or (a beam's dt from its modes)
  // the load's motion before the keys of dt.
  const bool end_first = p.entry_dominated || (!sc.time.end_auto && sc.time.dt_auto) || p.dt_from_modes;
  const std::string key =
      deciding_key(sc, end_first ? joined(p.end_keys, p.dt_keys) : joined(p.dt_keys, p.end_keys));
  const std::string found = count(p.steps) + " time steps of " + p.dt_text + " to " + p.end_text;
  if (!(p.steps <= kMaxGridSteps))
    scene::fail_at(sc, key,
                   "at most 2^32 = 4294967296 time steps (the most a double-precision time grid resolves: "
                   "--max-steps cannot raise it; docs/reliability.md \"Limits\")",
                   found);
  if (!(p.steps <= static_cast<double>(max_steps)))
    scene::fail_at(sc, key,
                   "at most " + std::to_string(max_steps) + " time steps (--max-steps N raises this limit" +
                       (max_steps == kDefaultMaxSteps ? ", default 10^7" : "") + ")",
                   found);
  p.grid = make_time_grid(0.0, p.t_end, p.dt,
                          sc.model == scene::Model::Beam ? beam::BeamSimulation::kGridJoin : 1e-6).grid;
}

MemoryPlan rod_memory(const scene::Scene& sc, const RodPathGuess& path) {
  MemoryPlan m;
  const double N = sc.mesh.nodes, n = owned_nodes(sc, path.ranks);
  const std::string ranks = ranks_text(path.ranks);
  m.keys = {mesh_key(sc)};
  const double replicated = rod::kReplicatedBytesPerNode * N;
  std::string tail = " + " + count(N) + " nodes x " + kb(rod::kReplicatedBytesPerNode) + " (states held on every rank) + " +
                     format_bytes(kProgramBytes) + " (program)";
  if (sc.continuation.enabled) {
    m.bytes = kProgramBytes + solver::continuation_bytes_per_node() * n + replicated;
    m.detail = mesh_text(sc) + " on " + ranks + ": " + count(n) + " nodes x " + kb(solver::continuation_bytes_per_node()) +
               " (continuation: Newton, LOCA, eigenvalues)" + tail;
    return m;
  }
  const int u3 = rod_unknowns_3d(sc), u = path.planar ? u3 / 2 : u3;
  std::string solver;
  const double factor = rod_solver_factor(sc, path.ranks, solver);
  const double stepper = factor * solver::time_step_bytes_per_node(u);
  const bool static_start = sc.initial_state.type == scene::InitialStateType::static_equilibrium;
  const bool arch = sc.initial_state.type == scene::InitialStateType::arch;
  const double stepping = stepper * n;
  // The static start is solved and freed before the stepper is built: the larger one counts.
  const double starting = static_start ? solver::static_start_bytes_per_node() * n
                          : arch       ? solver::continuation_bytes_per_node() * n
                                       : 0.0;
  m.bytes = kProgramBytes + std::max(stepping, starting) + replicated;
  const std::string stepping_text = count(n) + " nodes x " + kb(stepper) + " (time steps on the " +
                                    (path.planar ? "planar" : "3D") + " path, " + std::to_string(u) +
                                    " unknowns per node, linear solver " + solver + ")";
  std::string text;
  if (starting > stepping && static_start)
    text = count(n) + " nodes x " + kb(solver::static_start_bytes_per_node()) +
           " (the static initial state: the 3D static system and its block-tridiagonal LU; initial_state.type)";
  else if (starting > stepping)
    text = count(n) + " nodes x " + kb(solver::continuation_bytes_per_node()) + " (the arch formation; initial_state.type)";
  else
    text = stepping_text;
  m.detail = mesh_text(sc) + " on " + ranks + ": " + text + tail;
  if (u3 == 24) m.keys.push_back("scheme.rho_inf_space");
  return m;
}

MemoryPlan beam_memory(const scene::Scene& sc, int ranks) {
  MemoryPlan m;
  const double N = sc.mesh.nodes, n = owned_nodes(sc, ranks);
  // The deflection and the deflected shape (x, w, 0) are always written; slope and moment on
  // request.
  int components = 4;
  for (const auto f : sc.output.fields) components += f == scene::Field::deflection ? 0 : 1;
  const beam::BeamMemory b = beam::beam_memory(sc.beam.modes, static_cast<int>(sc.loads.size()), components);
  // The output steps the writer keeps until it flushes them (at most 64 MiB over all ranks,
  // this rank's share) and the step being written.
  const double kept = 64.0 * 1024.0 * 1024.0 * n / N + 8.0 * components * n;
  m.bytes = kProgramBytes + b.per_quadrature_node * N + b.per_output_node * n + b.fixed + kept;
  m.detail = mesh_text(sc) + " on " + ranks_text(ranks) + ": " + count(N) + " nodes x " + fmt(b.per_quadrature_node) +
             " bytes (quadrature, on every rank) + " + count(n) + " nodes x " + fmt(b.per_output_node) +
             " bytes (positions, output.fields, the modes at the node) + " + format_bytes(kept) +
             " (output steps kept until a flush) + " + format_bytes(b.fixed) + " (beam.modes = " +
             std::to_string(sc.beam.modes) + ": modal matrices) + " + format_bytes(kProgramBytes) + " (program)";
  m.keys = {mesh_key(sc), "beam.modes"};
  return m;
}

void check_memory(const scene::Scene& sc, const MemoryPlan& plan, const MemoryLimit& limit) {
  if (!(limit.bytes > 0.0) || plan.bytes <= limit.bytes) return;
  scene::fail_at(sc, deciding_key(sc, plan.keys),
                 "a run that fits the memory of one rank, at most " + format_bytes(limit.bytes) + " (" + limit.source +
                     (limit.source.rfind("--max-memory", 0) == 0 ? "" : "; --max-memory sets the limit") + ")",
                 "an estimated " + format_bytes(plan.bytes) + " per rank: " + plan.detail +
                     " (a coarser mesh or more ranks need less; docs/reliability.md \"Limits\")");
}

void check_counters(const scene::Scene& sc, const RodPathGuess& path) {
  const double N = sc.mesh.nodes, n = owned_nodes(sc, path.ranks);
  const double u3 = rod_unknowns_3d(sc);
  const double int_max = static_cast<double>(INT_MAX);
  if (n * u3 > int_max)
    scene::fail_at(sc, deciding_key(sc, {mesh_key(sc)}),
                   "at most " + count(std::floor(int_max / u3)) + " nodes per rank (" + fmt(u3) +
                       " unknowns per node; a rank's unknowns are counted in 32-bit integers)",
                   count(n) + " nodes per rank: " + mesh_text(sc));
  const double packed = static_cast<double>(rod::kPackedNodeValues);
  if (N * packed > int_max)
    scene::fail_at(sc, deciding_key(sc, {mesh_key(sc)}),
                   "at most " + count(std::floor(int_max / packed)) + " nodes (a gathered state of " + fmt(packed) +
                       " values per node is counted in a 32-bit MPI count)",
                   mesh_text(sc));
}

void check_properties(const scene::Scene& sc) {
  const bool beam = sc.model == scene::Model::Beam;
  const std::string model = beam ? "beam" : "rod";
  const auto& sec = beam ? sc.beam.section : sc.rod.section;
  const double E = beam ? sc.beam.youngs_modulus : sc.rod.youngs_modulus;
  const double rho = beam ? sc.beam.density : sc.rod.density;
  auto usable = [](double x) { return x > 0.0 && std::isfinite(x); };
  struct Quantity {
    const char* what;
    double value;
    std::vector<std::string> keys;
    std::string parts;
  };
  std::vector<Quantity> q = {
      {"the section's area A [m^2]", sec.area, {model + ".section"}, "from the dimensions of " + model + ".section"},
      {"the section's second moment I [m^4]", beam ? sec.I1 : std::min(sec.I1, sec.I2), {model + ".section"},
       "from the dimensions of " + model + ".section"},
      {"the mass per length rho A [kg/m]", rho * sec.area, {model + ".density", model + ".section"},
       model + ".density = " + fmt(rho) + " kg/m^3 x A = " + fmt(sec.area) + " m^2"},
      {"the bending stiffness E I [N m^2]", E * (beam ? sec.I1 : std::min(sec.I1, sec.I2)),
       {model + ".youngs_modulus", model + ".section"},
       model + ".youngs_modulus = " + fmt(E) + " Pa x I = " + fmt(beam ? sec.I1 : std::min(sec.I1, sec.I2)) + " m^4"}};
  if (!beam)
    q.push_back({"the torsional stiffness G J [N m^2]", sc.rod.shear_modulus * sec.J,
                 {"rod.shear_modulus", "rod.poisson_ratio", "rod.youngs_modulus", "rod.section"},
                 "G = " + fmt(sc.rod.shear_modulus) + " Pa x J = " + fmt(sec.J) + " m^4"});
  for (const auto& x : q)
    if (!usable(x.value))
      scene::fail_at(sc, deciding_key(sc, x.keys), std::string(x.what) + " that is a positive finite number",
                     fmt(x.value) + " (" + x.parts + ": the product leaves double precision)");
  // Both models are theories of slender structures: a section as wide as the structure is long
  // is no beam and no rod.
  const double width = std::sqrt(sec.area), L = sc.length();
  if (!(width <= L))
    scene::fail_at(sc, deciding_key(sc, {model + ".section", model + ".length"}),
                   "a slender " + model + ": a section smaller than the length, sqrt(A) <= " + model + ".length = " +
                       fmt(L) + " m",
                   "sqrt(A) = " + fmt(width) + " m (" + model + ".section)");
}

void check_load_speeds(const scene::Scene& sc) {
  for (const auto& l : sc.loads) {
    const double te = l.exit_time(sc.length());
    const double at_exit = std::isfinite(te) ? std::abs(l.velocity(te)) : 0.0;
    const double fastest = std::max(l.speed, at_exit);
    if (fastest <= kSpeedOfLight) continue;
    const std::string k = "loads." + l.name + ".";
    const bool at_entry = l.speed > kSpeedOfLight;
    scene::fail_at(sc, deciding_key(sc, at_entry ? std::vector<std::string>{k + "speed", k + "acceleration"}
                                                 : std::vector<std::string>{k + "acceleration", k + "speed"}),
                   "a load slower than light while it is on the " + std::string(sc.model == scene::Model::Beam ? "beam" : "rod") +
                       ", at most 299792458 m/s (docs/reliability.md \"Limits\")",
                   at_entry ? fmt(l.speed) + " m/s at entry (" + k + "speed)"
                            : fmt(fastest) + " m/s when it reaches the far end (" + k + "speed = " + fmt(l.speed) +
                                  " m/s, " + k + "acceleration = " + fmt(l.acceleration) + " m/s^2)");
  }
}

LoadRatio load_ratio(const scene::Scene& sc) {
  const bool beam = sc.model == scene::Model::Beam;
  const std::string model = beam ? "beam" : "rod";
  const double L = sc.length();
  const auto& sec = beam ? sc.beam.section : sc.rod.section;
  LoadRatio r;
  r.EI = (beam ? sc.beam.youngs_modulus : sc.rod.youngs_modulus) * (beam ? sec.I1 : std::min(sec.I1, sec.I2));
  r.W = (beam ? sc.beam.density : sc.rod.density) * sec.area * sc.gravity * L;
  r.what = "the weight of the " + model + " (gravity, " + model + ".density)";
  r.keys = {"gravity", model + ".density"};
  for (const auto& l : sc.loads) {
    const double f = l.force.norm();
    if (f > r.W || std::isnan(f)) {
      r.W = f;
      const std::string k = load_magnitude_key(sc, l);
      r.what = "load '" + l.name + "' (" + k + ")";
      r.keys = {k};
    }
  }
  if (!beam)
    for (const auto* e : {&sc.left, &sc.right})
      if (e->type == scene::EndType::roller && std::abs(e->axial_force) > r.W) {
        r.W = std::abs(e->axial_force);
        const std::string k = std::string("ends.") + (e == &sc.left ? "left" : "right") + ".force";
        r.what = k;
        r.keys = {k};
      }
  r.ratio = r.W / r.EI * L * L;
  return r;
}

void check_load_ratio(const scene::Scene& sc) {
  const LoadRatio r = load_ratio(sc);
  if (r.ratio <= kMaxLoadRatio) return;
  const bool beam = sc.model == scene::Model::Beam;
  const std::string model = beam ? "beam" : "rod";
  const double L = sc.length();
  const auto& sec = beam ? sc.beam.section : sc.rod.section;
  const double E = beam ? sc.beam.youngs_modulus : sc.rod.youngs_modulus;
  const double I = beam ? sec.I1 : std::min(sec.I1, sec.I2);
  // When the structure cannot even carry its own weight, the stiffness (or gravity, density)
  // is what is extreme; otherwise the load.
  const double own = (beam ? sc.beam.density : sc.rod.density) * sec.area * sc.gravity * L / r.EI * L * L;
  const std::vector<std::string> stiffness = {model + ".youngs_modulus", model + ".section"};
  const std::vector<std::string> keys = own > kMaxLoadRatio || std::isnan(own)
                                            ? joined(joined(stiffness, {"gravity", model + ".density"}), r.keys)
                                            : joined(r.keys, stiffness);
  scene::fail_at(sc, deciding_key(sc, keys),
                 "a load the bending stiffness can carry in double precision: W L^2 / (E I) <= 4.5e15 (beyond it E I "
                 "kappa is below the rounding of the load's moment; docs/reliability.md \"Limits\")",
                 "W L^2 / (E I) = " + fmt(r.ratio) + " with W = " + fmt(r.W) + " N from " + r.what + ", L = " + fmt(L) +
                     " m (" + model + ".length), E I = " + fmt(r.EI) + " N m^2 (" + model + ".youngs_modulus = " +
                     fmt(E) + " Pa, I = " + fmt(I) + " m^4 of " + model + ".section): use a smaller load or a stiffer " +
                     model);
}

}  // namespace traverse::setup

namespace traverse::setup {

namespace {

// Largest static deflection and slope of a uniform beam under a uniform load q, in units of
// q L^4 / (E I) and q L^3 / (E I) (the closed forms of the four supports).
// Largest static deflection of a uniform beam under a point load P at its worst place, in
// units of P L^3 / (E I).
double point_load_coefficient(scene::Supports s) {
  using S = scene::Supports;
  switch (s) {
    case S::simply_supported: return 1.0 / 48.0;
    case S::clamped_free: return 1.0 / 3.0;
    case S::clamped_clamped: return 1.0 / 192.0;
    case S::clamped_pinned: return 1.0 / (48.0 * std::sqrt(5.0));
    default: throw std::logic_error("point_load_coefficient: unknown supports");
  }
}

void uniform_load_coefficients(scene::Supports s, double& deflection, double& slope) {
  using S = scene::Supports;
  switch (s) {
    case S::simply_supported: deflection = 5.0 / 384.0, slope = 1.0 / 24.0; return;
    case S::clamped_free: deflection = 1.0 / 8.0, slope = 1.0 / 6.0; return;
    case S::clamped_clamped: deflection = 1.0 / 384.0, slope = 1.0 / (72.0 * std::sqrt(3.0)); return;
    case S::clamped_pinned: deflection = (39.0 + 55.0 * std::sqrt(33.0)) / 65536.0, slope = 1.0 / 48.0; return;
    default: throw std::logic_error("uniform_load_coefficients: unknown supports");
  }
}

std::string stiffness_text(const scene::Scene& sc) {
  const auto& b = sc.beam;
  return "E I = " + fmt(b.youngs_modulus * b.section.I1) + " N m^2 (beam.youngs_modulus = " + fmt(b.youngs_modulus) +
         " Pa, I = " + fmt(b.section.I1) + " m^4 of beam.section)";
}

}  // namespace

void check_beam_static_deflection(const scene::Scene& sc) {
  const auto& b = sc.beam;
  const double L = b.length, EI = b.youngs_modulus * b.section.I1;
  const double q = b.density * b.section.area * sc.gravity;
  double cw = 0.0, cs = 0.0;
  uniform_load_coefficients(b.supports, cw, cs);
  const double w = cw * q * std::pow(L, 4) / EI, slope = cs * q * std::pow(L, 3) / EI;
  if (w <= kMaxBeamDeflectionRatio * L && slope <= kMaxBeamSlope) return;
  const std::vector<std::string> keys = {"beam.youngs_modulus", "beam.section", "beam.density", "gravity",
                                         "beam.length"};
  scene::fail_at(sc, deciding_key(sc, keys),
                 "a beam whose static deflection under its own weight stays in the small-deflection range of the "
                 "beam model, |w| <= L / 10 = " + fmt(kMaxBeamDeflectionRatio * L) +
                     " m and |w_x| <= 0.2 (docs/beam.md \"Validity\"; is beam.youngs_modulus in Pa?)",
                 "|w| = " + fmt(w) + " m, |w_x| = " + fmt(slope) + " under q = rho A g = " + fmt(q) + " N/m with " +
                     stiffness_text(sc) + ", beam.length = " + fmt(L) + " m");
}

BeamDeflectionCheck::BeamDeflectionCheck(const scene::Scene& sc, const beam::ModeSet& modes) : sc_(sc) {
  const int n = 8 * std::max(1, sc.beam.modes);
  for (int i = 0; i <= n; ++i) points_.push_back(sc.beam.length * i / n);
  const Eigen::Index m = modes.size();
  phi_.resize(static_cast<Eigen::Index>(points_.size()), m);
  dphi_.resize(phi_.rows(), m);
  VecX phi(m), dphi(m), ddphi(m);
  for (Eigen::Index i = 0; i < phi_.rows(); ++i) {
    modes.evaluate(points_[static_cast<size_t>(i)], phi, dphi, ddphi);
    phi_.row(i) = phi.transpose();
    dphi_.row(i) = dphi.transpose();
  }
  const auto& b = sc.beam;
  const double L = b.length, EI = b.youngs_modulus * b.section.I1;
  double cw = 0.0, cs = 0.0;
  uniform_load_coefficients(b.supports, cw, cs);
  double P = 0.0;
  for (const auto& l : sc.loads) P += l.force.norm();
  static_bound_ = cw * b.density * b.section.area * sc.gravity * std::pow(L, 4) / EI +
                  point_load_coefficient(b.supports) * P * std::pow(L, 3) / EI;
}

std::string BeamDeflectionCheck::why(double t, const VecX& Y) const {
  const VecX w = phi_ * Y, slope = dphi_ * Y;
  // The first largest of each (a NaN counts as largest: it is outside any range).
  auto extreme = [&](const VecX& v) {
    Extreme e;
    for (Eigen::Index i = 0; i < v.size(); ++i)
      if (!(std::abs(v(i)) <= std::abs(e.value))) e = {v(i), points_[static_cast<size_t>(i)]};
    return e;
  };
  return message(t, extreme(w), extreme(slope));
}

std::string BeamDeflectionCheck::message(double t, const Extreme& w, const Extreme& slope) const {
  const double L = sc_.beam.length;
  const bool deflection_out = !(std::abs(w.value) <= kMaxBeamDeflectionRatio * L);
  const bool slope_out = !(std::abs(slope.value) <= kMaxBeamSlope);
  if (!deflection_out && !slope_out) return "";
  if (std::abs(w.value) > 10.0 * static_bound_)
    return "beam solver: the deflection grew to " + fmt(std::abs(w.value)) + " m at t = " + fmt(t) +
           " s, more than 10 times the largest static deflection the loads can cause (" + fmt(static_bound_) +
           " m): the time integration is unstable; reduce time.dt or use beam.integrator: newmark";
  const LoadRatio r = load_ratio(sc_);
  std::string what = deflection_out ? "|w| = " + fmt(std::abs(w.value)) + " m at x = " + fmt(w.at) +
                                          " m is more than L / 10 = " + fmt(kMaxBeamDeflectionRatio * L) +
                                          " m (beam.length = " + fmt(L) + " m)"
                                    : "";
  if (slope_out)
    what += std::string(deflection_out ? "; " : "") + "|w_x| = " + fmt(std::abs(slope.value)) + " at x = " +
            fmt(slope.at) + " m is more than " + fmt(kMaxBeamSlope);
  return "beam model: the deflection leaves the small-deflection range of the beam at t = " + fmt(t) + " s: " + what +
         ". Decided by the largest load, " + r.what + " = " + fmt(r.W) + " N, against " + stiffness_text(sc_) +
         " (docs/beam.md \"Validity\"): use a smaller load or a stiffer beam, or the rod model for large deflections";
}

std::vector<std::string> under_resolved_load_warnings(const scene::Scene& sc, const TimeGrid& g) {
  std::vector<std::string> out;
  const double ds = sc.mesh.ds;
  for (const auto& l : sc.loads) {
    const double t_leave = std::min(g.t_end, l.exit_time(sc.rod.length));
    const double v = std::max(std::abs(l.velocity(l.entry_time)), std::abs(l.velocity(std::max(l.entry_time, t_leave))));
    if (!(v > 0.0 && g.dt * v > ds * (1.0 + 1e-9))) continue;
    char cells[32];
    std::snprintf(cells, sizeof cells, "%.3g", g.dt * v / ds);
    out.push_back(sc.file + ": time.dt = " + fmt(g.dt) + " s moves load '" + l.name + "' (up to " + fmt(v) + " m/s) " +
                  cells + " cells per step (mesh.ds = " + fmt(ds) +
                  " m): its path is under-resolved in time (time.dt: auto gives ds / v)");
  }
  return out;
}

std::vector<std::string> idle_load_warnings(const scene::Scene& sc) {
  std::vector<std::string> out;
  const bool fixed_end = !sc.time.end_auto && !sc.time.end_at_event;
  for (const auto& l : sc.loads) {
    const std::string k = "loads." + l.name;
    if (fixed_end && !l.coupled && l.entry_time >= sc.time.end)
      out.push_back(sc.file + ": " + k + ".entry_time: load '" + l.name + "' can do nothing: it enters at t = " +
                    fmt(l.entry_time) + " s, at or after time.end = " + fmt(sc.time.end) + " s");
    if (!(l.force.norm() == 0.0) || l.drive != 0.0) continue;
    const bool weight = !sc.has(k + ".force") && !sc.has(k + ".force_vector");
    std::string why;
    if (weight && sc.gravity == 0.0)
      why = "its force is the weight M g of " + (sc.has(k + ".mass") ? k + ".mass" : k + ".mass_fraction") +
            ", and gravity = 0";
    else
      why = "its force is zero (" + load_magnitude_key(sc, l) + ")";
    out.push_back(sc.file + ": " + k + ": load '" + l.name + "' can do nothing: " + why +
                  (l.inertia || l.coupled ? "; a mass that weighs nothing only rides along" : "") +
                  " (set gravity, or give the load a force)");
  }
  return out;
}

std::vector<std::string> adaptive_warnings(const scene::Scene& sc) {
  std::vector<std::string> out;
  if (sc.model != scene::Model::Rod || !sc.time.adaptive.enabled || sc.loads.empty()) return out;
  const bool arch = sc.initial_state.type == scene::InitialStateType::arch;
  const auto steady_prescribed = [](const scene::MovingLoadSpec& l) {
    return (l.type == scene::LoadType::moving_force || l.type == scene::LoadType::moving_mass) && l.acceleration == 0.0;
  };
  const auto free_coupled = [](const scene::MovingLoadSpec& l) { return l.coupled && l.friction == 0.0; };
  const std::string head = sc.file + ": time.adaptive: ";
  if (!arch && std::all_of(sc.loads.begin(), sc.loads.end(), steady_prescribed))
    out.push_back(head +
                  "loads at constant speed on a rod not formed into an arch (no snap-through for the steps to follow): "
                  "on the hanging cables fixed steps reach the same error for less CPU; consider time.dt = ds / (4 v) "
                  "without time.adaptive (docs/adaptive.md, \"Work and precision\")");
  else if (std::all_of(sc.loads.begin(), sc.loads.end(), free_coupled))
    out.push_back(head +
                  "a coupled mass without friction (it cannot stick, no short violent phase for the steps to follow): "
                  "on the bead and the inspection robot fixed steps reach the same error for 1.3 to 2.3 times less CPU; "
                  "consider a fixed time.dt (docs/adaptive.md, \"Work and precision\")");
  return out;
}

}  // namespace traverse::setup

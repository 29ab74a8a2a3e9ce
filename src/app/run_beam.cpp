// A beam run in stages: the problem (beam_problem), the outputs (BeamOutputs), the restart
// replay check (BeamReplay), the observer of each output step (BeamObserver), the report.
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "interrupt.hpp"
#include "progress.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "traverse/beam/beam_simulation.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/version.hpp"

namespace traverse::app {

namespace {

beam::MovingLoad moving_load(const scene::MovingLoadSpec& l) {
  beam::MovingLoad m;
  m.kind = l.inertia ? beam::LoadKind::Mass : beam::LoadKind::Force;
  m.mass = l.mass;
  m.force = l.force.y();  // vertical, positive up (validated: no other components)
  m.entry = l.entry == scene::Entry::left ? beam::BeamEnd::Left : beam::BeamEnd::Right;
  m.direction = l.direction();
  m.speed = l.speed;
  m.acceleration = l.acceleration;
  m.entry_time = l.entry_time;
  m.start = l.start;
  return m;
}

/// Stage 1: the beam problem of a scene on the time grid of its checked run plan
/// (run_limits.hpp: dt auto is a twentieth of the highest mode's period, at most the time a
/// load needs to cross one mesh cell; end auto is when the last load leaves).
beam::BeamProblem beam_problem(const scene::Scene& sc, const TimeGrid& grid) {
  const auto& b = sc.beam;
  beam::BeamProblem p;
  p.length = b.length;
  p.EI = b.youngs_modulus * b.section.I1;
  p.rhoA = b.density * b.section.area;
  p.support = beam_support(b.supports);
  p.n_modes = b.modes;
  p.quadrature_nodes.resize(static_cast<size_t>(sc.mesh.nodes));
  for (int j = 0; j < sc.mesh.nodes; ++j) p.quadrature_nodes[static_cast<size_t>(j)] = j * sc.mesh.ds;
  p.quadrature_nodes.back() = b.length;
  p.gauss_points = b.quadrature_points;
  p.gravity = sc.gravity;
  p.self_weight = true;
  p.initial_state = beam::InitialState::Static;
  for (const auto& l : sc.loads) p.loads.push_back(moving_load(l));
  p.t_start = grid.t_start;
  p.t_end = grid.t_end;
  p.dt = grid.dt;
  p.integrator = b.integrator == scene::BeamIntegrator::newmark ? beam::Integrator::Newmark : beam::Integrator::RK4;
  p.output_every = sc.output.every;
  return p;
}

/// Stage 2: the outputs of a beam run: the probes (deflections, each load's position and the
/// deflection under it) and the fields (the deflection and the deflected shape (x, w, 0)
/// always; slope and bending moment on request) on this rank's contiguous range of nodes (the
/// beam itself is solved, replicated, on every rank: it is a small dense system).
class BeamOutputs {
 public:
  BeamOutputs(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes, MPI_Comm comm);
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const;
  const output::NodeLayout& layout() const { return layout_; }
  void declare(output::Writer& w) const;
  /// Evaluates every output at a snapshot (probe values are kept for the replay check).
  void evaluate(const beam::BeamSnapshot& s);
  const std::vector<std::vector<double>>& probes() const { return probes_; }
  void write(output::Writer& w, double t) const;

 private:
  const scene::Scene& sc_;
  double EI_;
  output::NodeLayout layout_;
  bool want_slope_ = false, want_moment_ = false;
  std::vector<VecX> phi_, dphi_, ddphi_;  ///< the modes at the output nodes, evaluated once
  std::vector<std::vector<double>> probes_, fields_;
  std::vector<double> sigma_;
};

BeamOutputs::BeamOutputs(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes, MPI_Comm comm)
    : sc_(sc), EI_(p.EI) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const size_t n_nodes = static_cast<size_t>(sc.mesh.nodes);
  layout_.global_count = n_nodes;
  layout_.first = n_nodes * static_cast<size_t>(rank) / static_cast<size_t>(ranks);
  layout_.count = n_nodes * static_cast<size_t>(rank + 1) / static_cast<size_t>(ranks) - layout_.first;
  for (size_t k = 0; k < layout_.count; ++k) layout_.s.push_back(p.quadrature_nodes[layout_.first + k]);
  for (const auto f : sc.output.fields) {
    switch (f) {
      case scene::Field::deflection: break;  // always written
      case scene::Field::slope: want_slope_ = true; break;
      case scene::Field::bending_moment: want_moment_ = true; break;
      default: throw std::logic_error("run_beam: a rod field in a beam scene");
    }
  }
  const Eigen::Index n = modes.size();
  phi_.assign(layout_.count, VecX(n));
  dphi_.assign(layout_.count, VecX(n));
  ddphi_.assign(layout_.count, VecX(n));
  for (size_t j = 0; j < layout_.count; ++j) modes.evaluate(layout_.s[j], phi_[j], dphi_[j], ddphi_[j]);
  probes_.assign(sc.output.probes.size() + 2 * sc.loads.size(), std::vector<double>(1));
  fields_.emplace_back(layout_.count);
  fields_.emplace_back(3 * layout_.count);
  if (want_slope_) fields_.emplace_back(layout_.count);
  if (want_moment_) fields_.emplace_back(layout_.count);
  sigma_.assign(std::max<size_t>(1, sc.loads.size()), std::numeric_limits<double>::quiet_NaN());
}

std::vector<std::string> BeamOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const auto& l : sc_.loads) {
    names.push_back(l.name + "_position");
    names.push_back(l.name + "_deflection");
  }
  return names;
}

std::vector<std::string> BeamOutputs::field_names() const {
  std::vector<std::string> names{"deflection", "position"};  // always: the sidecar shows the deflected beam
  if (want_slope_) names.push_back("slope");
  if (want_moment_) names.push_back("bending_moment");
  return names;
}

void BeamOutputs::declare(output::Writer& w) const {
  for (const auto& pr : sc_.output.probes)
    w.add_probe({pr.name, 1, "m", "transverse deflection w (positive up, +j) at x = " + scene::format_number(pr.at) + " m",
                 {}});
  for (const auto& l : sc_.loads) {
    w.add_probe({l.name + "_position", 1, "m", "position x(t) of load '" + l.name + "' along the beam", {}});
    w.add_probe({l.name + "_deflection", 1, "m",
                 "deflection w(x(t), t) under load '" + l.name + "' (NaN while it is off the beam)", {}});
  }
  w.add_field({"deflection", 1, "m", "transverse deflection w (positive up, +j)", {"w"}, false, false});
  w.add_field({"position", 3, "m", "deformed position (x, w, 0): the beam along x, w along y", {"x", "y", "z"}, true});
  if (want_slope_) w.add_field({"slope", 1, "1", "slope dw/dx", {"w_x"}, false});
  if (want_moment_) w.add_field({"bending_moment", 1, "N m", "bending moment E I d2w/dx2", {"M"}, false});
}

void BeamOutputs::evaluate(const beam::BeamSnapshot& s) {
  size_t k = 0;
  for (const auto& pr : sc_.output.probes) probes_[k++][0] = s.deflection(pr.at);
  for (size_t i = 0; i < sc_.loads.size(); ++i) {
    sigma_[i] = s.load_position(i);
    probes_[k++][0] = s.load_position(i);
    probes_[k++][0] = s.load_deflection(i);
  }
  auto& w = fields_[0];
  auto& pos = fields_[1];
  for (size_t j = 0; j < layout_.count; ++j) {
    w[j] = phi_[j].dot(s.Y);
    pos[3 * j] = layout_.s[j];
    pos[3 * j + 1] = w[j];
    pos[3 * j + 2] = 0.0;
  }
  size_t f = 2;
  if (want_slope_) {
    auto& v = fields_[f++];
    for (size_t j = 0; j < layout_.count; ++j) v[j] = dphi_[j].dot(s.Y);
  }
  if (want_moment_) {
    auto& v = fields_[f++];
    for (size_t j = 0; j < layout_.count; ++j) v[j] = EI_ * ddphi_[j].dot(s.Y);
  }
}

void BeamOutputs::write(output::Writer& w, double t) const {
  std::vector<output::DoubleView> views(fields_.begin(), fields_.end());
  w.write_step(t, sigma_, probes_, views);
}

/// Restart of a beam run (docs/reliability.md): the beam is re-integrated from t = 0
/// (BeamSimulation cannot be set to a stored state); the output steps the file already holds
/// are checked against the replay (same values to round-off, else the scene or the program
/// differ), then rewritten, and the run continues.
class BeamReplay {
 public:
  /// Reads the restart source's output steps and moves it aside (opt.restart only).
  BeamReplay(const RunOptions& opt, const std::vector<std::string>& probe_names, const std::vector<std::string>& fields,
             MPI_Comm comm);
  std::size_t kept() const { return kept_; }
  /// Throws UsageError when output step o (< kept()) of the replay differs from the file.
  void check(std::size_t o, double t, const std::vector<std::vector<double>>& probes) const;

 private:
  const RunOptions& opt_;
  std::vector<std::string> names_;
  std::size_t kept_ = 0;
  std::vector<double> time_;
  std::vector<output::Series> probes_;
};

BeamReplay::BeamReplay(const RunOptions& opt, const std::vector<std::string>& probe_names,
                       const std::vector<std::string>& fields, MPI_Comm comm)
    : opt_(opt), names_(probe_names) {
  if (!opt.restart) return;
  const std::string source = output::restart_source(opt.output);
  output::check_restart_outputs(source, probe_names, fields);
  try {
    output::Reader r(source);
    kept_ = r.steps_written();
    time_ = r.time();
    for (const auto& n : probe_names) probes_.push_back(r.probe(n));
  } catch (const output::OutputError& e) {
    throw UsageError{"--restart: cannot read " + source + " (" + e.what() + ")"};
  }
  output::move_aside_for_restart(opt.output, comm);
}

void BeamReplay::check(std::size_t o, double t, const std::vector<std::vector<double>>& probes) const {
  auto differs = [](double a, double b) {
    return !(a == b || (std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)));
  };
  std::string bad;
  if (differs(time_[o], t)) bad = "time " + scene::format_number(time_[o]) + " vs " + scene::format_number(t);
  for (size_t q = 0; bad.empty() && q < probes.size(); ++q)
    if (differs(probes_[q].values[o], probes[q][0]))
      bad = "probe " + names_[q] + " = " + scene::format_number(probes_[q].values[o]) + " vs " +
            scene::format_number(probes[q][0]);
  if (!bad.empty())
    throw UsageError{"--restart " + opt_.output + ": re-integrating the beam does not reproduce output step " +
                     std::to_string(o) + " (" + bad + "); the scene or the program differ from the run being restarted"};
}

/// What a beam run does at each output step: check the state, evaluate and write the
/// outputs (checked against the file on a restart), keep the restart arrays, stop on a signal.
class BeamObserver {
 public:
  BeamObserver(const scene::Scene& sc, const beam::BeamProblem& p, const beam::BeamSimulation& sim, BeamOutputs& out,
               const BeamReplay& replay, output::Writer& w, Progress& progress, const RunOptions& opt, MPI_Comm comm)
      : sc_(sc), p_(p), sim_(sim), out_(out), replay_(replay), w_(w), progress_(progress), opt_(opt), comm_(comm) {}
  void operator()(const beam::BeamSnapshot& s);
  long outputs() const { return outputs_; }
  /// /restart of a beam run: the modal state (Y then Y') and [t, steps taken, output steps]
  /// of the last output step, written when the run stops (a restart re-integrates from t = 0
  /// and needs only the output steps; these arrays document the state).
  void store_restart();

 private:
  const scene::Scene& sc_;
  const beam::BeamProblem& p_;
  const beam::BeamSimulation& sim_;
  BeamOutputs& out_;
  const BeamReplay& replay_;
  output::Writer& w_;
  Progress& progress_;
  const RunOptions& opt_;
  MPI_Comm comm_;
  long outputs_ = 0;
  std::vector<double> restart_state_, restart_meta_;
};

void BeamObserver::store_restart() {
  if (restart_meta_.empty()) return;
  w_.write_restart(restart_meta_[0],
                   {{"modal_state", output::RestartDistribution::replicated, 1, output::DoubleView(restart_state_)},
                    {"meta", output::RestartDistribution::replicated, 1, output::DoubleView(restart_meta_)}});
}

void BeamObserver::operator()(const beam::BeamSnapshot& s) {
  if (!s.Y.allFinite() || !s.Ydot.allFinite()) {
    std::ostringstream os;
    os << "beam solver: the modal state is not finite at t = " << s.t << " s (after " << sim_.steps_taken()
       << " steps of dt = " << p_.dt << " s with " << scene::name_of(sc_.beam.integrator)
       << "); reduce time.dt or use beam.integrator: newmark";
    throw NumericsError(os.str());
  }
  out_.evaluate(s);
  const auto o = static_cast<std::size_t>(outputs_);
  if (o < replay_.kept()) replay_.check(o, s.t, out_.probes());
  out_.write(w_, s.t);
  ++outputs_;
  if (opt_.restart && static_cast<std::size_t>(outputs_) == replay_.kept()) output::remove_restart_source(opt_.output, comm_);
  restart_state_.assign(s.Y.data(), s.Y.data() + s.Y.size());
  restart_state_.insert(restart_state_.end(), s.Ydot.data(), s.Ydot.data() + s.Ydot.size());
  restart_meta_ = {s.t, static_cast<double>(sim_.steps_taken()), static_cast<double>(outputs_)};
  progress_.update(s.t, sim_.steps_taken());
  if (s.t >= p_.t_end) return;
  if (const int sig = interrupt_requested(comm_)) {
    progress_.done();
    std::ostringstream os;
    os.precision(12);
    os << "interrupted at t = " << s.t << " s (time step " << sim_.steps_taken() << ", " << signal_name(sig) << "); "
       << w_.steps_written() << " output steps written; continue with traverse run --restart " << opt_.output;
    store_restart();
    w_.fail(os.str());
    throw Interrupted(sig, opt_.output, os.str(), os.str());
  }
}

}  // namespace

void run_beam(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  // The limits (steps, memory, load ratio: run_limits.hpp) before anything of the beam's size
  // is allocated; the time grid (dt, end) comes from the same plan.
  const TimeGrid grid = check_beam_run(sc, opt.limits, comm).grid;
  const beam::BeamProblem p = beam_problem(sc, grid);
  if (coupled_load(sc)) {
    run_beam_coupled(sc, p, opt, comm);
    return;
  }
  beam::BeamSimulation sim(p);
  BeamOutputs outputs(sc, p, sim.modes(), comm);
  const BeamReplay replay(opt, outputs.probe_names(), outputs.field_names(), comm);
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "beam"};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(),
                        std::max<size_t>(1, sc.loads.size()));
  outputs.declare(writer);
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", p.t_start, p.t_end);
  BeamObserver observe(sc, p, sim, outputs, replay, writer, progress, opt, comm);
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    sim.run([&](const beam::BeamSnapshot& s) { observe(s); });
  } catch (const NumericsError& e) {
    progress.done();
    observe.store_restart();
    writer.fail(e.what());
    throw;
  }
  progress.done();
  observe.store_restart();
  writer.finish();
  if (opt.restart && static_cast<std::size_t>(observe.outputs()) < replay.kept())
    output::remove_restart_source(opt.output, comm);  // a shorter run
  if (rank == 0 && !opt.quiet)
    std::printf("beam scene '%s': %d modes, %ld steps of dt = %.4g s (%s) to t = %.6g s; %ld output steps -> %s; "
                "time stepping %.3f s (wall, output included)\n",
                sc.file.c_str(), sc.beam.modes, sim.steps_taken(), p.dt, scene::name_of(sc.beam.integrator).c_str(),
                p.t_end, observe.outputs(), opt.output.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
}

}  // namespace traverse::app

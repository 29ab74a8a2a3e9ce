// A beam run with a coupled mass (issue 17, docs/beam.md "Coupled mass"): the mass's position
// is an unknown of the beam's ODE (beam::CoupledMassBeam). Outputs: the deflection probes and
// fields of a beam run, the mass's probes (position, speed, fixed-frame position and velocity,
// contact forces), the energies, and the events table (the run ends at the first event).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "interrupt.hpp"
#include "progress.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "traverse/beam/coupled_mass_beam.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/version.hpp"

namespace traverse::app {

namespace {

beam::CoupledMass coupled_mass(const scene::MovingLoadSpec& l) {
  beam::CoupledMass m;
  m.mass = l.mass;
  m.start = l.start;
  m.velocity = l.initial_velocity();
  m.drive = l.drive;
  m.resistance = l.resistance;
  m.unilateral = l.contact == scene::Contact::unilateral;
  return m;
}

/// The outputs of a coupled beam run: names, declarations, values at a state.
class CoupledOutputs {
 public:
  CoupledOutputs(const scene::Scene& sc, const scene::MovingLoadSpec& load, const beam::BeamProblem& p,
                 const beam::ModeSet& modes, MPI_Comm comm);
  const output::NodeLayout& layout() const { return layout_; }
  void declare(output::Writer& w) const;
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const;
  void evaluate(const beam::CoupledMassBeam& s);
  const std::vector<std::vector<double>>& probes() const { return probes_; }
  void write(output::Writer& w, double t) const {
    std::vector<output::DoubleView> views(fields_.begin(), fields_.end());
    w.write_step(t, sigma_, probes_, views);
  }

 private:
  const scene::Scene& sc_;
  const scene::MovingLoadSpec& load_;
  double EI_;
  output::NodeLayout layout_;
  bool want_slope_ = false, want_moment_ = false;
  std::vector<VecX> phi_, dphi_, ddphi_;
  std::vector<std::vector<double>> probes_, fields_;
  std::vector<double> sigma_{0.0};
};

CoupledOutputs::CoupledOutputs(const scene::Scene& sc, const scene::MovingLoadSpec& load, const beam::BeamProblem& p,
                               const beam::ModeSet& modes, MPI_Comm comm)
    : sc_(sc), load_(load), EI_(p.EI) {
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
      case scene::Field::deflection: break;
      case scene::Field::slope: want_slope_ = true; break;
      case scene::Field::bending_moment: want_moment_ = true; break;
      default: throw std::logic_error("run_beam_coupled: a rod field in a beam scene");
    }
  }
  const Eigen::Index n = modes.size();
  phi_.assign(layout_.count, VecX(n));
  dphi_.assign(layout_.count, VecX(n));
  ddphi_.assign(layout_.count, VecX(n));
  for (size_t j = 0; j < layout_.count; ++j) modes.evaluate(layout_.s[j], phi_[j], dphi_[j], ddphi_[j]);
  fields_.emplace_back(layout_.count);
  fields_.emplace_back(3 * layout_.count);
  if (want_slope_) fields_.emplace_back(layout_.count);
  if (want_moment_) fields_.emplace_back(layout_.count);
}

const char* const kEnergyProbes[] = {"energy_beam_kinetic", "energy_beam_elastic", "energy_beam_gravity",
                                      "energy_mass_kinetic", "energy_mass_gravity", "work_drive",
                                      "work_dissipated", "energy_balance"};

std::vector<std::string> CoupledOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const char* q : {"_position", "_speed", "_deflection", "_fixed_position", "_fixed_velocity", "_normal_force",
                        "_tangential_force"})
    names.push_back(load_.name + q);
  for (const char* e : kEnergyProbes) names.push_back(e);
  return names;
}

std::vector<std::string> CoupledOutputs::field_names() const {
  std::vector<std::string> names{"deflection", "position"};
  if (want_slope_) names.push_back("slope");
  if (want_moment_) names.push_back("bending_moment");
  return names;
}

void CoupledOutputs::declare(output::Writer& w) const {
  for (const auto& pr : sc_.output.probes)
    w.add_probe({pr.name, 1, "m", "transverse deflection w (positive up, +j) at x = " + scene::format_number(pr.at) + " m",
                 {}});
  const std::string m = load_.name, q = "coupled mass '" + m + "'";
  w.add_probe({m + "_position", 1, "m", "position x(t) of " + q + " along the beam", {}});
  w.add_probe({m + "_speed", 1, "m/s", "speed x'(t) of " + q + " along the beam (signed)", {}});
  w.add_probe({m + "_deflection", 1, "m", "deflection w(x(t), t) under " + q, {}});
  w.add_probe({m + "_fixed_position", 3, "m", "fixed-frame position (x, w(x), 0) of " + q, {"x", "y", "z"}});
  w.add_probe({m + "_fixed_velocity", 3, "m/s", "fixed-frame velocity (x', w_t + x' w_x, 0) of " + q, {"x", "y", "z"}});
  w.add_probe({m + "_normal_force", 1, "N", "normal contact force of the beam on " + q + " (positive: pushes it up)", {}});
  w.add_probe({m + "_tangential_force", 1, "N", "tangential contact force of the beam on " + q + " (0 without friction)",
               {}});
  const std::pair<const char*, const char*> energies[] = {
      {"energy_beam_kinetic", "beam kinetic energy 1/2 int rhoA w_t^2 dx"},
      {"energy_beam_elastic", "beam bending energy 1/2 int EI w_xx^2 dx"},
      {"energy_beam_gravity", "beam gravity potential int rhoA g w dx"},
      {"energy_mass_kinetic", "kinetic energy of the coupled mass 1/2 M |p'|^2"},
      {"energy_mass_gravity", "gravity potential of the coupled mass M g w(x)"},
      {"work_drive", "work of the drive since the start, int D x' dt"},
      {"work_dissipated", "work dissipated by the resistance since the start, int c x'^2 dt"},
      {"energy_balance", "mechanical energy - work_drive + work_dissipated (constant up to the time discretisation)"}};
  for (const auto& [name, what] : energies) w.add_probe({name, 1, "J", what, {}});
  w.add_field({"deflection", 1, "m", "transverse deflection w (positive up, +j)", {"w"}, false, false});
  w.add_field({"position", 3, "m", "deformed position (x, w, 0): the beam along x, w along y", {"x", "y", "z"}, true});
  if (want_slope_) w.add_field({"slope", 1, "1", "slope dw/dx", {"w_x"}, false});
  if (want_moment_) w.add_field({"bending_moment", 1, "N m", "bending moment E I d2w/dx2", {"M"}, false});
}

void CoupledOutputs::evaluate(const beam::CoupledMassBeam& s) {
  probes_.clear();
  for (const auto& pr : sc_.output.probes) probes_.push_back({s.deflection(pr.at)});
  const double x = s.position(), w = s.mass_deflection(), v = s.speed();
  probes_.push_back({x});
  probes_.push_back({v});
  probes_.push_back({w});
  probes_.push_back({x, w, 0.0});
  probes_.push_back({v, s.mass_vertical_velocity(), 0.0});
  probes_.push_back({s.normal_force()});
  probes_.push_back({s.tangential_force()});
  const beam::CoupledEnergies e = s.energies();
  for (double value : {e.beam_kinetic, e.beam_elastic, e.beam_gravity, e.mass_kinetic, e.mass_gravity, e.drive_work,
                       e.dissipated, e.mechanical() - e.drive_work + e.dissipated})
    probes_.push_back({value});
  sigma_[0] = x;
  for (size_t j = 0; j < layout_.count; ++j) {
    fields_[0][j] = phi_[j].dot(s.Y());
    fields_[1][3 * j] = layout_.s[j];
    fields_[1][3 * j + 1] = fields_[0][j];
    fields_[1][3 * j + 2] = 0.0;
  }
  size_t f = 2;
  if (want_slope_)
    for (size_t j = 0; j < layout_.count; ++j) fields_[f][j] = dphi_[j].dot(s.Y());
  if (want_slope_) ++f;
  if (want_moment_)
    for (size_t j = 0; j < layout_.count; ++j) fields_[f][j] = EI_ * ddphi_[j].dot(s.Y());
}

}  // namespace


CoupledReplay::CoupledReplay(const RunOptions& opt, const std::vector<std::string>& probe_names,
                             const std::vector<std::string>& field_names, MPI_Comm comm)
    : opt_(opt), names_(probe_names) {
  if (!opt.restart) return;
  const std::string source = output::restart_source(opt.output);
  output::check_restart_outputs(source, names_, field_names);
  try {
    output::Reader r(source);
    kept_ = r.steps_written();
    time_ = r.time();
    for (const auto& n : names_) probes_.push_back(r.probe(n));
  } catch (const output::OutputError& e) {
    throw UsageError{"--restart: cannot read " + source + " (" + e.what() + ")"};
  }
  output::move_aside_for_restart(opt.output, comm);
}

void CoupledReplay::check(std::size_t o, double t, const std::vector<std::vector<double>>& probes) const {
  auto differs = [](double a, double b) {
    return !(a == b || (std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)));
  };
  std::string bad;
  if (differs(time_[o], t)) bad = "time " + scene::format_number(time_[o]) + " vs " + scene::format_number(t);
  for (size_t q = 0; bad.empty() && q < probes.size(); ++q)
    for (size_t c = 0; bad.empty() && c < probes[q].size(); ++c)
      if (differs(probes_[q].values[o * probes_[q].components + c], probes[q][c]))
        bad = "probe " + names_[q] + " = " + scene::format_number(probes_[q].values[o * probes_[q].components + c]) +
              " vs " + scene::format_number(probes[q][c]);
  if (!bad.empty())
    throw UsageError{"--restart " + opt_.output + ": re-integrating the structure and its coupled mass does not "
                     "reproduce output step " + std::to_string(o) + " (" + bad + "); the scene or the program differ "
                     "from the run being restarted"};
}

void CoupledReplay::written(std::size_t steps, MPI_Comm comm) const {
  if (opt_.restart && steps == kept_) output::remove_restart_source(opt_.output, comm);
}

void CoupledReplay::finished(std::size_t steps, MPI_Comm comm) const {
  if (opt_.restart && steps < kept_) output::remove_restart_source(opt_.output, comm);
}

const scene::MovingLoadSpec* coupled_load(const scene::Scene& sc) {
  for (const auto& l : sc.loads)
    if (l.coupled) return &l;
  return nullptr;
}

void run_beam_coupled(const scene::Scene& sc, const beam::BeamProblem& problem, const RunOptions& opt, MPI_Comm comm) {
  const scene::MovingLoadSpec& load = *coupled_load(sc);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  beam::BeamProblem p = problem;
  p.loads.clear();
  beam::CoupledMassBeam sim(p, coupled_mass(load));
  CoupledOutputs outputs(sc, load, p, sim.modes(), comm);
  const CoupledReplay replay(opt, outputs.probe_names(), outputs.field_names(), comm);
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "beam"};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(), 1);
  outputs.declare(writer);
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", p.t_start, p.t_end);
  long written = 0;
  const auto wall_start = std::chrono::steady_clock::now();
  const std::string integrator = scene::name_of(sc.beam.integrator);
  auto observe = [&](const beam::CoupledMassBeam& s) {
    if (!s.Y().allFinite() || !s.Ydot().allFinite() || !std::isfinite(s.position()) || !std::isfinite(s.speed())) {
      std::ostringstream os;
      os << "beam solver: the state of the beam and coupled mass '" << load.name << "' is not finite at t = " << s.time()
         << " s (after " << s.steps_taken() << " steps of dt = " << p.dt << " s with " << integrator
         << "); reduce time.dt";
      progress.done();
      writer.fail(os.str());
      throw NumericsError(os.str());
    }
    outputs.evaluate(s);
    const auto o = static_cast<std::size_t>(written);
    if (o < replay.kept()) replay.check(o, s.time(), outputs.probes());
    outputs.write(writer, s.time());
    ++written;
    replay.written(static_cast<std::size_t>(written), comm);
    progress.update(s.time(), s.steps_taken());
    if (s.time() >= p.t_end || s.end_reason() != beam::CoupledEnd::EndTime) return;
    if (const int sig = interrupt_requested(comm)) {
      progress.done();
      std::ostringstream os;
      os.precision(12);
      os << "interrupted at t = " << s.time() << " s (time step " << s.steps_taken() << ", " << signal_name(sig)
         << "); " << writer.steps_written() << " output steps written; continue with traverse run --restart "
         << opt.output;
      writer.fail(os.str());
      throw Interrupted(sig, opt.output, os.str(), os.str());
    }
  };
  try {
    sim.run(observe);
  } catch (const std::runtime_error& e) {  // the Newmark iteration (NumericsError, Interrupted pass)
    if (dynamic_cast<const NumericsError*>(&e) || dynamic_cast<const Interrupted*>(&e)) throw;
    progress.done();
    writer.fail(e.what());
    throw NumericsError(e.what());
  }
  progress.done();
  std::vector<output::RunEvent> events;
  const bool event = sim.end_reason() != beam::CoupledEnd::EndTime;
  if (event) events.push_back({sim.time(), sim.position(), load.name, beam::coupled_end_name(sim.end_reason())});
  writer.write_events(events);
  writer.finish();
  replay.finished(static_cast<std::size_t>(written), comm);
  if (rank == 0 && !opt.quiet) {
    std::printf("beam scene '%s': %d modes, coupled mass '%s', %ld steps of dt = %.4g s (%s) to t = %.9g s", sc.file.c_str(),
                sc.beam.modes, load.name.c_str(), sim.steps_taken(), p.dt, integrator.c_str(), sim.time());
    if (event)
      std::printf(", ended by the event %s at x = %.9g m", beam::coupled_end_name(sim.end_reason()).c_str(),
                  sim.position());
    std::printf("; %ld output steps -> %s; time stepping %.3f s (wall, output included)\n", written, opt.output.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
  }
}

}  // namespace traverse::app

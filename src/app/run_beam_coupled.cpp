// A beam run with a coupled mass (docs/beam.md "Coupled mass"): the mass's position
// is an unknown of the beam's ODE (beam::CoupledMassBeam). Outputs: the deflection probes and
// fields of a beam run, the mass's probes (position, speed, fixed-frame position and velocity,
// contact forces), the energies, and the events table (the run ends at the first event).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "beam_fields.hpp"
#include "progress.hpp"
#include "run_observer.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "step_control.hpp"
#include "traverse/beam/coupled_mass_beam.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/version.hpp"

#include "traverse/core/comm.hpp"

namespace traverse::app {

namespace {

beam::CoupledMass coupled_mass(const scene::MovingLoadSpec& l) {
  beam::CoupledMass m;
  m.mass = l.mass;
  m.start = l.start;
  m.velocity = l.initial_velocity();
  m.drive = l.drive;
  m.resistance = l.resistance;
  m.friction = l.friction;
  m.unilateral = l.contact == scene::Contact::unilateral;
  return m;
}

/// The outputs of a coupled beam run: names, declarations, values at a state.
class CoupledOutputs {
 public:
  CoupledOutputs(const scene::Scene& sc, const scene::MovingLoadSpec& load, const beam::BeamProblem& p,
                 const beam::ModeSet& modes, MPI_Comm comm);
  const output::NodeLayout& layout() const { return fields_.layout(); }
  void declare(output::Writer& w) const;
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const;
  void evaluate(const beam::CoupledMassBeam& s);
  const std::vector<std::vector<double>>& probes() const { return probes_; }
  void write(output::Writer& w, double t) const {
    w.write_step(t, sigma_, probes_, fields_.views());
  }

 private:
  const scene::Scene& sc_;
  const scene::MovingLoadSpec& load_;
  BeamFields fields_;
  std::vector<std::vector<double>> probes_;
  std::vector<double> sigma_{0.0};
};

CoupledOutputs::CoupledOutputs(const scene::Scene& sc, const scene::MovingLoadSpec& load, const beam::BeamProblem& p,
                               const beam::ModeSet& modes, MPI_Comm comm)
    : sc_(sc), load_(load), fields_(sc, p, modes, comm) {}

const char* const kEnergyProbes[] = {"energy_beam_kinetic", "energy_beam_elastic", "energy_beam_gravity",
                                      "energy_mass_kinetic", "energy_mass_gravity", "work_drive",
                                      "work_dissipated", "work_friction", "energy_balance"};

std::vector<std::string> CoupledOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const char* q : {"_position", "_speed", "_deflection", "_fixed_position", "_fixed_velocity", "_normal_force",
                        "_tangential_force"})
    names.push_back(load_.name + q);
  for (const char* e : kEnergyProbes) names.push_back(e);
  return names;
}

std::vector<std::string> CoupledOutputs::field_names() const { return fields_.names(); }

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
      {"work_friction", "work dissipated by the Coulomb friction since the start, int mu |N| |x'| dt"},
      {"energy_balance", "mechanical energy - work_drive + work_dissipated + work_friction (constant up to the time "
                         "discretisation)"}};
  for (const auto& [name, what] : energies) w.add_probe({name, 1, "J", what, {}});
  fields_.declare(w);
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
                       e.dissipated, e.friction_work, e.balance()})
    probes_.push_back({value});
  sigma_[0] = x;
  fields_.evaluate(s.Y());
}

}  // namespace



const scene::MovingLoadSpec* coupled_load(const scene::Scene& sc) {
  for (const auto& l : sc.loads)
    if (l.coupled) return &l;
  return nullptr;
}

void add_time_limit_event(const scene::Scene& sc, std::vector<output::RunEvent>& events, double t, double position,
                          bool quiet) {
  if (!sc.time.end_at_event || !events.empty()) return;
  const scene::MovingLoadSpec& load = *coupled_load(sc);
  events.push_back({t, position, load.name, "time_limit"});
  if (!quiet)
    std::printf("time.end: auto: coupled mass '%s' had no event (leaving, lift-off, stick) by time.auto_limit = %.9g s; "
                "the run ends there (event time_limit)\n", load.name.c_str(), t);
}

void run_beam_coupled(const scene::Scene& sc, const beam::BeamProblem& problem, const RunOptions& opt, MPI_Comm comm) {
  const scene::MovingLoadSpec& load = *coupled_load(sc);
  const int rank = par::rank(comm);
  beam::BeamProblem p = problem;
  p.loads.clear();
  beam::CoupledMassBeam sim(p, coupled_mass(load));
  CoupledOutputs outputs(sc, load, p, sim.modes(), comm);
  const CoupledReplay replay(opt, outputs.probe_names(), outputs.field_names(), "the beam and its coupled mass", comm);
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "beam"};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(), 1);
  writer.set_intervals(opt.flush_interval, writer.xdmf_interval());
  outputs.declare(writer);
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", p.t_start, p.t_end,
                    opt.progress_interval);
  long written = 0;
  const std::string integrator = scene::name_of(sc.beam.integrator);
  const BeamDeflectionCheck deflection_check(sc);
  auto fail = [&](const std::string& why) {  // a state the outputs refuse: the file keeps it
    progress.done();
    writer.fail(why);
    throw NumericsError(why);
  };
  auto write = [&] {
    if (!sim.Y().allFinite() || !sim.Ydot().allFinite() || !std::isfinite(sim.position()) ||
        !std::isfinite(sim.speed())) {
      std::ostringstream os;
      os << "beam solver: the state of the beam and coupled mass '" << load.name << "' is not finite at t = "
         << sim.time() << " s (after " << sim.steps_taken() << " steps of "
         << (p.adaptive ? "adaptive dt, first " : "dt = ") << p.dt << " s with " << integrator << "); "
         << (p.adaptive ? "reduce time.adaptive.tolerance" : "reduce time.dt");
      fail(os.str());
    }
    outputs.evaluate(sim);
    replay.write(outputs, writer, sim.time(), written, comm);
    if (const std::string why = deflection_check.why(sim.time(), sim); !why.empty()) fail(why);
  };
  RunObserver observer({write, [](long) {}, [&] { return sim.time(); }, {}}, writer, opt, progress, comm);
  time::TimeIntegrator steps(sim.schedule(), sim, observer);
  const auto wall_start = std::chrono::steady_clock::now();
  write();
  steps.run();  // stuck at the start: no step
  progress.done();
  std::vector<output::RunEvent> events;
  const bool event = sim.end_reason() != beam::CoupledEnd::EndTime;
  if (event) events.push_back({sim.time(), sim.position(), load.name, beam::coupled_end_name(sim.end_reason())});
  add_time_limit_event(sc, events, sim.time(), sim.position(), opt.quiet || rank != 0);
  writer.write_events(events);
  if (p.adaptive) write_adaptive_totals(writer, steps.totals());
  writer.finish();
  replay.finished(static_cast<std::size_t>(written), comm);
  if (rank == 0 && !opt.quiet) {
    std::printf("beam scene '%s': %d modes, coupled mass '%s', %ld steps of %s%.4g s (%s) to t = %.9g s", sc.file.c_str(),
                sc.beam.modes, load.name.c_str(), sim.steps_taken(), p.adaptive ? "adaptive dt, first " : "dt = ", p.dt,
                integrator.c_str(), sim.time());
    if (event)
      std::printf(", ended by the event %s at x = %.9g m", beam::coupled_end_name(sim.end_reason()).c_str(),
                  sim.position());
    std::printf("; %ld output steps -> %s; time stepping %.3f s (wall, output included)\n", written, opt.output.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
  }
  if (rank == 0 && !opt.quiet && p.adaptive) std::printf("adaptive: %s\n", steps.totals().summary().c_str());
}

}  // namespace traverse::app

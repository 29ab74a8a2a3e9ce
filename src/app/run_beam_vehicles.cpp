// A beam run with sprung masses and vehicles (docs/beam.md "Vehicles"): the bodies' bounce and
// pitch are unknowns coupled with the beam's modes (beam::VehicleBeam). Outputs: the probes and
// fields of a beam run and, per vehicle, its leading axle's position, the body's displacement,
// acceleration and pitch, each axle's contact force; the event lift_off when it ends the run.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "beam_fields.hpp"
#include "output_replay.hpp"
#include "progress.hpp"
#include "run_observer.hpp"
#include "run_beam_vehicles.hpp"
#include "traverse/beam/vehicle_beam.hpp"
#include "traverse/core/comm.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/version.hpp"

namespace traverse::app {

namespace {

beam::Vehicle vehicle(const scene::MovingLoadSpec& l) {
  beam::Vehicle v;
  v.name = l.name;
  v.mass = l.mass;
  v.pitch_inertia = l.pitch_inertia;
  for (std::size_t a = 0; a < l.axle_offsets.size(); ++a)
    v.axles.push_back({l.axle_offsets[a], l.axle_stiffness[a], l.axle_damping[a], l.wheel_masses[a]});
  v.motion.entry = l.entry == scene::Entry::left ? beam::BeamEnd::Left : beam::BeamEnd::Right;
  v.motion.direction = l.direction();
  v.motion.speed = l.speed;
  v.motion.acceleration = l.acceleration;
  v.motion.entry_time = l.entry_time;
  v.motion.start = l.start;
  v.unilateral = l.contact == scene::Contact::unilateral;
  return v;
}

/// The outputs of a vehicle run: names, declarations, values at a state.
class VehicleOutputs {
 public:
  VehicleOutputs(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes, MPI_Comm comm)
      : sc_(sc), fields_(sc, p, modes, comm) {
    for (const auto& l : sc.loads) vehicles_.push_back(&l);
    sigma_.assign(vehicles_.size(), 0.0);
  }
  const output::NodeLayout& layout() const { return fields_.layout(); }
  std::size_t count() const { return vehicles_.size(); }
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const { return fields_.names(); }
  void declare(output::Writer& w) const;
  void evaluate(const beam::VehicleBeam& s);
  const std::vector<std::vector<double>>& probes() const { return probes_; }
  void write(output::Writer& w, double t) const { w.write_step(t, sigma_, probes_, fields_.views()); }

 private:
  const scene::Scene& sc_;
  BeamFields fields_;
  std::vector<const scene::MovingLoadSpec*> vehicles_;
  std::vector<std::vector<double>> probes_;
  std::vector<double> sigma_;
};

std::vector<std::string> VehicleOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const auto* l : vehicles_) {
    for (const char* q : {"_position", "_deflection", "_body_displacement", "_body_acceleration"})
      names.push_back(l->name + q);
    if (l->type == scene::LoadType::vehicle) names.push_back(l->name + "_pitch");
    names.push_back(l->name + "_contact_force");
  }
  return names;
}

void VehicleOutputs::declare(output::Writer& w) const {
  for (const auto& pr : sc_.output.probes) declare_beam_probe(w, pr);
  for (const auto* l : vehicles_) {
    const std::string m = l->name, q = "of " + scene::name_of(l->type) + " '" + m + "'";
    w.add_probe({m + "_position", 1, "m", "position x(t) of the leading axle " + q + " along the beam", {}});
    w.add_probe({m + "_deflection", 1, "m", "deflection w(x(t), t) under the leading axle " + q + " (0 off the beam)",
                 {}});
    w.add_probe({m + "_body_displacement", 1, "m",
                 "body displacement z (up) " + q + ", from where it sits on undeformed ground with unloaded springs", {}});
    w.add_probe({m + "_body_acceleration", 1, "m/s^2", "body acceleration z'' (up) " + q, {}});
    if (l->type == scene::LoadType::vehicle)
      w.add_probe({m + "_pitch", 1, "rad", "body pitch theta " + q + " (positive: the front rises)", {}});
    std::vector<std::string> axles;
    for (std::size_t a = 0; a < l->axle_offsets.size(); ++a) axles.push_back("axle" + std::to_string(a + 1));
    w.add_probe({m + "_contact_force", axles.size(), "N",
                 "contact force on each axle " + q + " from the beam (or the ground off it), positive when compressive",
                 axles.size() > 1 ? axles : std::vector<std::string>{}});
  }
  fields_.declare(w);
}

void VehicleOutputs::evaluate(const beam::VehicleBeam& s) {
  probes_.clear();
  for (const auto& pr : sc_.output.probes)
    probes_.push_back({pr.type == scene::ProbeType::acceleration ? s.acceleration(pr.at) : s.deflection(pr.at)});
  for (std::size_t j = 0; j < vehicles_.size(); ++j) {
    const scene::MovingLoadSpec& l = *vehicles_[j];
    std::size_t lead = 0;
    for (std::size_t a = 1; a < l.axle_offsets.size(); ++a)
      if (l.axle_offsets[a] > l.axle_offsets[lead]) lead = a;
    const double x = s.axle_position(j, lead);
    sigma_[j] = x;
    probes_.push_back({x});
    probes_.push_back({x >= 0.0 && x <= sc_.beam.length ? s.deflection(x) : 0.0});
    probes_.push_back({s.body_displacement(j)});
    probes_.push_back({s.body_acceleration(j)});
    if (l.type == scene::LoadType::vehicle) probes_.push_back({s.body_pitch(j)});
    std::vector<double> f;
    for (std::size_t a = 0; a < l.axle_offsets.size(); ++a) f.push_back(s.contact_force(j, a));
    probes_.push_back(f);
  }
  fields_.evaluate(s.Y());
}

}  // namespace

void run_beam_vehicles(const scene::Scene& sc, const beam::BeamProblem& problem, const RunOptions& opt, MPI_Comm comm) {
  const int rank = par::rank(comm);
  beam::BeamProblem p = problem;
  p.loads.clear();
  std::vector<beam::Vehicle> vehicles;
  for (const auto& l : sc.loads) vehicles.push_back(vehicle(l));
  beam::VehicleBeam sim(p, vehicles);
  VehicleOutputs outputs(sc, p, sim.modes(), comm);
  const OutputReplay replay(opt, outputs.probe_names(), outputs.field_names(), "the beam and its vehicles", comm);
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "beam"};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(), outputs.count());
  outputs.declare(writer);
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", p.t_start, p.t_end);
  long written = 0;
  const std::string integrator = scene::name_of(sc.beam.integrator);
  auto write = [&] {
    if (!sim.Y().allFinite() || !sim.Ydot().allFinite() || !std::isfinite(sim.body_displacement(0))) {
      std::ostringstream os;
      os << "beam solver: the state of the beam and its vehicles is not finite at t = " << sim.time() << " s (after "
         << sim.steps_taken() << " steps of dt = " << p.dt << " s with " << integrator
         << "); reduce time.dt or use beam.integrator: newmark";
      progress.done();
      writer.fail(os.str());
      throw NumericsError(os.str());
    }
    outputs.evaluate(sim);
    replay.write(outputs, writer, sim.time(), written, comm);
  };
  RunObserver observer({write, [](long) {}, [&] { return sim.time(); }, {}}, writer, opt, progress, comm);
  time::TimeIntegrator steps(sim.schedule(), sim, observer);
  const auto wall_start = std::chrono::steady_clock::now();
  write();
  steps.run();
  progress.done();
  std::vector<output::RunEvent> events;
  const bool lift_off = sim.end_reason() == beam::VehicleEnd::LiftOff;
  if (lift_off) {
    // The vehicle whose unilateral contact force is the smallest.
    std::size_t who = 0;
    double least = HUGE_VAL;
    for (std::size_t j = 0; j < vehicles.size(); ++j)
      for (std::size_t a = 0; a < vehicles[j].axles.size(); ++a)
        if (vehicles[j].unilateral && sim.contact_force(j, a) < least) {
          least = sim.contact_force(j, a);
          who = j;
        }
    events.push_back({sim.time(), sim.axle_position(who, 0), vehicles[who].name, "lift_off"});
  }
  writer.write_events(events);
  writer.finish();
  replay.finished(static_cast<std::size_t>(written), comm);
  if (rank == 0 && !opt.quiet) {
    std::printf("beam scene '%s': %d modes, %zu vehicle(s), %ld steps of dt = %.4g s (%s) to t = %.9g s%s; %ld output "
                "steps -> %s; time stepping %.3f s (wall, output included)\n",
                sc.file.c_str(), sc.beam.modes, vehicles.size(), sim.steps_taken(), p.dt, integrator.c_str(), sim.time(),
                lift_off ? (", ended by the event lift_off of '" + events[0].load + "'").c_str() : "", written,
                opt.output.c_str(), std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
  }
}

}  // namespace traverse::app

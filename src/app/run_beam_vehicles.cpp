// A beam run with sprung masses and vehicles (docs/beam.md "Vehicles"): the bodies' bounce and
// pitch are unknowns coupled with the beam's modes (beam::VehicleBeam). Outputs: the probes and
// fields of a beam run and, per vehicle, its leading axle's position, the body's displacement,
// acceleration and pitch, each axle's contact force; the event lift_off when it ends the run.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "traverse/setup/beam_outputs.hpp"
#include "traverse/setup/beam_setup.hpp"
#include "output_replay.hpp"
#include "progress.hpp"
#include "run_observer.hpp"
#include "traverse/beam/vehicle_beam.hpp"
#include "traverse/core/comm.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/version.hpp"

namespace traverse::app {

void run_beam_vehicles(const scene::Scene& sc, const beam::BeamProblem& problem, const RunOptions& opt, MPI_Comm comm) {
  const int rank = par::rank(comm);
  beam::BeamProblem p = problem;
  p.loads.clear();
  std::vector<beam::Vehicle> vehicles;
  for (const auto& l : sc.loads) vehicles.push_back(setup::vehicle(l));
  beam::VehicleBeam sim(p, vehicles);
  setup::VehicleOutputs outputs(sc, p, sim.modes(), comm);
  const OutputReplay replay(opt, outputs.probe_names(), outputs.field_names(), "the beam and its vehicles", comm);
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "beam"};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(), outputs.count());
  outputs.declare(writer);
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", p.t_start, p.t_end);
  long written = 0;
  const std::string integrator = scene::name_of(sc.beam.integrator);
  setup::ProbeTracker extremes;
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
    extremes.take(sim.time(), outputs.probes());
    replay.write(outputs, writer, sim.time(), written, comm);
  };
  auto track = [&] { extremes.take_after_step(outputs, sim); };  // the probes' extremes over every time step
  RunObserver observer({write, [](long) {}, [&] { return sim.time(); }, {}, track}, writer, opt, progress, comm);
  time::StepHookObserver hook(observer, opt.on_step.every, setup::beam_step_hook(opt.on_step, sim, sc, p, comm));
  time::TimeIntegrator steps(sim.schedule(), sim, hook.chosen(static_cast<bool>(opt.on_step)));
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
  extremes.write(writer);
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

// A beam run with a coupled mass (docs/beam.md "Coupled mass"): the mass's position
// is an unknown of the beam's ODE (beam::CoupledMassBeam). Outputs: the deflection probes and
// fields of a beam run, the mass's probes (position, speed, fixed-frame position and velocity,
// contact forces), the energies, and the events table (the run ends at the first event).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "traverse/setup/beam_outputs.hpp"
#include "progress.hpp"
#include "run_observer.hpp"
#include "run.hpp"
#include "traverse/setup/beam_setup.hpp"
#include "run_beam_coupled.hpp"
#include "traverse/setup/step_control.hpp"
#include "traverse/beam/coupled_mass_beam.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/version.hpp"

#include "traverse/core/comm.hpp"

namespace traverse::app {

const scene::MovingLoadSpec* coupled_load(const scene::Scene& sc) {
  for (const auto& l : sc.loads)
    if (sc.model == scene::Model::Rod ? l.stepped_with_rod() : l.coupled) return &l;
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
  beam::CoupledMassBeam sim(p, setup::coupled_mass(load));
  setup::CoupledBeamOutputs outputs(sc, load, p, sim.modes(), comm);
  const OutputReplay replay(opt, outputs.probe_names(), outputs.field_names(), "the beam and its coupled mass", comm);
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "beam"};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(), 1);
  writer.set_intervals(opt.flush_interval, writer.xdmf_interval());
  outputs.declare(writer);
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", p.t_start, p.t_end,
                    opt.progress_interval);
  long written = 0;
  const std::string integrator = scene::name_of(sc.beam.integrator);
  const setup::BeamDeflectionCheck deflection_check(sc, sim.modes());
  auto fail = [&](const std::string& why) {  // a state the outputs refuse: the file keeps it
    progress.done();
    writer.fail(why);
    throw NumericsError(why);
  };
  setup::ProbeTracker extremes;
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
    extremes.take(sim.time(), outputs.probes());
    replay.write(outputs, writer, sim.time(), written, comm);
    if (const std::string why = deflection_check.why(sim.time(), sim.Y()); !why.empty()) fail(why);
  };
  auto track = [&] { extremes.take_after_step(outputs, sim); };  // the probes' extremes over every time step
  RunObserver observer({write, [](long) {}, [&] { return sim.time(); }, {}, track}, writer, opt, progress, comm);
  time::StepHookObserver hook(observer, opt.on_step.every, setup::beam_step_hook(opt.on_step, sim, sc, p, comm));
  time::TimeIntegrator steps(sim.schedule(), sim, hook.chosen(static_cast<bool>(opt.on_step)));
  const auto wall_start = std::chrono::steady_clock::now();
  write();
  steps.run();  // stuck at the start: no step
  progress.done();
  std::vector<output::RunEvent> events;
  const bool event = sim.end_reason() != beam::CoupledEnd::EndTime;
  if (event) events.push_back({sim.time(), sim.position(), load.name, beam::coupled_end_name(sim.end_reason())});
  add_time_limit_event(sc, events, sim.time(), sim.position(), opt.quiet || rank != 0);
  writer.write_events(events);
  if (p.adaptive) setup::write_adaptive_totals(writer, steps.totals());
  extremes.write(writer);
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

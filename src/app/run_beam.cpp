// A beam run in stages: the problem (beam_problem), the outputs (setup::BeamOutputs), the restart
// replay check (OutputReplay), what each output step writes (BeamRecord), the time
// integrator's run with the run's observer (RunObserver), the report.
#include <algorithm>
#include <chrono>
#include <sstream>

#include "progress.hpp"
#include "run_observer.hpp"
#include "traverse/setup/beam_outputs.hpp"
#include "output_replay.hpp"
#include "run.hpp"
#include "traverse/setup/beam_setup.hpp"
#include "run_beam_coupled.hpp"
#include "traverse/beam/beam_simulation.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/setup/step_control.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/version.hpp"

#include "traverse/core/comm.hpp"

namespace traverse::app {

namespace {

/// What a beam run does at each output step: check the state, evaluate and write the
/// outputs (checked against the file on a restart), keep the restart arrays.
class BeamRecord {
 public:
  BeamRecord(const scene::Scene& sc, const beam::BeamProblem& p, beam::BeamSimulation& sim, setup::BeamOutputs& out,
             const OutputReplay& replay, output::Writer& w, MPI_Comm comm)
      : sc_(sc), p_(p), sim_(sim), out_(out), replay_(replay), w_(w), comm_(comm) {}
  void write();
  /// The probes at the current state into their extremes (after every time step).
  void track();
  /// Writes the probes' extremes over every time step.
  void write_extremes() { extremes_.write(w_); }
  long outputs() const { return outputs_; }
  /// /restart of a beam run: the modal state (Y then Y') and [t, steps taken, output steps]
  /// of the last output step (a restart re-integrates from t = 0 and needs only the output
  /// steps; these arrays document the state).
  void store_restart();

 private:
  const scene::Scene& sc_;
  const beam::BeamProblem& p_;
  beam::BeamSimulation& sim_;
  setup::BeamOutputs& out_;
  const OutputReplay& replay_;
  output::Writer& w_;
  MPI_Comm comm_;
  const setup::BeamDeflectionCheck deflection_check_{sc_, sim_.modes()};
  setup::ProbeTracker extremes_;
  long outputs_ = 0;
  std::vector<double> restart_state_, restart_meta_;
};

void BeamRecord::store_restart() {
  if (restart_meta_.empty()) return;
  w_.write_restart(restart_meta_[0],
                   {{"modal_state", output::RestartDistribution::replicated, 1, output::DoubleView(restart_state_)},
                    {"meta", output::RestartDistribution::replicated, 1, output::DoubleView(restart_meta_)}});
}

void BeamRecord::write() {
  const beam::BeamSnapshot s = sim_.snapshot();
  if (!s.Y.allFinite() || !s.Ydot.allFinite()) {
    std::ostringstream os;
    os << "beam solver: the modal state is not finite at t = " << s.t << " s (after " << sim_.steps_taken()
       << " steps of dt = " << p_.dt << " s with " << scene::name_of(sc_.beam.integrator)
       << "); reduce time.dt or use beam.integrator: newmark";
    throw NumericsError(os.str());
  }
  out_.evaluate(s);
  extremes_.take(s.t, out_.probes());
  replay_.write(out_, w_, s.t, outputs_, comm_);
  // After the write: the file keeps the state that left the model's range.
  if (const std::string why = deflection_check_.why(s.t, s.Y); !why.empty()) throw NumericsError(why);
  restart_state_.assign(s.Y.data(), s.Y.data() + s.Y.size());
  restart_state_.insert(restart_state_.end(), s.Ydot.data(), s.Ydot.data() + s.Ydot.size());
  restart_meta_ = {s.t, static_cast<double>(sim_.steps_taken()), static_cast<double>(outputs_)};
}

void BeamRecord::track() {
  if (extremes_.taken_at(sim_.time())) return;  // an output step: write() took them
  const beam::BeamSnapshot s = sim_.snapshot();
  out_.evaluate_probes(s);
  extremes_.take(s.t, out_.probes());
}

}  // namespace

void run_beam(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  const int rank = par::rank(comm);
  // The limits (steps, memory, load ratio: run_limits.hpp) before anything of the beam's size
  // is allocated; the time grid (dt, end) comes from the same plan.
  const beam::BeamProblem p = setup::beam_problem(sc, setup::check_beam_run(sc, opt.limits, comm));
  if (coupled_load(sc)) {
    run_beam_coupled(sc, p, opt, comm);
    return;
  }
  if (std::any_of(sc.loads.begin(), sc.loads.end(), [](const scene::MovingLoadSpec& l) { return l.suspended(); })) {
    run_beam_vehicles(sc, p, opt, comm);
    return;
  }
  beam::BeamSimulation sim(p);
  setup::BeamOutputs outputs(sc, p, sim.modes(), comm);
  const OutputReplay replay(opt, outputs.probe_names(), outputs.field_names(), "the beam", comm);
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "beam"};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(),
                        std::max<size_t>(1, sc.loads.size()));
  writer.set_intervals(opt.flush_interval, writer.xdmf_interval());
  outputs.declare(writer);
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", p.t_start, p.t_end,
                    opt.progress_interval);
  BeamRecord record(sc, p, sim, outputs, replay, writer, comm);
  auto write = [&] {
    try {
      record.write();
    } catch (const NumericsError& e) {  // a state the outputs refuse: the file keeps it
      progress.done();
      record.store_restart();
      writer.fail(e.what());
      throw;
    }
  };
  RunObserver observer(
      {write, [&](long) { record.store_restart(); }, [&] { return sim.time(); }, {}, [&] { record.track(); }}, writer,
      opt, progress, comm);
  time::StepHookObserver hook(observer, opt.on_step.every, setup::beam_step_hook(opt.on_step, sim, sc, p, comm));
  time::TimeIntegrator integrator(sim.schedule(), sim, hook.chosen(static_cast<bool>(opt.on_step)));
  const auto wall_start = std::chrono::steady_clock::now();
  write();
  integrator.run();
  progress.done();
  record.store_restart();
  record.write_extremes();
  if (p.adaptive) setup::write_adaptive_totals(writer, integrator.totals());
  writer.finish();
  replay.finished(static_cast<std::size_t>(record.outputs()), comm);  // a shorter run
  if (rank == 0 && !opt.quiet)
    std::printf("beam scene '%s': %d modes, %ld steps of dt = %.4g s (%s) to t = %.6g s; %ld output steps -> %s; "
                "time stepping %.3f s (wall, output included)\n",
                sc.file.c_str(), sc.beam.modes, sim.steps_taken(), p.dt, scene::name_of(sc.beam.integrator).c_str(),
                p.t_end, record.outputs(), opt.output.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
  if (rank == 0 && !opt.quiet && p.adaptive) std::printf("adaptive: %s\n", integrator.totals().summary().c_str());
}

}  // namespace traverse::app

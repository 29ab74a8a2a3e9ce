// A beam run in stages: the problem (beam_problem), the outputs (BeamOutputs), the restart
// replay check (OutputReplay), what each output step writes (BeamRecord), the time
// integrator's run with the run's observer (RunObserver), the report.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "progress.hpp"
#include "run_observer.hpp"
#include "beam_fields.hpp"
#include "output_replay.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "run_beam_vehicles.hpp"
#include "traverse/beam/beam_simulation.hpp"
#include "traverse/output/reader.hpp"
#include "step_control.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/version.hpp"

#include "traverse/core/comm.hpp"

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

/// The moving forces of an axle train: axle a, e_a behind the head, enters when the head has
/// travelled e_a, at the head's speed then.
void add_axle_train(const scene::MovingLoadSpec& l, std::vector<beam::MovingLoad>& loads) {
  for (std::size_t a = 0; a < l.train_offsets.size(); ++a) {
    beam::MovingLoad m = moving_load(l);
    m.kind = beam::LoadKind::Force;
    m.mass = 0.0;
    m.force = -l.train_loads[a];
    m.entry_time = l.travel_time(l.train_offsets[a]);
    m.speed = std::abs(l.velocity(m.entry_time));
    loads.push_back(m);
  }
}

/// Stage 1: the beam problem of a scene on the time grid and output stride of its checked run
/// plan (run_limits.hpp: dt auto is a twentieth of the highest mode's period, at most the time
/// a load needs to cross one mesh cell; end auto is when the last load leaves; output.every
/// auto keeps kBeamOutputsPerPeriod outputs per period of the highest mode).
beam::BeamProblem beam_problem(const scene::Scene& sc, const CheckedRun& checked) {
  const TimeGrid& grid = checked.grid;
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
  p.self_weight = b.self_weight;
  p.initial_state = beam::InitialState::Static;
  for (const auto& l : sc.loads) {
    if (l.type == scene::LoadType::axle_train)
      add_axle_train(l, p.loads);
    else if (!l.suspended())  // vehicles on suspensions: run_beam_vehicles
      p.loads.push_back(moving_load(l));
  }
  p.damping = beam_damping(b);
  for (const auto& pr : sc.output.probes) p.accelerations |= pr.type == scene::ProbeType::acceleration;
  p.t_start = grid.t_start;
  p.t_end = grid.t_end;
  p.dt = grid.dt;
  p.integrator = b.integrator == scene::BeamIntegrator::newmark ? beam::Integrator::Newmark : beam::Integrator::RK4;
  p.output_every = checked.output_every;
  p.adaptive = sc.time.adaptive.enabled;
  if (p.adaptive) p.control = step_control_parameters(sc.time.adaptive, grid.dt, p.integrator == beam::Integrator::RK4 ? 4 : 2);
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
  const output::NodeLayout& layout() const { return fields_.layout(); }
  void declare(output::Writer& w) const;
  /// Evaluates every output at a snapshot (probe values are kept for the replay check).
  void evaluate(const beam::BeamSnapshot& s);
  const std::vector<std::vector<double>>& probes() const { return probes_; }
  void write(output::Writer& w, double t) const;

 private:
  const scene::Scene& sc_;
  BeamFields fields_;
  std::vector<std::vector<double>> probes_;
  std::vector<double> sigma_;
  std::vector<std::size_t> first_;  ///< per scene load: its first load of the problem (a train's head)
};

BeamOutputs::BeamOutputs(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes, MPI_Comm comm)
    : sc_(sc), fields_(sc, p, modes, comm) {
  probes_.assign(sc.output.probes.size() + 2 * sc.loads.size(), std::vector<double>(1));
  sigma_.assign(std::max<size_t>(1, sc.loads.size()), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0, k = 0; i < sc.loads.size(); ++i) {
    first_.push_back(k);
    k += sc.loads[i].type == scene::LoadType::axle_train ? sc.loads[i].train_offsets.size() : 1;
  }
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

std::vector<std::string> BeamOutputs::field_names() const { return fields_.names(); }

void BeamOutputs::declare(output::Writer& w) const {
  for (const auto& pr : sc_.output.probes) declare_beam_probe(w, pr);
  for (const auto& l : sc_.loads) {
    w.add_probe({l.name + "_position", 1, "m", "position x(t) of load '" + l.name + "' along the beam" +
                 (l.type == scene::LoadType::axle_train ? " (its head)" : ""), {}});
    w.add_probe({l.name + "_deflection", 1, "m",
                 "deflection w(x(t), t) under load '" + l.name + "' (NaN while it is off the beam)", {}});
  }
  fields_.declare(w);
}

void BeamOutputs::evaluate(const beam::BeamSnapshot& s) {
  size_t k = 0;
  for (const auto& pr : sc_.output.probes)
    probes_[k++][0] = pr.type == scene::ProbeType::acceleration ? s.acceleration(pr.at) : s.deflection(pr.at);
  for (size_t i = 0; i < sc_.loads.size(); ++i) {
    sigma_[i] = s.load_position(first_[i]);
    probes_[k++][0] = s.load_position(first_[i]);
    probes_[k++][0] = s.load_deflection(first_[i]);
  }
  fields_.evaluate(s.Y);
}

void BeamOutputs::write(output::Writer& w, double t) const {
  w.write_step(t, sigma_, probes_, fields_.views());
}

/// What a beam run does at each output step: check the state, evaluate and write the
/// outputs (checked against the file on a restart), keep the restart arrays.
class BeamRecord {
 public:
  BeamRecord(const scene::Scene& sc, const beam::BeamProblem& p, beam::BeamSimulation& sim, BeamOutputs& out,
             const OutputReplay& replay, output::Writer& w, MPI_Comm comm)
      : sc_(sc), p_(p), sim_(sim), out_(out), replay_(replay), w_(w), comm_(comm) {}
  void write();
  long outputs() const { return outputs_; }
  /// /restart of a beam run: the modal state (Y then Y') and [t, steps taken, output steps]
  /// of the last output step (a restart re-integrates from t = 0 and needs only the output
  /// steps; these arrays document the state).
  void store_restart();

 private:
  const scene::Scene& sc_;
  const beam::BeamProblem& p_;
  beam::BeamSimulation& sim_;
  BeamOutputs& out_;
  const OutputReplay& replay_;
  output::Writer& w_;
  MPI_Comm comm_;
  const BeamDeflectionCheck deflection_check_{sc_};
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
  replay_.write(out_, w_, s.t, outputs_, comm_);
  // After the write: the file keeps the state that left the model's range.
  if (const std::string why = deflection_check_.why(s.t, s); !why.empty()) throw NumericsError(why);
  restart_state_.assign(s.Y.data(), s.Y.data() + s.Y.size());
  restart_state_.insert(restart_state_.end(), s.Ydot.data(), s.Ydot.data() + s.Ydot.size());
  restart_meta_ = {s.t, static_cast<double>(sim_.steps_taken()), static_cast<double>(outputs_)};
}

}  // namespace

void run_beam(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  const int rank = par::rank(comm);
  // The limits (steps, memory, load ratio: run_limits.hpp) before anything of the beam's size
  // is allocated; the time grid (dt, end) comes from the same plan.
  const beam::BeamProblem p = beam_problem(sc, check_beam_run(sc, opt.limits, comm));
  if (coupled_load(sc)) {
    run_beam_coupled(sc, p, opt, comm);
    return;
  }
  if (std::any_of(sc.loads.begin(), sc.loads.end(), [](const scene::MovingLoadSpec& l) { return l.suspended(); })) {
    run_beam_vehicles(sc, p, opt, comm);
    return;
  }
  beam::BeamSimulation sim(p);
  BeamOutputs outputs(sc, p, sim.modes(), comm);
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
  RunObserver observer({write, [&](long) { record.store_restart(); }, [&] { return sim.time(); }, {}}, writer, opt,
                       progress, comm);
  time::TimeIntegrator integrator(sim.schedule(), sim, observer);
  const auto wall_start = std::chrono::steady_clock::now();
  write();
  integrator.run();
  progress.done();
  record.store_restart();
  if (p.adaptive) write_adaptive_totals(writer, integrator.totals());
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

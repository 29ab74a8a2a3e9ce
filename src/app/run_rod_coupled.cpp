// A rod run with a coupled mass (docs/rod.md "Coupled mass"): the mass's position an
// unknown of each step (rod::CoupledRodStepper), the rod's step solved by
// solver::RodStepper (any ranks, the planar or the 3D path, any linear solver), the whole
// state kept on every rank between the steps. Outputs: the rod's probes and fields, the mass's probes (position, speed, fixed-frame position
// and velocity, contact forces), the energies, and the events table (the run ends when the mass
// leaves the rod).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <optional>

#include "interrupt.hpp"
#include "mpi_session.hpp"
#include "restart.hpp"
#include "progress.hpp"
#include "run_observer.hpp"
#include "traverse/setup/coupled_restart.hpp"
#include "traverse/setup/step_control.hpp"
#include "traverse/setup/rod_outputs.hpp"
#include "traverse/setup/rod_setup.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/rod/coupled_mass_rod.hpp"
#include "traverse/solver/coupled_rod_solve.hpp"
#include "traverse/solver/coupled_rod_time_model.hpp"
#include "traverse/time/time_integrator.hpp"
#include "traverse/version.hpp"

namespace traverse::app {

namespace {

/// Restart points of a coupled rod run (docs/reliability.md "Restart"): per node the node
/// (rod::kPackedNodeValues values), its point of the centreline (3) and with time.adaptive the rod
/// estimate's values (solver::RodErrorEstimate::kPerNode); `extra` holds setup::pack_coupled_run's
/// values, then with time.adaptive the mass controller's per-node values, the count of the rod
/// controller's scalars, those scalars and the mass controller's.
namespace extra = setup::coupled_extra;
std::size_t coupled_restart_components(bool adaptive) {
  return rod::kPackedNodeValues + 3 + (adaptive ? solver::RodErrorEstimate::kPerNode : 0);
}

/// The outputs and restart points of a coupled run; the state is the model's.
class CoupledRecord {
 public:
  /// `first`, `count`: this rank's nodes (the restart point's share); `planar`: the path;
  /// `rc`, `mc`: the adaptive estimates of the rod and the mass (or nullptr).
  CoupledRecord(solver::CoupledRodTimeModel& model, const rod::RodState& state, const rod::CoupledMassState& m,
                setup::CoupledRodOutputs& outputs, output::Writer& w, double dt, bool planar, int first, int count,
                MPI_Comm comm, solver::RodErrorEstimate* rc, solver::RodErrorEstimate* mc)
      : model_(model), state_(state), m_(m), out_(outputs), w_(w), dt_(dt), planar_(planar), first_(first),
        count_(count), rc_(rc), mc_(mc), slots_(comm, coupled_restart_components(rc != nullptr),
                                                 static_cast<std::size_t>(first)) {}
  void write() {  // once per time (a stick at the start of a step ends the run at a time already written)
    if (state_.t == written_t_) return;
    written_t_ = state_.t;
    out_.write(w_, state_, model_.r, m_, model_.contact);
  }
  /// Stores a restart point of the current state (collective).
  void store();
  /// Continues from a restart point: the model's values and the estimates'; the controller's
  /// state (adaptive steps).
  std::optional<time::ControllerState> restore(const output::RestartPoint& point, rod::CoupledMassState& m);
  /// The controller whose state an adaptive run's points keep.
  const time::TimeIntegrator* integrator = nullptr;

 private:
  std::vector<double> restart_extra() const;
  solver::CoupledRodTimeModel& model_;
  const rod::RodState& state_;
  const rod::CoupledMassState& m_;
  setup::CoupledRodOutputs& out_;
  output::Writer& w_;
  double dt_;
  bool planar_;
  int first_, count_;
  solver::RodErrorEstimate *rc_, *mc_;
  output::RestartSlots slots_;
  double written_t_ = std::numeric_limits<double>::quiet_NaN();
};

std::vector<double> CoupledRecord::restart_extra() const {
  std::vector<double> x = setup::pack_coupled_run(model_, m_, dt_, planar_, written_t_);
  if (rc_) {
    std::vector<double> mass_node(solver::RodErrorEstimate::kPerNode);
    mc_->pack_node(0, mass_node.data());
    const time::ControllerState ctl = integrator->controller_state();
    const std::vector<double> a = rc_->pack_scalars(ctl), b = mc_->pack_scalars(ctl);
    x.insert(x.end(), mass_node.begin(), mass_node.end());
    x.push_back(double(a.size()));
    x.insert(x.end(), a.begin(), a.end());
    x.insert(x.end(), b.begin(), b.end());
  }
  return x;
}

void CoupledRecord::store() {
  const std::size_t comps = coupled_restart_components(rc_ != nullptr);
  std::vector<double> local(comps * static_cast<std::size_t>(count_));
  for (int k = 0; k < count_; ++k) {
    const std::size_t j = static_cast<std::size_t>(first_ + k);
    double* o = &local[comps * static_cast<std::size_t>(k)];
    rod::pack_node(state_.nodes[j], o);
    for (int c = 0; c < 3; ++c) o[rod::kPackedNodeValues + c] = model_.r[j](c);
    if (rc_) rc_->pack_node(first_ + k, o + rod::kPackedNodeValues + 3);
  }
  slots_.write(w_, state_.t, model_.steps, restart_extra(), local);
}

std::optional<time::ControllerState> CoupledRecord::restore(const output::RestartPoint& point,
                                                            rod::CoupledMassState& m) {
  const auto& x = point.extra;
  const std::size_t comps = point.components, n = state_.nodes.size();
  for (std::size_t j = 0; j < n; ++j)
    for (int c = 0; c < 3; ++c)
      model_.r[j](c) = point.state[comps * j + rod::kPackedNodeValues + static_cast<std::size_t>(c)];
  written_t_ = setup::unpack_coupled_run(x, model_, m);
  if (!rc_) return std::nullopt;
  constexpr std::size_t kPerNode = solver::RodErrorEstimate::kPerNode;
  std::vector<double> per_node(kPerNode * n);
  for (std::size_t j = 0; j < n; ++j)
    std::copy_n(&point.state[comps * j + rod::kPackedNodeValues + 3], kPerNode, &per_node[kPerNode * j]);
  const auto p = x.begin() + static_cast<std::ptrdiff_t>(extra::fixed);
  const std::vector<double> mass_node(p, p + kPerNode);
  const auto q = p + kPerNode;
  const auto na = static_cast<std::ptrdiff_t>(*q);
  mc_->restore(solver::mass_level(m), mass_node, std::vector<double>(q + 1 + na, x.end()));
  return rc_->restore(solver::rod_levels(state_), per_node, std::vector<double>(q + 1, q + 1 + na));
}

// The rod's estimate and the mass's (its position only); the larger decides.
void make_estimates(const scene::Scene& sc, const rod::AlphaParameters& alpha, const rod::RodState& state,
                    const rod::CoupledMassState& m, std::unique_ptr<solver::RodErrorEstimate>& rc,
                    std::unique_ptr<solver::RodErrorEstimate>& mc) {
  rod::ErrorWeights w = setup::error_weights(sc.time.adaptive, sc.rod.length);
  rc = std::make_unique<solver::RodErrorEstimate>(w, alpha, MPI_COMM_NULL);
  w.controlled = {true, false, false, false, false};
  mc = std::make_unique<solver::RodErrorEstimate>(w, alpha, MPI_COMM_NULL);
  rc->start(solver::rod_levels(state));
  mc->start(solver::mass_level(m));
}

void print_start(const scene::Scene& sc, const TimeGrid& grid, const std::string& initial,
                 const solver::RodStepper& st, const std::string& path_text, const RunOptions& opt,
                 const output::RestartPoint& point) {
  const scene::MovingLoadSpec& load = *coupled_load(sc);
  std::printf("rod scene '%s': %d nodes, %s '%s', up to %ld steps of dt = %.6g s to t = %.6g s%s\n", sc.file.c_str(),
              sc.mesh.nodes, scene::name_of(load.type).c_str(), load.name.c_str(), grid.steps, grid.dt, grid.t_end,
              sc.time.adaptive.enabled ? " (adaptive: the first step and the output spacing)" : "");
  if (opt.verbose)
    std::printf("  initial state: %s; partitioned iteration of rod and mass; linear solver: %s; path: %s\n",
                initial.c_str(), st.resolved_linear_solver().c_str(), path_text.c_str());
  if (opt.restart)
    std::printf("restart from %s: time step %ld at t = %.9g s, %zu output steps kept\n", opt.output.c_str(),
                point.step, point.time, point.steps_written);
}

void print_done(const solver::CoupledRodTimeModel& model, const std::vector<output::RunEvent>& events,
                std::size_t written, const std::string& output, std::chrono::steady_clock::time_point wall,
                const time::TimeIntegrator* adaptive, bool verbose) {
  std::printf("done: %ld steps", model.steps);
  if (verbose) std::printf(", %ld coupling iterations, %ld Newton iterations", model.coupling, model.newton);
  if (!events.empty())
    std::printf("; ended by the event %s at t = %.9g s%s", events[0].reason.c_str(), events[0].time,
                events[0].reason.rfind("left_rod", 0) == 0 || events[0].reason == "lift_off" ? " (interpolated)" : "");
  std::printf("; %zu output steps -> %s; time stepping %.3f s (wall, output included)\n", written, output.c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count());
  if (adaptive) std::printf("adaptive: %s\n", adaptive->totals().summary().c_str());
}

}  // namespace

void run_rod_coupled(const scene::Scene& sc, const setup::RodSetup& setup, const TimeGrid& grid, const RunOptions& opt,
                     MPI_Comm comm) {
  const scene::MovingLoadSpec& load = *coupled_load(sc);
  const int rank = comm_rank(comm);
  setup::check_coupled_rod(sc, setup.model);
  if (!opt.restart) setup::precheck_planar(sc, setup.model);
  // The initial state, or the restart point's (the whole state on every rank).
  setup::InitialState start;
  output::RestartPoint point;
  std::string source;
  if (opt.restart) {
    source = output::restart_source(opt.output);
    const bool adaptive = sc.time.adaptive.enabled;
    point = read_rod_restart_point(opt.output, source, static_cast<std::size_t>(sc.mesh.nodes),
                                   coupled_restart_components(adaptive), coupled_restart_components(!adaptive),
                                   adaptive, grid.dt, extra::dt);
    start.description = "restart";
    start.state.t = point.time;
    start.state.ds = sc.mesh.ds;
    for (std::size_t j = 0; j < static_cast<std::size_t>(sc.mesh.nodes); ++j)
      start.state.nodes.push_back(rod::unpack_node(&point.state[point.components * j]));
  } else {
    start = setup::initial_state(sc, setup, comm);
  }
  const rod::CoupledRodMass mass = setup::coupled_rod_mass(load);
  // The rod's steps on the distributed stepper, made from the model with the mass's loads.
  solver::DistributedCoupledRodSolve* rod_solve = nullptr;
  rod::CoupledRodStepper stepper(setup.model, mass, [&](rod::RodModel with_mass) {
    setup::RodSetup s{std::move(with_mass), setup.solver};
    auto made = std::make_unique<solver::DistributedCoupledRodSolve>(setup::make_stepper(sc, s, comm), comm);
    rod_solve = made.get();
    return made;
  });
  solver::RodStepper& st = rod_solve->stepper();
  st.set_state(start.state, start.first_node);
  rod::RodState state = st.gather_state();  // whole, on every rank
  start.state = rod::RodState();
  // The mass's loads lie in the plane of a planar rod (its weight, its inertia along the rod
  // and the resistance along d3): the path is chosen from the model without them. A restart
  // keeps the path of the run it continues.
  const int stored_path = opt.restart ? (point.extra[extra::planar] != 0.0 ? 1 : 0) : -1;
  const setup::PathChoice path = setup::choose_path(sc, setup.model, st, stored_path, comm);
  if (path.planar) st.set_planar(&path.symmetry);
  const std::string path_text = st.path_description() + "; " + path.detail;
  rod::CoupledMassState m{load.position(0.0), load.velocity(0.0)};
  if (mass.suspended && !opt.restart) rod::start_suspension(mass, stepper.model(), state, m);
  const int first = st.first_owned_node(), count = st.num_owned_nodes();
  setup::CoupledRodOutputs outputs(sc, load, stepper.coupled_mass(), stepper.model(), first, count);
  if (opt.restart) {
    output::check_restart_outputs(source, outputs.probe_names(), outputs.field_names());
    source = output::move_aside_for_restart(opt.output, comm);
  }
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "rod", {}};
  info.attributes = {{"rod_path", path.planar ? "planar" : "3D"},
                     {"rod_path_detail", path_text + " (" + scene::name_of(load.type) + ")"},
                     {"initial_state", start.description}};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(), 1);
  writer.set_intervals(opt.flush_interval, writer.xdmf_interval());
  outputs.declare(writer);
  std::unique_ptr<solver::RodErrorEstimate> rc, mc;  // time.adaptive: the rod's and the mass's
  if (sc.time.adaptive.enabled) make_estimates(sc, stepper.model().alpha, state, m, rc, mc);
  solver::CoupledRodTimeModel model(stepper, state, m, load.name, load.contact == scene::Contact::unilateral,
                                    rc.get(), mc.get());
  CoupledRecord record(model, state, m, outputs, writer, grid.dt, path.planar, first, count, comm, rc.get(), mc.get());
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", state.t, grid.t_end,
                    opt.progress_interval);
  RunObserver observer({[&] { record.write(); }, [&](long) { record.store(); }, [&] { return state.t; }, {}, {}},
                       writer, opt, progress, comm);
  time::StepHookObserver hooked(observer, opt.on_step.every, [&](long i) {
    return setup::coupled_call_back(opt.on_step, i, state, model.r, m, mass.suspended, comm);
  });
  time::TimeIntegrator integrator(setup::rod_schedule(sc, grid), model, hooked.chosen(static_cast<bool>(opt.on_step)));
  record.integrator = &integrator;
  if (opt.restart) {
    output::copy_output_steps(source, writer, point.steps_written, outputs.probe_names(), outputs.field_names(),
                              static_cast<std::size_t>(first), static_cast<std::size_t>(count));
    if (const auto controller = record.restore(point, m)) integrator.restore(*controller);
    record.store();
    output::remove_restart_source(opt.output, comm);
  } else {
    record.write();
    record.store();
  }
  if (rank == 0 && !opt.quiet) print_start(sc, grid, start.description, st, path_text, opt, point);
  const auto wall = std::chrono::steady_clock::now();
  integrator.run(model.steps + 1);
  progress.done();
  std::vector<output::RunEvent> events;
  for (const auto& e : model.events) events.push_back({e.time, e.position, load.name, e.reason});
  add_time_limit_event(sc, events, state.t, m.sigma, opt.quiet || rank != 0);
  record.store();  // the end: a restart of the complete file continues nothing
  writer.write_events(events);
  if (rc) setup::write_adaptive_totals(writer, integrator.totals());
  setup::write_solve_totals(writer, model.steps, model.newton, model.coupling);
  writer.finish();
  if (rank == 0 && !opt.quiet)
    print_done(model, events, writer.steps_written(), opt.output, wall, rc ? &integrator : nullptr, opt.verbose);
}

}  // namespace traverse::app

// A dynamic rod run in stages (docs/developer.md, "Module map"):
//   model (rod_setup: build_rod_model) -> initial state (rod_setup: initial_state, each rank
//   its piece) -> stepper and path -> output plan (RodOutputs) -> the time integrator with the
//   rod as its model (solver::RodTimeModel) and the run's observer (RunObserver) ->
//   report.
// Each stage is a function or a class of its own; run_rod only strings them together.
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>

#include "interrupt.hpp"
#include "progress.hpp"
#include "run_observer.hpp"
#include "traverse/setup/step_control.hpp"
#include "traverse/setup/rod_outputs.hpp"
#include "restart.hpp"
#include "traverse/setup/rod_setup.hpp"
#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/output/restart.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/solver/rod_stepper.hpp"
#include "traverse/solver/rod_time_model.hpp"
#include "traverse/time/time_integrator.hpp"
#include "traverse/core/comm.hpp"
#include "traverse/version.hpp"
#include "traverse/setup/solver_access.hpp"

namespace traverse::app {

namespace {

/// Restart points of a rod run (docs/reliability.md): the state, the time, the step index
/// (adaptive: the accepted steps) and extra = (left-end position, dt, path, and with
/// time.adaptive the controller's scalars).
class RodRestartPoints {
 public:
  RodRestartPoints(const solver::RodStepper& st, output::Writer& w, double dt, bool planar,
                   const solver::RodErrorEstimate* adaptive, MPI_Comm comm)
      : st_(st), w_(w), dt_(dt), planar_(planar), adaptive_(adaptive),
        components_(rod::kPackedNodeValues + (adaptive ? solver::RodErrorEstimate::kPerNode : 0)),
        slots_(comm, components_, static_cast<std::size_t>(st.first_owned_node())),
        packed_(components_ * static_cast<std::size_t>(st.num_owned_nodes())) {}
  /// The controller whose state an adaptive run's points keep.
  const time::TimeIntegrator* integrator = nullptr;
  /// Stores the point of time step i (once per step).
  void store(long i, const Vec3& r0) {
    if (i == stored_at_) return;
    for (int k = 0; k < st_.num_owned_nodes(); ++k) {
      double* o = &packed_[components_ * static_cast<std::size_t>(k)];
      rod::pack_node(st_.owned_node(k), o);
      if (adaptive_) adaptive_->pack_node(k, o + rod::kPackedNodeValues);
    }
    std::vector<double> extra = {r0.x(), r0.y(), r0.z(), dt_, planar_ ? 1.0 : 0.0};
    if (adaptive_)
      for (const double v : adaptive_->pack_scalars(integrator->controller_state())) extra.push_back(v);
    slots_.write(w_, st_.time(), i, extra, packed_);
    stored_at_ = i;
  }

 private:
  const solver::RodStepper& st_;
  output::Writer& w_;
  double dt_;
  bool planar_;
  const solver::RodErrorEstimate* adaptive_;
  std::size_t components_;
  output::RestartSlots slots_;
  std::vector<double> packed_;
  long stored_at_ = -1;
};

/// ", N solves retried from the other initial guess" (solver key 'Initial Guess: auto'), or "".
std::string retries_note(long retries) {
  if (retries == 0) return "";
  return ", " + std::to_string(retries) + (retries == 1 ? " solve" : " solves") + " retried from the other initial guess";
}

/// A restart's source file, restart point and state (opt.restart only).
struct RestartSource {
  std::string file;
  output::RestartPoint point;
};
RestartSource read_restart(const scene::Scene& sc, const RunOptions& opt, const TimeGrid& g, rod::RodState& state) {
  RestartSource src;
  const int N = sc.mesh.nodes - 1;
  src.file = output::restart_source(opt.output);
  const std::size_t comps = setup::rod_restart_components(sc);
  const std::size_t other = sc.time.adaptive.enabled ? rod::kPackedNodeValues : rod::kPackedNodeValues + solver::RodErrorEstimate::kPerNode;
  src.point = read_rod_restart_point(opt.output, src.file, static_cast<std::size_t>(N + 1), comps, other,
                                     sc.time.adaptive.enabled, g.dt, 3);
  state.t = src.point.time;
  state.ds = sc.rod.length / N;
  state.nodes.resize(static_cast<std::size_t>(N + 1));
  for (int j = 0; j <= N; ++j)
    state.nodes[static_cast<std::size_t>(j)] = rod::unpack_node(&src.point.state[comps * static_cast<std::size_t>(j)]);
  return src;
}

// What the stepper would refuse about its linear solver, found before anything is allocated.
void check_linear_solver(const scene::Scene& sc, const setup::RodSetup& setup, MPI_Comm comm) {
  const int ranks = par::size(comm);
  try {
    solver::LinearSolverChoice::resolve(setup.solver, ranks, solver::LinearSolverChoice::Use::time_step);
  } catch (const std::invalid_argument& e) {
    setup::linear_solver_refused(sc, ranks, e);
  }
}

/// One line: the scene, its size and steps; with -v the initial state, the linear solver and
/// the path.
void print_start(const scene::Scene& sc, const TimeGrid& g, const std::string& initial,
                 const solver::RodStepper& st, const std::string& path_text, bool verbose) {
  char steps[160];
  if (sc.time.adaptive.enabled)
    std::snprintf(steps, sizeof steps, "adaptive steps (tolerance %.3g, first dt = %.6g s, outputs every %.6g s)",
                  sc.time.adaptive.tolerance, g.dt, g.dt * sc.output.every);
  else
    std::snprintf(steps, sizeof steps, "%ld steps of dt = %.6g s", g.steps, g.dt);
  std::printf("rod scene '%s': %d nodes, %s to t = %.6g s\n", sc.file.c_str(), sc.mesh.nodes, steps, g.t_end);
  if (verbose)
    std::printf("  initial state: %s; linear solver: %s%s; path: %s\n", initial.c_str(),
                st.resolved_linear_solver().c_str(),
                st.linear_solver_rerouted() ? " (rerouted: Amesos2 gives wrong answers on 2+ ranks here)" : "",
                path_text.c_str());
}

/// The output file's first steps: a restart's copy of the kept ones (and its restart point),
/// or the initial state's. The first time step to take.
long start_outputs(const RunOptions& opt, const RestartSource& restart, setup::RodOutputs& outputs, output::Writer& writer,
                   RodRestartPoints& points, const solver::RodStepper& st, const solver::LeftEnd& left, MPI_Comm comm) {
  if (!opt.restart) {
    outputs.write(writer, 0.0, left.position());
    points.store(0, left.position());
    return 1;
  }
  output::copy_output_steps(restart.file, writer, restart.point.steps_written, outputs.probe_names(),
                            outputs.field_names(), static_cast<std::size_t>(st.first_owned_node()),
                            static_cast<std::size_t>(st.num_owned_nodes()));
  points.store(restart.point.step, left.position());
  output::remove_restart_source(opt.output, comm);
  if (par::rank(comm) == 0 && !opt.quiet)
    std::printf("restart from %s: time step %ld at t = %.9g s, %zu output steps kept\n", opt.output.c_str(),
                restart.point.step, restart.point.time, restart.point.steps_written);
  return restart.point.step + 1;
}

/// One line: the output steps, where they went and the time; with -v the Newton iterations
/// and the path.
void print_done(const solver::SolveCounts& tot, bool planar, const output::Writer& writer, const std::string& output,
                double seconds, const time::TimeIntegrator* adaptive, bool verbose) {
  std::printf("done: %zu output steps -> %s; time stepping %.3f s (wall, output included)\n", writer.steps_written(),
              output.c_str(), seconds);
  if (verbose)
    std::printf("  %ld Newton iterations in %ld solves (%.2f per solve%s) on the %s path\n", tot.newton, tot.solves,
                tot.solves ? double(tot.newton) / double(tot.solves) : 0.0, retries_note(tot.guess_retries).c_str(),
                planar ? "planar" : "3D");
  if (adaptive) std::printf("adaptive: %s\n", adaptive->totals().summary().c_str());
}

}  // namespace

void check_rod(const scene::Scene& sc) {
  const setup::RodSetup setup = setup::build_rod_model(sc);
  if (coupled_load(sc)) setup::check_coupled_rod(sc, setup.model);
  setup::precheck_planar(sc, setup.model);
}

void run_rod(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  const int rank = par::rank(comm);
  const setup::RodSetup setup = setup::build_rod_model(sc);
  // Kokkos lives from the first rod run of the process to the process's end
  // (setup::finish_solver_runtime), Tpetra for this run only.
  const setup::TpetraScope tpetra(comm);

  // Model, limits and stepper first: the limits (steps, memory, load ratio: run_limits.hpp),
  // the partition (ranks <= nodes), the linear solver and a required planar path are bad
  // input (exit 2), found before anything of the rod's size is allocated and before any
  // initial state is computed.
  const TimeGrid grid = setup::check_rod_run(sc, setup.model, opt.limits, comm).grid;
  check_linear_solver(sc, setup, comm);
  if (coupled_load(sc)) {
    run_rod_coupled(sc, setup, grid, opt, comm);
    return;
  }
  if (!opt.restart) setup::precheck_planar(sc, setup.model);

  // The initial state before the stepper: the static solve's matrices are freed before the
  // stepper allocates its own, so the peak memory is the larger of the two, not their sum.
  setup::InitialState start;
  RestartSource restart;
  if (opt.restart) {
    start.description = "restart";
    restart = read_restart(sc, opt, grid, start.state);
  } else {
    start = setup::initial_state(sc, setup, comm);
  }
  auto stepper = setup::make_stepper(sc, setup, comm);
  stepper->set_state(start.state, start.first_node);

  // Path: the planar fast path or the 3D system (docs/solver.md); a restart keeps the path
  // of the run it continues (restart extra[4]: 1 planar, 0 3D).
  const auto& extra = restart.point.extra;
  const int stored_path = opt.restart && extra.size() >= 5 ? (extra[4] != 0.0 ? 1 : 0) : -1;
  start.state = rod::RodState();  // the stepper holds its own copy
  const setup::PathChoice path = setup::choose_path(sc, setup.model, *stepper, stored_path, comm);
  if (path.planar) stepper->set_planar(&path.symmetry);
  const std::string path_text = stepper->path_description() + "; " + path.detail;

  setup::RodOutputs outputs(sc, setup.model, *stepper, comm);
  if (opt.restart) {
    output::check_restart_outputs(restart.file, outputs.probe_names(), outputs.field_names());
    restart.file = output::move_aside_for_restart(opt.output, comm);
  }
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "rod", {}};
  info.attributes = {{"rod_path", path.planar ? "planar" : "3D"}, {"rod_path_detail", path_text},
                     {"initial_state", start.description}};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(),
                        std::max<size_t>(1, sc.loads.size()));
  writer.set_intervals(opt.flush_interval, writer.xdmf_interval());
  outputs.declare(writer);

  const Vec3 r0 = opt.restart ? Vec3(extra[0], extra[1], extra[2]) : Vec3(Vec3::Zero());
  solver::LeftEnd left(*stepper, setup.model.left.end_moves(), r0, comm);
  std::optional<time::ControllerState> controller;
  std::unique_ptr<solver::RodErrorEstimate> estimate;
  if (sc.time.adaptive.enabled)
    estimate = setup::rod_error_estimate(sc, setup.model, *stepper, restart.file.empty() ? nullptr : &restart.point,
                                         comm, controller);
  RodRestartPoints points(*stepper, writer, grid.dt, path.planar, estimate.get(), comm);
  std::function<double(double)> kinks;  // adaptive steps land on the loads' node crossings
  if (sc.time.adaptive.land_on_nodes)
    kinks = [&](double t) { return setup::next_node_crossing(sc.loads, t, setup.model.ds(), setup.model.length); };
  solver::RodTimeModel model(*stepper, left, estimate.get(), kinks);
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", stepper->time(), grid.t_end,
                    opt.progress_interval);
  const setup::LoadRatio load = setup::load_ratio(sc);
  RunObserver observer({[&] { outputs.write(writer, stepper->time(), left.position()); },
                        [&](long i) { points.store(i, left.position()); }, [&] { return stepper->time(); },
                        [&](const std::string& where, const time::StepFailed& e) {
                          const auto* f = dynamic_cast<const solver::StepFailure*>(&e);
                          return f ? setup::explain_step_failure(where, *f, setup.model, grid, load) : where + ": " + e.what();
                        },
                        {}},
                       writer, opt, progress, comm);
  time::StepHookObserver hooked(observer, opt.on_step.every, [&](long i) {
    return outputs.call_back(opt.on_step, i, stepper->time(), left.position());
  });
  time::TimeIntegrator integrator(setup::rod_schedule(sc, grid), model, hooked.chosen(static_cast<bool>(opt.on_step)));
  points.integrator = &integrator;
  if (controller) integrator.restore(*controller);
  if (rank == 0 && !opt.quiet) print_start(sc, grid, start.description, *stepper, path_text, opt.verbose);
  if (rank == 0 && !estimate)
    for (const std::string& w : setup::under_resolved_load_warnings(sc, grid))
      std::fprintf(stderr, "traverse: warning: %s\n", w.c_str());
  const long first_step = start_outputs(opt, restart, outputs, writer, points, *stepper, left, comm);
  const auto wall = std::chrono::steady_clock::now();
  integrator.run(first_step);
  progress.done();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
  points.store(integrator.last_step(), left.position());  // the end (a no-op when the last output step stored it)
  if (estimate) setup::write_adaptive_totals(writer, integrator.totals());
  setup::write_solve_totals(writer, integrator.last_step(), model.counts().newton);
  writer.finish();
  if (rank == 0 && !opt.quiet) print_done(model.counts(), path.planar, writer, opt.output, seconds, estimate ? &integrator : nullptr,
                                         opt.verbose);
}

}  // namespace traverse::app

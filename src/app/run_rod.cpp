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
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "interrupt.hpp"
#include "progress.hpp"
#include "rod_adaptive.hpp"
#include "run_observer.hpp"
#include "step_control.hpp"
#include "rod_quantities.hpp"
#include "restart.hpp"
#include "rod_setup.hpp"
#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/output/restart.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "run_rod_coupled.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/solver/rod_stepper.hpp"
#include "traverse/solver/rod_time_model.hpp"
#include "traverse/time/time_integrator.hpp"
#include "traverse/core/comm.hpp"
#include "traverse/version.hpp"
#include "solver_access.hpp"

namespace traverse::app {

namespace {

/// A load that crosses more than one cell per time step is resolved by the space grid but
/// not in time: the run goes on (it converges as dt falls), with a warning naming the keys.
void warn_under_resolved_loads(const scene::Scene& sc, const TimeGrid& g) {
  const double ds = sc.mesh.ds;
  for (const auto& l : sc.loads) {
    const double t_leave = std::min(g.t_end, l.exit_time(sc.rod.length));
    const double v = std::max(std::abs(l.velocity(l.entry_time)), std::abs(l.velocity(std::max(l.entry_time, t_leave))));
    if (v > 0.0 && g.dt * v > ds * (1.0 + 1e-9))
      std::fprintf(stderr,
                   "traverse: warning: %s: time.dt = %.6g s moves load '%s' (up to %.6g m/s) %.3g cells per step "
                   "(mesh.ds = %.6g m): its path is under-resolved in time (time.dt: auto gives ds / v)\n",
                   sc.file.c_str(), g.dt, l.name.c_str(), v, g.dt * v / ds, ds);
  }
}

/// The outputs of a rod run: the scene's probes and fields plus each load's position,
/// declared in the output file and evaluated at an output step.
class RodOutputs {
 public:
  RodOutputs(const scene::Scene& sc, const rod::RodModel& model, const solver::RodStepper& st, MPI_Comm comm);
  /// Names as the output file holds them, in declaration order (a restart's copy).
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const;
  output::NodeLayout layout() const;
  void declare(output::Writer& w) const;
  void write(output::Writer& w, double t, const Vec3& r0);

 private:
  void evaluate_probes(const std::vector<rod::RodNode>& near, const std::vector<Vec3>& near_r);
  void evaluate_fields(const std::vector<Vec3>& r);
  std::vector<Vec3> owned_centreline(const Vec3& r0) const;
  std::vector<Vec3> near_positions(const std::vector<Vec3>& r) const;
  const scene::Scene& sc_;
  const rod::RodModel& model_;
  const solver::RodStepper& st_;
  MPI_Comm comm_;
  int num_cells_, first_, count_;
  rod::OutputNeeds needs_;
  std::vector<std::vector<double>> probe_values_, field_values_;
  std::vector<double> sigma_;
};

RodOutputs::RodOutputs(const scene::Scene& sc, const rod::RodModel& model, const solver::RodStepper& st,
                       MPI_Comm comm)
    : sc_(sc), model_(model), st_(st), comm_(comm), num_cells_(sc.mesh.nodes - 1), first_(st.first_owned_node()),
      count_(st.num_owned_nodes()) {
  // What the outputs read at an output step: the nodes around the probes, and the centreline
  // (each rank its own nodes) only for a position probe or the field r.
  std::vector<rod::PointOutput> points;
  for (const auto& pr : sc.output.probes) points.push_back({pr.at, pr.quantity == scene::Quantity::position});
  bool r_field = false;
  for (const auto f : sc.output.fields) r_field = r_field || f == scene::Field::r;
  needs_ = rod::output_needs(num_cells_, sc.mesh.ds, points, r_field);
  probe_values_.assign(sc.output.probes.size() + sc.loads.size(), std::vector<double>(1));
  for (size_t i = 0; i < sc.output.probes.size(); ++i) probe_values_[i].assign(3, 0.0);
  field_values_.resize(sc.output.fields.size());
  sigma_.assign(std::max<size_t>(1, sc.loads.size()), std::numeric_limits<double>::quiet_NaN());
}

std::vector<std::string> RodOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const auto& l : sc_.loads) names.push_back(l.name + "_position");
  return names;
}

std::vector<std::string> RodOutputs::field_names() const {
  std::vector<std::string> names;
  for (const auto f : sc_.output.fields) names.push_back(scene::name_of(f));
  return names;
}

output::NodeLayout RodOutputs::layout() const {
  output::NodeLayout layout;
  layout.global_count = static_cast<size_t>(num_cells_ + 1);
  layout.first = static_cast<size_t>(first_);
  layout.count = static_cast<size_t>(count_);
  for (int k = 0; k < count_; ++k) layout.s.push_back((first_ + k) * sc_.mesh.ds);
  return layout;
}

void RodOutputs::declare(output::Writer& w) const {
  declare_rod_probes(w, sc_.output.probes);
  for (const auto& l : sc_.loads)
    w.add_probe({l.name + "_position", 1, "m", "arclength sigma(t) of load '" + l.name + "'", {}});
  for (const auto f : sc_.output.fields) {
    const RodFieldInfo fi = rod_field_info(f);
    w.add_field({scene::name_of(f), fi.components, fi.units, fi.description, fi.component_names, fi.geometry});
  }
}

void RodOutputs::evaluate_probes(const std::vector<rod::RodNode>& near, const std::vector<Vec3>& near_r) {
  auto view = [&](int j) {
    const auto i = static_cast<size_t>(std::lower_bound(needs_.nodes.begin(), needs_.nodes.end(), j) - needs_.nodes.begin());
    return node_view(near[i], near_r.empty() ? Vec3::Zero() : near_r[i]);
  };
  for (size_t i = 0; i < sc_.output.probes.size(); ++i) {
    const auto& pr = sc_.output.probes[i];
    const Vec3 v = quantity_at(pr.quantity, pr.at, sc_.mesh.ds, num_cells_, model_.props, pr.frame, view);
    probe_values_[i].assign(v.data(), v.data() + 3);
  }
}

void RodOutputs::evaluate_fields(const std::vector<Vec3>& r) {
  for (size_t f = 0; f < sc_.output.fields.size(); ++f) {
    const scene::Field field = sc_.output.fields[f];
    auto& out = field_values_[f];
    const size_t comps = rod_field_info(field).components;
    out.resize(comps * static_cast<size_t>(count_));
    for (int k = 0; k < count_; ++k) {
      const Vec3 p = field == scene::Field::r ? r[static_cast<size_t>(k)] : Vec3::Zero();
      field_values(field, node_view(st_.owned_node(k), p), model_.props, out.data() + comps * static_cast<size_t>(k));
    }
  }
}

// The centreline at this rank's nodes from r(0) = r0: each rank sums up its piece, the
// summaries of all ranks give each its start (rod::centreline_starts), and it integrates its
// own nodes from there.
std::vector<Vec3> RodOutputs::owned_centreline(const Vec3& r0) const {
  std::vector<Vec3> t(static_cast<size_t>(count_));
  for (int k = 0; k < count_; ++k) t[static_cast<size_t>(k)] = rod::tangent(st_.owned_node(k), model_.props);
  const rod::CentrelinePiece mine = rod::centreline_piece(t, first_, model_.ds(), first_ == 0 ? r0 : Vec3::Zero());
  const int rank = par::rank(comm_);
  std::vector<rod::CentrelinePiece> all(static_cast<size_t>(par::size(comm_)));
  par::allgather_bytes(&mine, sizeof mine, all.data(), comm_);
  return rod::centreline_from(t, model_.ds(), rod::centreline_starts(all, model_.ds(), r0)[static_cast<size_t>(rank)]);
}

// r at the nodes the probes read (needs_.nodes), on every rank, from their owners' `r`.
std::vector<Vec3> RodOutputs::near_positions(const std::vector<Vec3>& r) const {
  const std::vector<int>& wanted = needs_.nodes;
  std::vector<double> local(3 * wanted.size(), 0.0), all(local.size());
  for (size_t i = 0; i < wanted.size(); ++i)
    if (wanted[i] >= first_ && wanted[i] < first_ + count_) {
      const Vec3& p = r[static_cast<size_t>(wanted[i] - first_)];
      std::copy(p.data(), p.data() + 3, &local[3 * i]);
    }
  par::allreduce(local.data(), all.data(), static_cast<int>(local.size()), MPI_DOUBLE, MPI_SUM, comm_);
  std::vector<Vec3> out(wanted.size());
  for (size_t i = 0; i < wanted.size(); ++i) out[i] = Vec3(all[3 * i], all[3 * i + 1], all[3 * i + 2]);
  return out;
}

void RodOutputs::write(output::Writer& w, double t, const Vec3& r0) {
  std::vector<Vec3> r, near_r;     // r at the owned nodes and at needs_.nodes (with the centreline)
  std::vector<rod::RodNode> near;  // needs_.nodes
  if (needs_.centreline) r = owned_centreline(r0);
  if (!needs_.nodes.empty()) {
    near = gather_nodes(st_, needs_.nodes, comm_);
    if (needs_.centreline) near_r = near_positions(r);
  }
  evaluate_probes(near, near_r);
  for (size_t i = 0; i < sc_.loads.size(); ++i) {
    sigma_[i] = sc_.loads[i].sigma(t);
    probe_values_[sc_.output.probes.size() + i][0] = sigma_[i];
  }
  evaluate_fields(r);
  std::vector<output::DoubleView> views(field_values_.begin(), field_values_.end());
  w.write_step(t, sigma_, probe_values_, views);
}

/// Values per node of a rod run's restart point: the node, and with time.adaptive the
/// controller's two earlier levels.
std::size_t restart_components(const scene::Scene& sc) {
  return rod::kPackedNodeValues + (sc.time.adaptive.enabled ? solver::RodErrorEstimate::kPerNode : 0);
}

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

/// The message of a failed fixed step: where and why, and what to try. A step far shorter
/// than the time a bending wave needs to cross a cell cannot converge by shortening it: the
/// residual's 1/dt terms round above the absolute residual tolerance.
std::string explain_step_failure(const std::string& where, const solver::StepFailure& e, const rod::RodModel& model,
                                 const TimeGrid& g, const LoadRatio& load) {
  std::ostringstream os;
  os << where << " (t = " << e.time() << " s, dt = " << e.step() << " s) failed after halving it " << e.depth()
     << " times: " << e.report().status << " (residual ";
  // A norm is >= 0: NOX reports a non-finite residual as a huge negative number.
  const double residual = e.report().residual_norm;
  if (residual >= 0.0 && std::isfinite(residual)) os << residual;
  else os << "not finite";
  os << "); ";
  const double ds = model.ds(), cell_time = ds * ds * std::sqrt(model.props.rhoA / model.props.bending_stiffness());
  const double h = e.step();
  // The step is time.dt, or the last one, shortened to end at time.end.
  const bool last = std::abs(e.time() + h - g.t_end) <= 1e-9 * g.dt && h < g.dt * (1.0 - 1e-6);
  if (h < 1e-6 * cell_time) {
    os << (last ? "the last step, to time.end = " + scene::format_number(g.t_end) + " s, is "
                : "time.dt = " + scene::format_number(g.dt) + " s is ")
       << cell_time / h << " times shorter than a bending wave needs to cross a cell (mesh.ds^2 sqrt(rho A / (E I)) = "
       << cell_time << " s), where the rounding of the 1/dt terms keeps the residual above 'Residual Tolerance': try "
       << (!last ? "a larger time.dt (auto: mesh.ds / the fastest loads.*.speed)"
           : g.steps == 1 ? "a larger time.end" : "a time.end that is a whole number of time.dt steps")
       << " or a larger 'Residual Tolerance' in solver";
  } else {
    os << "try scheme.rho_inf < 1, a smaller time.dt, or a larger 'Max Subdivision Depth' in solver";
  }
  // A load the rod can hardly carry: say so, with the keys (the static start's criterion).
  if (load.ratio > 1e5)
    os << "; the load ratio W L^2 / (E I) = " << load.ratio << " is large (W = " << load.W << " N from " << load.what
       << ", E I = " << load.EI << " N m^2 from rod.youngs_modulus and rod.section): a smaller load or a stiffer rod "
       << "may be needed";
  return os.str();
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
  const std::size_t comps = restart_components(sc);
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

/// The adaptive steps' error estimate of a run: from the restart point when restarting (the
/// controller's state into `controller`), else started at the current (initial) level.
std::unique_ptr<solver::RodErrorEstimate> make_estimate(const scene::Scene& sc, const rod::RodModel& model,
                                                        const solver::RodStepper& st, const RestartSource& restart,
                                                        MPI_Comm comm, std::optional<time::ControllerState>& controller) {
  using solver::RodErrorEstimate;
  auto est = std::make_unique<RodErrorEstimate>(error_weights(sc.time.adaptive, model.length), model.alpha, comm);
  if (restart.file.empty()) {
    est->start(solver::owned_levels(st));
    return est;
  }
  const auto& x = restart.point.extra;
  const std::size_t comps = restart_components(sc), first = static_cast<std::size_t>(st.first_owned_node());
  std::vector<double> per_node(RodErrorEstimate::kPerNode * static_cast<std::size_t>(st.num_owned_nodes()));
  for (std::size_t k = 0; k < static_cast<std::size_t>(st.num_owned_nodes()); ++k)
    for (std::size_t i = 0; i < RodErrorEstimate::kPerNode; ++i)
      per_node[RodErrorEstimate::kPerNode * k + i] = restart.point.state[comps * (first + k) + rod::kPackedNodeValues + i];
  controller = est->restore(solver::owned_levels(st), per_node,
                            std::vector<double>(x.begin() + std::min<std::size_t>(5, x.size()), x.end()));
  return est;
}

// What the stepper would refuse about its linear solver, found before anything is allocated.
void check_linear_solver(const scene::Scene& sc, const RodSetup& setup, MPI_Comm comm) {
  const int ranks = par::size(comm);
  try {
    solver::LinearSolverChoice::resolve(setup.solver, ranks, solver::LinearSolverChoice::Use::time_step);
  } catch (const std::invalid_argument& e) {
    linear_solver_refused(sc, ranks, e);
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
long start_outputs(const RunOptions& opt, const RestartSource& restart, RodOutputs& outputs, output::Writer& writer,
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
  const RodSetup setup = build_rod_model(sc);
  if (coupled_load(sc)) check_coupled_rod(sc, setup.model);
  precheck_planar(sc, setup.model);
}

void run_rod(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  const int rank = par::rank(comm);
  const RodSetup setup = build_rod_model(sc);
  // Kokkos lives from the first rod run of the process to the process's end
  // (finish_solver_runtime), Tpetra for this run only.
  const TpetraScope tpetra(comm);

  // Model, limits and stepper first: the limits (steps, memory, load ratio: run_limits.hpp),
  // the partition (ranks <= nodes), the linear solver and a required planar path are bad
  // input (exit 2), found before anything of the rod's size is allocated and before any
  // initial state is computed.
  const TimeGrid grid = check_rod_run(sc, setup.model, opt.limits, comm).grid;
  check_linear_solver(sc, setup, comm);
  if (coupled_load(sc)) {
    run_rod_coupled(sc, setup, grid, opt, comm);
    return;
  }
  if (!opt.restart) precheck_planar(sc, setup.model);

  // The initial state before the stepper: the static solve's matrices are freed before the
  // stepper allocates its own, so the peak memory is the larger of the two, not their sum.
  InitialState start;
  RestartSource restart;
  if (opt.restart) {
    start.description = "restart";
    restart = read_restart(sc, opt, grid, start.state);
  } else {
    start = initial_state(sc, setup, comm);
  }
  auto stepper = make_stepper(sc, setup, comm);
  stepper->set_state(start.state, start.first_node);

  // Path: the planar fast path or the 3D system (docs/solver.md); a restart keeps the path
  // of the run it continues (restart extra[4]: 1 planar, 0 3D).
  const auto& extra = restart.point.extra;
  const int stored_path = opt.restart && extra.size() >= 5 ? (extra[4] != 0.0 ? 1 : 0) : -1;
  start.state = rod::RodState();  // the stepper holds its own copy
  const PathChoice path = choose_path(sc, setup.model, *stepper, stored_path, comm);
  if (path.planar) stepper->set_planar(&path.symmetry);
  const std::string path_text = stepper->path_description() + "; " + path.detail;

  RodOutputs outputs(sc, setup.model, *stepper, comm);
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
  if (sc.time.adaptive.enabled) estimate = make_estimate(sc, setup.model, *stepper, restart, comm, controller);
  RodRestartPoints points(*stepper, writer, grid.dt, path.planar, estimate.get(), comm);
  std::function<double(double)> kinks;  // adaptive steps land on the loads' node crossings
  if (sc.time.adaptive.land_on_nodes)
    kinks = [&](double t) { return next_node_crossing(sc.loads, t, setup.model.ds(), setup.model.length); };
  solver::RodTimeModel model(*stepper, left, estimate.get(), kinks);
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", stepper->time(), grid.t_end,
                    opt.progress_interval);
  const LoadRatio load = load_ratio(sc);
  RunObserver observer({[&] { outputs.write(writer, stepper->time(), left.position()); },
                        [&](long i) { points.store(i, left.position()); }, [&] { return stepper->time(); },
                        [&](const std::string& where, const time::StepFailed& e) {
                          const auto* f = dynamic_cast<const solver::StepFailure*>(&e);
                          return f ? explain_step_failure(where, *f, setup.model, grid, load) : where + ": " + e.what();
                        }},
                       writer, opt, progress, comm);
  time::TimeIntegrator integrator(rod_schedule(sc, grid), model, observer);
  points.integrator = &integrator;
  if (controller) integrator.restore(*controller);
  if (rank == 0 && !opt.quiet) print_start(sc, grid, start.description, *stepper, path_text, opt.verbose);
  if (rank == 0 && !estimate) warn_under_resolved_loads(sc, grid);
  const long first_step = start_outputs(opt, restart, outputs, writer, points, *stepper, left, comm);
  const auto wall = std::chrono::steady_clock::now();
  integrator.run(first_step);
  progress.done();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
  points.store(integrator.last_step(), left.position());  // the end (a no-op when the last output step stored it)
  if (estimate) write_adaptive_totals(writer, integrator.totals());
  writer.finish();
  if (rank == 0 && !opt.quiet) print_done(model.counts(), path.planar, writer, opt.output, seconds, estimate ? &integrator : nullptr,
                                         opt.verbose);
}

}  // namespace traverse::app

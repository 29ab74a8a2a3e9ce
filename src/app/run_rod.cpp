// Scene -> rod::RodModel, initial state, the distributed time stepper, and the output.
#include <mpi.h>

#include <Teuchos_DefaultMpiComm.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include "interrupt.hpp"
#include "progress.hpp"
#include "rod_setup.hpp"
#include "restart.hpp"
#include "run.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/rod/static_solver.hpp"
#include "traverse/solver/distributed_stepper.hpp"
#include "traverse/solver/solver_parameters.hpp"
#include "traverse/version.hpp"

namespace traverse::app {

namespace {

// A load is on the structure at time t when it has started and lies in [0, L].
double load_sigma(const scene::MovingLoadSpec& l, double t) {
  return t < l.entry_time ? std::numeric_limits<double>::quiet_NaN() : l.position(t);
}


// Value of a probe quantity at one node (3 components).
Vec3 node_quantity(const rod::RodNode& nd, const Vec3& r, const rod::RodProperties& props, const std::string& q,
                   bool fixed) {
  Vec3 v;
  if (q == "position") return r;
  if (q == "d1") return nd.R.row(0).transpose();
  if (q == "d2") return nd.R.row(1).transpose();
  if (q == "d3") return nd.R.row(2).transpose();
  if (q == "u") v = nd.y.segment<3>(rod::var::u);
  else if (q == "omega") v = nd.y.segment<3>(rod::var::omega);
  else if (q == "kappa") v = nd.y.segment<3>(rod::var::kappa);
  else if (q == "n") v = nd.y.segment<3>(rod::var::n);
  else if (q == "m") v = props.K.cwiseProduct(nd.y.segment<3>(rod::var::kappa) - props.kappa0);
  else throw std::logic_error("run_rod: unknown probe quantity " + q);
  return fixed ? Vec3(nd.R.transpose() * v) : v;
}

// Restart packing of one node: y (12), R row-major (9), yt (12), ys (12).
constexpr std::size_t kPackedNode = 45;
void pack_node(const rod::RodNode& nd, double* o) {
  for (int i = 0; i < 12; ++i) o[i] = nd.y(i);
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c) o[12 + 3 * i + c] = nd.R(i, c);
  for (int i = 0; i < 12; ++i) o[21 + i] = nd.yt(i);
  for (int i = 0; i < 12; ++i) o[33 + i] = nd.ys(i);
}
rod::RodNode unpack_node(const double* o) {
  rod::RodNode nd;
  for (int i = 0; i < 12; ++i) nd.y(i) = o[i];
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c) nd.R(i, c) = o[12 + 3 * i + c];
  for (int i = 0; i < 12; ++i) nd.yt(i) = o[21 + i];
  for (int i = 0; i < 12; ++i) nd.ys(i) = o[33 + i];
  return nd;
}

/// The global nodes `wanted` of the distributed state, on every rank (each rank packs the
/// ones it owns; one sum-reduction of wanted.size() nodes, as gather_state does for all).
std::vector<rod::RodNode> gather_nodes(const solver::DistributedStepper& st, const std::vector<int>& wanted,
                                       MPI_Comm comm) {
  const int first = st.first_owned_node(), count = st.num_owned_nodes();
  std::vector<double> local(kPackedNode * wanted.size(), 0.0), all(local.size());
  for (size_t i = 0; i < wanted.size(); ++i)
    if (wanted[i] >= first && wanted[i] < first + count) pack_node(st.owned_node(wanted[i] - first), &local[kPackedNode * i]);
  MPI_Allreduce(local.data(), all.data(), static_cast<int>(local.size()), MPI_DOUBLE, MPI_SUM, comm);
  std::vector<rod::RodNode> out(wanted.size());
  for (size_t i = 0; i < wanted.size(); ++i) out[i] = unpack_node(&all[kPackedNode * i]);
  return out;
}

/// The rod model of a scene, with its solver parameters validated; throws SceneError.
rod::RodModel build_rod_model(const scene::Scene& sc, Teuchos::ParameterList& solver_params) {
  const auto& rs = sc.rod;
  const int N = sc.mesh.nodes - 1;
  try {
    solver_params = solver::validated_solver_parameters(sc.solver_parameters());
  } catch (const std::invalid_argument& e) {
    scene::fail_at(sc, "solver", "valid solver parameters (see docs/solver.md)", e.what());
  }
  rod::RodModel model;
  model.props = rod_properties(rs);
  if (sc.scheme.explicit_parameters) {
    model.alpha = {sc.scheme.as, sc.scheme.bs, sc.scheme.gs, sc.scheme.at, sc.scheme.bt, sc.scheme.gt};
  } else {
    model.alpha = rod::AlphaParameters::from_rho_inf(sc.scheme.rho_inf, sc.scheme.rho_inf_space);
  }
  model.num_cells = N;
  model.length = rs.length;
  model.left = rod_end(sc.left);
  model.right = rod_end(sc.right);
  const auto check = rod::validate_end_conditions(model.left, model.right);
  if (!check.ok) scene::fail_at(sc, "ends", "a well-posed pair of end conditions", check.message);
  model.loads.gravity = Vec3(0.0, -sc.gravity, 0.0);
  for (const auto& l : sc.loads) {
    auto sigma = [l](double t) { return load_sigma(l, t); };
    if (l.inertia) {
      rod::MovingMass m;
      m.mass = l.mass;
      m.sigma = sigma;
      m.speed = [l](double t) { return l.velocity(t); };
      const double a = l.direction() * l.acceleration;
      m.accel = [a](double) { return a; };
      m.inertia = true;
      model.loads.masses.push_back(m);
    } else {
      const Vec3 F = l.force;
      model.loads.point_forces.push_back({[F](double) { return F; }, sigma});
    }
  }

  return model;
}

}  // namespace

void check_rod(const scene::Scene& sc) {
  Teuchos::ParameterList solver_params;
  const rod::RodModel model = build_rod_model(sc, solver_params);
  precheck_planar(sc, model);
}

void run_rod(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  // Kokkos and Tpetra live for this run only (beam runs never start them).
  int no_argc = 0;
  char** no_argv = nullptr;
  Tpetra::ScopeGuard tpetra(&no_argc, &no_argv, comm);
  const auto& rs = sc.rod;
  const int N = sc.mesh.nodes - 1;

  Teuchos::ParameterList solver_params;
  const rod::RodModel model = build_rod_model(sc, solver_params);

  // The stepper first: it checks the partition (ranks <= nodes) and the linear solver, which
  // are bad input (exit 2), before a static initial state is computed.
  auto tcomm = Teuchos::rcp(new Teuchos::MpiComm<int>(comm));
  std::unique_ptr<solver::DistributedStepper> stepper_ptr;
  try {
    stepper_ptr = std::make_unique<solver::DistributedStepper>(model, tcomm, solver_params);
  } catch (const std::invalid_argument& e) {
    scene::fail_at(sc, "solver", "a linear solver that is valid on " + std::to_string(tcomm->getSize()) + " rank(s)",
                   e.what());
  }
  // scheme.planar: on with a scene that cannot be planar is bad input, found before any
  // initial state is computed (the state itself is checked below).
  if (!opt.restart) precheck_planar(sc, model);

  // ---- Initial state -----------------------------------------------------------------
  rod::RodState state = rod::straight_rest_state(N, rs.length);
  std::string initial = "straight, at rest, unloaded";
  if (opt.restart) {
    initial = "restart";
  } else if (sc.initial_state.type == "static") {
    rod::StaticModel sm;
    sm.props = model.props;
    sm.num_cells = N;
    sm.length = rs.length;
    sm.left = static_end(sc.left, 0.0);
    sm.right = static_end(sc.right, rs.length);
    sm.gravity = model.loads.gravity;
    for (const auto& l : sc.loads) {
      const double s0 = load_sigma(l, 0.0);
      if (std::isfinite(s0) && s0 >= 0.0 && s0 <= rs.length) sm.point_forces.push_back({l.force, s0});
    }
    auto nodes = rod::straight_static_state(sm);
    const auto rep = rod::StaticSolver().solve_with_load_steps(sm, nodes);
    if (!rep.converged)
      throw NumericsError("initial static state: " + rep.message + " (residual " +
                          scene::format_number(rep.residual_norm) + " after " + std::to_string(rep.iterations) +
                          " Newton iterations)");
    state = rod::dynamic_state_from_static(sm, nodes);
    initial = "static equilibrium under gravity" + std::string(sm.point_forces.empty() ? "" : " and the loads on the rod at t = 0") +
              " (" + std::to_string(rep.load_steps) + " load steps, " + std::to_string(rep.iterations) + " Newton iterations)";
  } else if (sc.initial_state.type == "arch" || sc.initial_state.type == "file") {
    try {
      state = static_start(sc, Teuchos::rcp(new Teuchos::MpiComm<int>(comm)), solver_params, initial);
    } catch (const std::runtime_error& e) {
      if (dynamic_cast<const scene::SceneError*>(&e)) throw;
      throw NumericsError(std::string("initial state: ") + e.what());
    }
  }

  solver::DistributedStepper& stepper = *stepper_ptr;
  stepper.set_state(state);

  // ---- Time grid ---------------------------------------------------------------------
  double t_end = sc.time.end;
  if (sc.time.end_auto) {
    t_end = 0.0;
    for (const auto& l : sc.loads) t_end = std::max(t_end, l.exit_time(rs.length));
  }
  const double dt = sc.time.dt;
  // A remainder below 1e-6 dt is rounding of dt or of the end time, not a step: it joins the
  // last step (a sliver step of 1e-12 s makes the Newton matrix, with its 1/dt terms, useless).
  const long steps = std::max(1L, static_cast<long>(std::ceil(t_end / dt - 1e-6)));

  // ---- Restart point (docs/reliability.md): state, time, step index, left-end position --
  RestartPoint rp;
  std::string restart_from;
  if (opt.restart) {
    restart_from = restart_source(opt.output);
    rp = read_restart_point(restart_from, static_cast<std::size_t>(N + 1), kPackedNode);
    if (rp.extra.size() < 4 || rp.extra[3] != dt)
      throw UsageError{"--restart " + opt.output + ": time.dt = " + scene::format_number(dt) +
                       " s differs from the run being restarted (" +
                       (rp.extra.size() < 4 ? std::string("unknown") : scene::format_number(rp.extra[3])) +
                       " s); a restart keeps the time step"};
    state.t = rp.time;
    state.ds = rs.length / N;
    state.nodes.resize(static_cast<std::size_t>(N + 1));
    for (int j = 0; j <= N; ++j) state.nodes[static_cast<std::size_t>(j)] = unpack_node(&rp.state[kPackedNode * static_cast<std::size_t>(j)]);
    stepper.set_state(state);
  }

  // ---- Path: the planar fast path or the 3D system (docs/solver.md) ------------------------
  // A restart keeps the path of the run it continues (restart extra[4]: 1 planar, 0 3D).
  const int stored_path = opt.restart && rp.extra.size() >= 5 ? (rp.extra[4] != 0.0 ? 1 : 0) : -1;
  const PathChoice path = choose_path(sc, model, state, stored_path, comm);
  if (path.planar) stepper.set_planar(&path.symmetry);
  const std::string path_text = stepper.path_description() + "; " + path.detail;

  // ---- Output ------------------------------------------------------------------------
  const int first = stepper.first_owned_node(), count = stepper.num_owned_nodes();
  output::NodeLayout layout;
  layout.global_count = static_cast<size_t>(N + 1);
  layout.first = static_cast<size_t>(first);
  layout.count = static_cast<size_t>(count);
  for (int k = 0; k < count; ++k) layout.s.push_back((first + k) * sc.mesh.ds);
  // Names of the probes and fields, in declaration order (for a restart's copy).
  std::vector<std::string> probe_names, field_names = sc.output.fields;
  for (const auto& pr : sc.output.probes) probe_names.push_back(pr.name);
  for (const auto& l : sc.loads) probe_names.push_back(l.name + "_position");
  if (opt.restart) {
    check_restart_outputs(restart_from, probe_names, field_names);
    restart_from = move_aside_for_restart(opt.output, comm);
  }
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "rod", {}};
  info.attributes = {{"rod_path", path.planar ? "planar" : "3D"}, {"rod_path_detail", path_text}};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, layout,
                        std::max<size_t>(1, sc.loads.size()));

  const std::vector<std::string> xyz{"x", "y", "z"}, d123{"1", "2", "3"};
  // What the outputs read at an output step: the full state and the centreline only for a
  // position probe or the field r; otherwise just the nodes around the probes.
  std::vector<rod::PointOutput> points;
  for (const auto& pr : sc.output.probes) points.push_back({pr.at, pr.quantity});
  const rod::OutputNeeds needs = rod::output_needs(N, sc.mesh.ds, points, sc.output.fields);
  for (const auto& pr : sc.output.probes) {
    const bool fixed = pr.frame == "fixed";
    std::string units = pr.quantity == "position" ? "m" : pr.quantity == "u" ? "m/s" : pr.quantity == "omega" ? "rad/s"
                        : pr.quantity == "kappa" ? "1/m" : pr.quantity == "n" ? "N" : pr.quantity == "m" ? "N m" : "1";
    writer.add_probe({pr.name, 3, units,
                      pr.quantity + " at s = " + scene::format_number(pr.at) + " m, " +
                          (fixed ? "fixed-frame components (i, j, k)" : "body components (d1, d2, d3)"),
                      fixed ? xyz : d123});
  }
  for (const auto& l : sc.loads)
    writer.add_probe({l.name + "_position", 1, "m", "arclength sigma(t) of load '" + l.name + "'", {}});
  std::vector<std::string> fields = sc.output.fields;
  for (const auto& f : fields) {
    if (f == "u") writer.add_field({"u", 3, "m/s", "velocity, body components", d123, false});
    else if (f == "omega") writer.add_field({"omega", 3, "rad/s", "spin, body components", d123, false});
    else if (f == "kappa") writer.add_field({"kappa", 3, "1/m", "curvature and twist, body components", d123, false});
    else if (f == "n") writer.add_field({"n", 3, "N", "contact force, body components", d123, false});
    else if (f == "m") writer.add_field({"m", 3, "N m", "contact moment K (kappa - kappa0), body components", d123, false});
    else if (f == "r") {
      writer.add_field({"r", 3, "m", "centreline, fixed components", xyz, true});
    } else if (f == "R") {
      writer.add_field({"R", 9, "1", "orientation: rows d1, d2, d3 in fixed components",
                        {"d1x", "d1y", "d1z", "d2x", "d2y", "d2z", "d3x", "d3y", "d3z"}, false});
    } else {
      throw std::logic_error("run_rod: unknown field " + f);
    }
  }

  // Left-end position: fixed for ends that hold it, else integrated in time (trapezoidal).
  const bool left_moves = sc.left.type == "free" || sc.left.type == "sliding" || sc.left.type == "prescribed";
  Vec3 r0 = Vec3::Zero();
  if (opt.restart) r0 = Vec3(rp.extra[0], rp.extra[1], rp.extra[2]);
  auto node0_velocity = [&]() -> Vec3 {  // R^T u at node 0, broadcast from its owner
    Vec3 v = Vec3::Zero();
    if (first == 0) v = stepper.owned_node(0).R.transpose() * stepper.owned_node(0).y.segment<3>(rod::var::u);
    int owner = first == 0 ? rank : 0, root = 0;
    MPI_Allreduce(&owner, &root, 1, MPI_INT, MPI_MAX, comm);
    MPI_Bcast(v.data(), 3, MPI_DOUBLE, root, comm);
    return v;
  };

  std::vector<std::vector<double>> probe_values(sc.output.probes.size() + sc.loads.size(), std::vector<double>(1));
  for (size_t i = 0; i < sc.output.probes.size(); ++i) probe_values[i].assign(3, 0.0);
  std::vector<std::vector<double>> field_values(fields.size());
  std::vector<double> sigma(std::max<size_t>(1, sc.loads.size()), std::numeric_limits<double>::quiet_NaN());

  auto write = [&](double t) {
    rod::RodState full;
    std::vector<Vec3> r;
    std::vector<rod::RodNode> near;  // needs.nodes, when the full state is not gathered
    if (needs.centreline) {
      full = stepper.gather_state();
      r = rod::centreline_in_space(full, r0);
    } else if (!needs.nodes.empty()) {
      near = gather_nodes(stepper, needs.nodes, comm);
    }
    auto node = [&](int j) -> const rod::RodNode& {
      if (needs.centreline) return full.nodes[static_cast<size_t>(j)];
      const auto it = std::lower_bound(needs.nodes.begin(), needs.nodes.end(), j);
      return near[static_cast<size_t>(it - needs.nodes.begin())];
    };
    auto position = [&](int j) { return needs.centreline ? r[static_cast<size_t>(j)] : Vec3(Vec3::Zero()); };
    for (size_t i = 0; i < sc.output.probes.size(); ++i) {
      const auto& pr = sc.output.probes[i];
      const auto loc = rod::locate_on_nodes(pr.at, sc.mesh.ds, N);
      const auto& a = node(loc.j);
      const auto& b = node(loc.j + 1);
      const bool fixed = pr.frame == "fixed";
      const Vec3 v = (1.0 - loc.xi) * node_quantity(a, position(loc.j), model.props, pr.quantity, fixed) +
                     loc.xi * node_quantity(b, position(loc.j + 1), model.props, pr.quantity, fixed);
      probe_values[i].assign(v.data(), v.data() + 3);
    }
    for (size_t i = 0; i < sc.loads.size(); ++i) {
      sigma[i] = load_sigma(sc.loads[i], t);
      probe_values[sc.output.probes.size() + i][0] = sigma[i];
    }
    for (size_t f = 0; f < fields.size(); ++f) {
      auto& out = field_values[f];
      const std::string& name = fields[f];
      const size_t comps = name == "R" ? 9 : 3;
      out.resize(comps * static_cast<size_t>(count));
      for (int k = 0; k < count; ++k) {
        const auto& nd = stepper.owned_node(k);
        double* o = out.data() + comps * static_cast<size_t>(k);
        if (name == "r") {
          const Vec3& p = r[static_cast<size_t>(first + k)];
          std::copy(p.data(), p.data() + 3, o);
        } else if (name == "R") {
          for (int i = 0; i < 3; ++i)
            for (int c = 0; c < 3; ++c) o[3 * i + c] = nd.R(i, c);
        } else {
          const Vec3 v = node_quantity(nd, Vec3::Zero(), model.props, name, false);
          std::copy(v.data(), v.data() + 3, o);
        }
      }
    }
    std::vector<output::DoubleView> views(field_values.begin(), field_values.end());
    writer.write_step(t, sigma, probe_values, views);
  };

  RestartSlots restart_slots(comm, kPackedNode, static_cast<std::size_t>(first));
  std::vector<double> packed(kPackedNode * static_cast<std::size_t>(count));
  long stored_at = -1;  // time-step index of the newest restart point
  auto last_stored = std::chrono::steady_clock::now();
  auto store_restart = [&](long i) {
    if (i == stored_at) return;
    for (int k = 0; k < count; ++k) pack_node(stepper.owned_node(k), &packed[kPackedNode * static_cast<std::size_t>(k)]);
    restart_slots.write(writer, stepper.time(), i, {r0.x(), r0.y(), r0.z(), dt, path.planar ? 1.0 : 0.0}, packed);
    stored_at = i;
    last_stored = std::chrono::steady_clock::now();
  };
  // After an output step: a restart point if --restart-interval seconds have passed (rank 0's
  // clock decides for all ranks).
  auto restart_due = [&]() {
    if (opt.restart_interval <= 0.0) return true;
    int due = std::chrono::duration<double>(std::chrono::steady_clock::now() - last_stored).count() >=
              opt.restart_interval;
    MPI_Bcast(&due, 1, MPI_INT, 0, comm);
    return due != 0;
  };

  // ---- Run ---------------------------------------------------------------------------
  if (rank == 0 && !opt.quiet)
    std::printf("rod scene '%s': %d nodes, %ld steps of dt = %.6g s to t = %.6g s; initial state: %s; linear solver: %s%s; "
                "path: %s\n",
                sc.file.c_str(), N + 1, steps, dt, t_end, initial.c_str(), stepper.resolved_linear_solver().c_str(),
                stepper.linear_solver_rerouted() ? " (rerouted: Amesos2 gives wrong answers on 2+ ranks here)" : "",
                path_text.c_str());
  // A load that crosses more than one cell per time step is resolved by the space grid but
  // not in time: the run goes on (it converges as dt falls), with a warning naming the keys.
  if (rank == 0) {
    const double ds = sc.mesh.ds;
    for (const auto& l : sc.loads) {
      const double t_leave = std::min(t_end, l.exit_time(sc.mesh.ds * N));
      const double v = std::max(std::abs(l.velocity(l.entry_time)),
                                std::abs(l.velocity(std::max(l.entry_time, t_leave))));
      if (v > 0.0 && dt * v > ds * (1.0 + 1e-9))
        std::fprintf(stderr,
                     "traverse: warning: %s: time.dt = %.6g s moves load '%s' (up to %.6g m/s) %.3g cells per step "
                     "(mesh.ds = %.6g m): its path is under-resolved in time (time.dt: auto gives ds / v)\n",
                     sc.file.c_str(), dt, l.name.c_str(), v, dt * v / ds, ds);
    }
  }
  long first_step = 1;
  if (opt.restart) {
    copy_output_steps(restart_from, writer, rp.steps_written, probe_names, field_names,
                      static_cast<std::size_t>(first), static_cast<std::size_t>(count));
    store_restart(rp.step);
    remove_restart_source(opt.output, comm);
    first_step = rp.step + 1;
    if (rank == 0 && !opt.quiet)
      std::printf("restart from %s: time step %ld at t = %.9g s, %zu output steps kept\n", opt.output.c_str(),
                  rp.step, rp.time, rp.steps_written);
  } else {
    write(0.0);
    store_restart(0);
  }
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", stepper.time(), t_end);
  long newton = 0, substeps = 0;
  const auto stepping_start = std::chrono::steady_clock::now();
  for (long i = first_step; i <= steps; ++i) {
    const double t0 = stepper.time();
    const double h = i == steps ? t_end - t0 : dt;
    if (h <= 0.0) break;
    const Vec3 v_old = left_moves ? node0_velocity() : Vec3::Zero();
    try {
      const auto rep = stepper.step(h);
      newton += rep.newton_iterations;
      substeps += rep.substeps;
    } catch (const solver::StepFailure& e) {
      progress.done();
      std::ostringstream os;
      os << "time step " << i << " of " << steps << " (t = " << e.time() << " s, dt = " << e.step()
         << " s) failed after halving it " << e.depth() << " times: " << e.report().status
         << " (residual " << e.report().residual_norm
         << "); try scheme.rho_inf < 1, a smaller time.dt, or a larger 'Max Subdivision Depth' in solver"
         << " (traverse run --restart " << opt.output << " --set ... continues from t = " << t0 << " s)";
      store_restart(i - 1);  // the stepper kept the state before the failed step
      writer.fail(os.str());
      throw NumericsError(os.str());
    } catch (const solver::PlanarityLost& e) {
      progress.done();
      const std::string msg = "time step " + std::to_string(i) + " of " + std::to_string(steps) + ": " + e.what() +
                              "; traverse run --restart " + opt.output + " --set scheme.planar=off continues on the 3D path";
      store_restart(i - 1);
      writer.fail(msg);
      throw NumericsError(msg);
    }
    if (left_moves) r0 += 0.5 * h * (v_old + node0_velocity());
    if (i % sc.output.every == 0 || i == steps) {
      write(stepper.time());
      if (restart_due()) store_restart(i);
    }
    progress.update(stepper.time(), i);
    if (const int sig = i < steps ? interrupt_requested(comm) : 0) {
      progress.done();
      std::ostringstream os;
      os.precision(12);
      os << "interrupted at t = " << stepper.time() << " s (time step " << i << " of " << steps << ", "
         << signal_name(sig) << "); " << writer.steps_written() << " output steps written; continue with "
         << "traverse run --restart " << opt.output;
      store_restart(i);
      writer.fail(os.str());
      throw Interrupted(sig, opt.output, os.str(), os.str());
    }
  }
  progress.done();
  writer.finish();
  const double stepping = std::chrono::duration<double>(std::chrono::steady_clock::now() - stepping_start).count();
  if (rank == 0 && !opt.quiet)
    std::printf("done: %ld Newton iterations in %ld solves (%.2f per solve) on the %s path; %zu output steps -> %s; "
                "time stepping %.3f s (wall, output included)\n",
                newton, substeps, substeps ? double(newton) / double(substeps) : 0.0, path.planar ? "planar" : "3D",
                writer.steps_written(), opt.output.c_str(), stepping);
}

}  // namespace traverse::app

#include "traverse/setup/rod_setup.hpp"


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <utility>

#include "traverse/core/numerics_error.hpp"
#include "traverse/setup/run_checks.hpp"
#include "traverse/setup/run_limits.hpp"
#include "traverse/output/output_error.hpp"
#include "traverse/rod/static_load_steps.hpp"
#include "traverse/mesh/mesh.hpp"
#include "traverse/core/comm.hpp"
#include "traverse/setup/solver_access.hpp"
#include "traverse/solver/solver_parameters.hpp"

namespace traverse::setup {

rod::RodStrain rod_strain(scene::RodStrain s) {
  switch (s) {
    case scene::RodStrain::inextensible: return rod::RodStrain::inextensible;
    case scene::RodStrain::extensible: return rod::RodStrain::extensible;
    case scene::RodStrain::shearable: return rod::RodStrain::shearable;
    default: throw std::logic_error("rod_strain: unknown rod.model");
  }
}

rod::RodProperties rod_properties(const scene::RodSpec& r) {
  rod::RodProperties p;
  const auto& s = r.section;
  p.rhoA = r.density * s.area;
  p.rhoI = r.density * Vec3(s.I1, s.I2, s.J);
  p.K = Vec3(r.youngs_modulus * s.I1, r.youngs_modulus * s.I2, r.shear_modulus * s.J);
  p.kappa0 = r.intrinsic_curvature;
  // rod.model and rod.damping: the compliance of the strains and the Kelvin-Voigt viscosities.
  p.C = rod::RodProperties::compliance(rod_strain(r.strain), r.axial_stiffness, r.shear_stiffness);
  p.B_se = Vec3(r.damping_shear, r.damping_shear, r.damping_axial);
  p.B_bt = Vec3(r.damping_bending, r.damping_bending, r.damping_torsion);
  return p;
}

namespace {

rod::RodLoads rod_loads(const scene::Scene& sc) {
  rod::RodLoads loads;
  loads.gravity = Vec3(0.0, -sc.gravity, 0.0);
  for (const auto& l : sc.loads) {
    if (l.stepped_with_rod()) continue;  // rod::CoupledRodStepper adds its loads (run_rod_coupled.cpp)
    auto sigma = [l](double t) { return l.sigma(t); };
    if (l.inertia) {
      rod::MovingMass m;
      m.mass = l.mass;
      m.sigma = sigma;
      m.speed = [l](double t) { return l.velocity(t); };
      const double a = l.direction() * l.acceleration;
      m.accel = [a](double) { return a; };
      m.inertia = true;
      loads.masses.push_back(m);
    } else {
      const Vec3 F = l.force;
      loads.point_forces.push_back({[F](double) { return F; }, sigma});
    }
  }
  return loads;
}

std::string fmt4(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// What a failed static initial state says: how far the load stepping got, how the last
// Newton solve ended, the keys that set the load and the stiffness, and what to try.
std::string static_failure(const scene::Scene& sc, const rod::StaticModel& sm, const rod::StaticReport& rep) {
  std::string msg = "initial static state: no equilibrium found under the load: " + rep.message;
  if (rep.failed_factor > 0.0)
    msg += "; the last Newton solve, at load factor " + fmt4(rep.failed_factor) + ", stopped with max |residual| " +
           fmt4(rep.failed_residual) + " (the test is " + fmt4(rod::StaticTolerances().ftol * rep.failed_scale) +
           "): " + rep.failed_reason;
  msg += "; " + std::to_string(rep.iterations) + " Newton iterations in all. The load: ";
  std::string loads;
  double W = sm.props.rhoA * sc.gravity * sc.rod.length;
  for (const auto& l : sc.loads) {
    const double s0 = l.sigma(0.0);
    if (!(std::isfinite(s0) && s0 >= 0.0 && s0 <= sc.rod.length)) continue;
    loads += load_magnitude_key(sc, l) + " (" + fmt4(l.force.norm()) + " N), ";
    W = std::max(W, l.force.norm());
  }
  for (const auto* e : {&sc.left, &sc.right})
    if (e->type == scene::EndType::roller && e->axial_force != 0.0) {
      loads += std::string("ends.") + (e == &sc.left ? "left" : "right") + ".force (" + fmt4(e->axial_force) + " N), ";
      W = std::max(W, std::abs(e->axial_force));
    }
  const double EI = std::min(sm.props.K.x(), sm.props.K.y());
  msg += loads + "gravity = " + fmt4(sc.gravity) + " m/s^2 on rod.density and rod.section (a weight of " +
         fmt4(sm.props.rhoA * sc.gravity * sc.rod.length) + " N); the stiffness: rod.youngs_modulus = " +
         fmt4(sc.rod.youngs_modulus) + " Pa and rod.section (E I = " + fmt4(EI) + " N m^2, W L^2 / (E I) = " +
         fmt4(W / EI * sc.rod.length * sc.rod.length) +
         "). Try a smaller load, a stiffer rod, or initial_state: {type: rest} (the rod starts straight and at rest; "
         "the loads act from t = 0)";
  return msg;
}

}  // namespace

rod::RodState arch_dynamic_start(
    const scene::Scene& sc, const rod::StaticProblem& problem, const std::vector<rod::StaticNode>& state,
    const std::function<rod::StaticReport(const rod::StaticProblem&, std::vector<rod::StaticNode>&)>& solve,
    std::string& description) {
  // Without initial_state.loaded a load entering at a pinned end puts its force into the first
  // cell at once, a step that excites grid-scale waves the undamped scheme keeps.
  if (!sc.initial_state.loaded) return rod::dynamic_state_from_static(problem.model(), state);
  const auto loads = scene::prescribed_loads_at_start(sc);
  if (loads.size() != 1) throw std::logic_error("initial_state.loaded: the scene has not exactly one load at t = 0");
  const double sigma = loads.front()->sigma(0.0);
  rod::StaticProblem pr = problem;
  pr.set_point_load(loads.front()->force, sigma);
  std::vector<rod::StaticNode> loaded = state;
  const rod::StaticReport r = solve(pr, loaded);
  if (!r.converged) throw std::runtime_error("arch formation: the equilibrium with the load at t = 0: " + r.message);
  std::ostringstream os;
  os << "; in equilibrium with the load at s = " << sigma << " m (" << r.iterations << " Newton iterations)";
  description += os.str();
  return rod::dynamic_state_from_static(pr.model(), loaded);
}

std::string arch_scene_key(const scene::Scene& sc) {
  const auto& r = sc.rod;
  std::ostringstream os;
  os.precision(17);
  os << r.length << ' ' << r.youngs_modulus << ' ' << r.shear_modulus << ' ' << r.density << ' ' << r.section.area
     << ' ' << r.section.I1 << ' ' << r.section.I2 << ' ' << r.section.J << ' ' << r.intrinsic_curvature.transpose()
     << ' ' << sc.mesh.nodes << ' ' << sc.initial_state.end_to_end << ' ' << sc.gravity;
  return os.str();
}

namespace {

// Equilibrium under gravity and the loads on the rod at t = 0 (Newton with load steps) over
// the ranks; this rank's nodes first .. first + count - 1 of the dynamic state at rest.
InitialState static_equilibrium(const scene::Scene& sc, const RodSetup& setup, MPI_Comm comm) {
  const rod::RodModel& model = setup.model;
  const double L = sc.rod.length;
  rod::StaticModel sm;
  sm.props = model.props;
  sm.num_cells = model.num_cells;
  sm.length = L;
  sm.left = static_end(sc.left, 0.0);
  sm.right = static_end(sc.right, L);
  sm.gravity = model.loads.gravity;
  for (const auto& l : sc.loads) {
    const double s0 = l.sigma(0.0);
    if (std::isfinite(s0) && s0 >= 0.0 && s0 <= L) sm.point_forces.push_back({l.force, s0});
  }
  const solver::StaticStart st = distributed_static_start(sm, setup.solver, comm);
  if (!st.report.converged) throw NumericsError(static_failure(sc, sm, st.report));
  InitialState out;
  out.state = solver::dynamic_state_piece(sm, st, out.first_node);
  out.description = "static equilibrium under gravity" +
                    std::string(sm.point_forces.empty() ? "" : " and the loads on the rod at t = 0") + " (" +
                    std::to_string(st.report.load_steps) + " load steps, " + std::to_string(st.report.iterations) +
                    " Newton iterations)";
  return out;
}

}  // namespace

RodSetup build_rod_model(const scene::Scene& sc) {
  RodSetup out;
  try {
    out.solver = solver::checked_solver_parameters(sc.solver_parameters());
  } catch (const std::invalid_argument& e) {
    scene::fail_at(sc, "solver", "valid solver parameters (see docs/solver.md)", e.what());
  }
  rod::RodModel& model = out.model;
  model.props = rod_properties(sc.rod);
  const auto& sch = sc.scheme;
  model.alpha = sch.explicit_parameters ? rod::AlphaParameters{sch.as, sch.bs, sch.gs, sch.at, sch.bt, sch.gt}
                                        : rod::AlphaParameters::from_rho_inf(sch.rho_inf, sch.rho_inf_space);
  model.num_cells = sc.mesh.nodes - 1;
  model.length = sc.rod.length;
  model.left = rod_end(sc.left);
  model.right = rod_end(sc.right);
  const auto check = rod::validate_end_conditions(model.left, model.right);
  if (!check.ok) scene::fail_at(sc, "ends", "a well-posed pair of end conditions", check.message);
  model.loads = rod_loads(sc);
  return out;
}

InitialState initial_state(const scene::Scene& sc, const RodSetup& setup, MPI_Comm comm) {
  using T = scene::InitialStateType;
  switch (sc.initial_state.type) {
    case T::rest: {
      // This rank's nodes and their ghosts, as the stepper's mesh partitions the rod.
      const int rank = par::rank(comm), ranks = par::size(comm);
      const int N = setup.model.num_cells;
      const mesh::Partition part = mesh::partition_nodes(mesh::Mesh1D(setup.model.length, N + 1), ranks);
      const int owned = part.first[static_cast<size_t>(rank)], owned_count = part.count[static_cast<size_t>(rank)];
      const int first = std::max(0, owned - 1), count = std::min(N, owned + owned_count) - first + 1;
      InitialState out;  // every node alike: straight along k, at rest
      out.state.ds = setup.model.ds();
      out.state.nodes.assign(static_cast<size_t>(count), rod::RodNode{});
      out.first_node = first;
      out.description = "straight, at rest, unloaded";
      return out;
    }
    case T::static_equilibrium: return static_equilibrium(sc, setup, comm);
    case T::arch:
    case T::file: {
      InitialState out;
      try {
        // The arch's statics get the scene's solver section unfilled, as a statics run does:
        // their 2-rank default (GMRES + ILUT) applies only when no preconditioner is given
        // (docs/statics.md, "Methods"); the filled defaults' SCHWARZ fails there.
        if (sc.initial_state.type == T::arch)
          out.state = arch_start(sc, sc.solver_parameters(), comm, out.description);
        else
          out.state = file_start(sc, out.description);
      } catch (const std::runtime_error& e) {
        if (dynamic_cast<const scene::SceneError*>(&e)) throw;
        throw NumericsError(std::string("initial state: ") + e.what());
      }
      return out;
    }
    default: throw std::logic_error("initial_state: unknown type");
  }
}

rod::EndCondition rod_end(const scene::EndSpec& e) { return rod::end_condition(e); }

rod::StaticEnd static_end(const scene::EndSpec& e, double s_end) { return rod::static_end(e, Vec3(0.0, 0.0, s_end)); }

output::NodalState nodal_state(const std::vector<rod::StaticNode>& nodes) {
  output::NodalState st;
  for (const auto& nd : nodes) {
    const Mat3 R = nd.frame();
    for (int c = 0; c < 3; ++c) {
      st.r.push_back(nd.x(rod::svar::r + c));
      st.kappa.push_back(nd.x(rod::svar::kappa + c));
      st.n.push_back(nd.x(rod::svar::n + c));
    }
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 3; ++c) st.R.push_back(R(i, c));
  }
  return st;
}

std::vector<rod::StaticNode> static_nodes(const output::NodalState& st, const scene::Scene& sc, const std::string& key) {
  const size_t n = st.r.size() / 3;
  if (n != static_cast<size_t>(sc.mesh.nodes))
    scene::fail_at(sc, key, "a state with " + std::to_string(sc.mesh.nodes) + " nodes (the scene's mesh)",
                   "a state with " + std::to_string(n) + " nodes");
  std::vector<rod::StaticNode> nodes(n);
  for (size_t j = 0; j < n; ++j) {
    auto& nd = nodes[j];
    for (int c = 0; c < 3; ++c) {
      nd.x(rod::svar::r + c) = st.r[3 * j + c];
      nd.x(rod::svar::kappa + c) = st.kappa[3 * j + c];
      nd.x(rod::svar::n + c) = st.n[3 * j + c];
    }
    for (int i = 0; i < 3; ++i)
      for (int c = 0; c < 3; ++c) nd.Rbar(i, c) = st.R[9 * j + 3 * i + c];
  }
  return nodes;
}

rod::StaticProblem static_problem(const scene::Scene& sc) {
  rod::StaticProblem p;
  p.base.props = rod_properties(sc.rod);
  p.base.num_cells = sc.mesh.nodes - 1;
  p.base.length = sc.rod.length;
  p.base.left = static_end(sc.left, 0.0);
  p.base.right = static_end(sc.right, sc.rod.length);
  p.gravity = Vec3(0.0, -sc.gravity, 0.0);
  p.end_load_direction = -Vec3::UnitZ();
  p.end_position_axis = Vec3::UnitZ();
  p.value(rod::StaticParameter::gravity_factor) = 1.0;  // gravity = factor * the scene's g
  // The right end's external load along -k: a roller's or sliding end's given force.
  p.value(rod::StaticParameter::end_load) = -sc.right.axial_force;
  p.value(rod::StaticParameter::end_position) = sc.rod.length;
  if (sc.loads.size() == 1) {
    p.set_point_load(sc.loads.front().force, sc.loads.front().start);
  } else if (!sc.loads.empty()) {
    scene::fail_at(sc, "loads", "at most one load in a continuation scene", std::to_string(sc.loads.size()) + " loads");
  }
  return p;
}

rod::RodState file_start(const scene::Scene& sc, std::string& description) {
  std::vector<rod::StaticNode> nodes;
  try {
    nodes = static_nodes(output::read_state(sc.initial_state.file, sc.initial_state.state), sc, "initial_state.file");
  } catch (const output::OutputError& e) {
    scene::fail_at(sc, "initial_state.file", "a continuation file with the state '" + sc.initial_state.state + "'",
                   e.what());
  }
  description = "state '" + sc.initial_state.state + "' of " + sc.initial_state.file + ", at rest";
  return rod::dynamic_state_from_static(static_problem(sc).model(), nodes);
}

std::vector<Vec3> point_force_vectors(const scene::Scene& sc) {
  std::vector<Vec3> v;
  for (const auto& l : sc.loads)
    if (!l.inertia && !l.stepped_with_rod()) v.push_back(l.force);
  return v;
}

rod::PlanarCheck reference_state_planarity(const scene::Scene& sc, const rod::RodModel& model) {
  rod::RodModel small = model;
  small.num_cells = 2;
  return rod::check_planar(small, rod::straight_rest_state(2, model.length), point_force_vectors(sc));
}

void precheck_planar(const scene::Scene& sc, const rod::RodModel& model) {
  if (sc.scheme.planar != scene::PlanarMode::on) return;
  const rod::PlanarCheck c = reference_state_planarity(sc, model);
  if (!c.planar)
    scene::fail_at(sc, "scheme.planar",
                   "a planar scene for 'on' (rod, loads, gravity and end conditions symmetric about one plane; "
                   "use auto or off)",
                   "a scene that is not planar: " + c.reason);
}

std::vector<rod::RodNode> gather_nodes(const solver::RodStepper& st, const std::vector<int>& wanted, MPI_Comm comm) {
  constexpr std::size_t n = rod::kPackedNodeValues;
  const int first = st.first_owned_node(), count = st.num_owned_nodes();
  std::vector<double> local(n * wanted.size(), 0.0), all(local.size());
  for (size_t i = 0; i < wanted.size(); ++i)
    if (wanted[i] >= first && wanted[i] < first + count) rod::pack_node(st.owned_node(wanted[i] - first), &local[n * i]);
  par::allreduce(local.data(), all.data(), static_cast<int>(local.size()), MPI_DOUBLE, MPI_SUM, comm);
  std::vector<rod::RodNode> out(wanted.size());
  for (size_t i = 0; i < wanted.size(); ++i) out[i] = rod::unpack_node(&all[n * i]);
  return out;
}

namespace {

// Whether the stepper's state is planar: each rank sums up its owned nodes, the summaries are
// merged in rank (= node) order.
rod::PlanarCheck state_planarity(const scene::Scene& sc, const rod::RodModel& model,
                                 const solver::RodStepper& st, MPI_Comm comm) {
  const std::vector<rod::RodNode> ends = gather_nodes(st, {0, model.num_cells}, comm);
  const rod::RodNode& left = ends[0];
  const rod::RodNode& right = ends[1];
  rod::RodState piece;
  piece.t = st.time();
  for (int k = 0; k < st.num_owned_nodes(); ++k) piece.nodes.push_back(st.owned_node(k));
  const rod::PlanarStateSummary mine = rod::summarize_planarity(piece, st.first_owned_node(), left.R);
  std::vector<rod::PlanarStateSummary> all(static_cast<size_t>(par::size(comm)));
  par::allgather_bytes(&mine, sizeof mine, all.data(), comm);
  std::sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.first_node < b.first_node; });
  rod::PlanarStateSummary merged = all.front();
  for (size_t r = 1; r < all.size(); ++r) rod::merge(merged, all[r]);
  return rod::check_planar(model, merged, left, right, st.time(), point_force_vectors(sc));
}

}  // namespace

PathChoice choose_path(const scene::Scene& sc, const rod::RodModel& model, const solver::RodStepper& stepper,
                       int stored, MPI_Comm comm) {
  PathChoice out;
  const scene::PlanarMode mode = sc.scheme.planar;
  if (mode == scene::PlanarMode::off) {
    out.detail = "scheme.planar: off";
    return out;
  }
  const rod::PlanarCheck c = state_planarity(sc, model, stepper, comm);  // the same on every rank
  if (mode == scene::PlanarMode::on) {
    if (!c.planar)
      scene::fail_at(sc, "scheme.planar",
                     "a planar scene for 'on' (initial state, loads, gravity and end conditions symmetric about one "
                     "plane; use auto or off)",
                     "a scene whose initial state is not planar: " + c.reason);
    out.detail = "scheme.planar: on";
  } else if (mode == scene::PlanarMode::automatic) {
    if (stored == 0) {
      out.detail = "the path of the run being restarted (scheme.planar: auto)";
      return out;
    }
    if (stored == 1 && !c.planar)
      scene::fail_at(sc, "scheme.planar", "the planar path of the run being restarted, from a planar restart state",
                     "a restart state that is not planar: " + c.reason + " (restart with --set scheme.planar=off)");
    if (!c.planar) {
      out.detail = "not planar: " + c.reason;
      return out;
    }
    out.detail = stored == 1 ? "the path of the run being restarted (scheme.planar: auto)"
                             : "detected (scheme.planar: auto)";
  } else {
    throw std::logic_error("choose_path: scheme.planar " + scene::name_of(mode));
  }
  out.planar = true;
  out.symmetry = c.symmetry;
  return out;
}

[[noreturn]] void linear_solver_refused(const scene::Scene& sc, int ranks, const std::invalid_argument& e) {
  scene::fail_at(sc, "solver", "a linear solver that is valid on " + std::to_string(ranks) + " rank(s)", e.what());
}

std::unique_ptr<solver::RodStepper> make_stepper(const scene::Scene& sc, const RodSetup& setup, MPI_Comm comm) {
  const int ranks = par::size(comm);
  try {
    return distributed_stepper(setup.model, setup.solver, comm);
  } catch (const std::invalid_argument& e) {
    linear_solver_refused(sc, ranks, e);
  }
}

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


}  // namespace traverse::setup

#include "rod_setup.hpp"

#include <sstream>

#include "traverse/output/output_error.hpp"

namespace traverse::app {

rod::RodProperties rod_properties(const scene::RodSpec& r) {
  rod::RodProperties p;
  const auto& s = r.section;
  p.rhoA = r.density * s.area;
  p.rhoI = r.density * Vec3(s.I1, s.I2, s.J);
  p.K = Vec3(r.youngs_modulus * s.I1, r.youngs_modulus * s.I2, r.shear_modulus * s.J);
  p.kappa0 = r.intrinsic_curvature;
  return p;
}

rod::EndCondition rod_end(const scene::EndSpec& e) {
  if (e.type == "clamped") return rod::EndCondition::make_clamped();
  if (e.type == "pinned") return rod::EndCondition::make_pinned(e.axis);
  if (e.type == "sliding") return rod::EndCondition::make_sliding(e.axis);
  if (e.type == "roller") return rod::EndCondition::make_roller(e.axis, e.slide_axis, e.axial_force);
  if (e.type == "free") return rod::EndCondition::make_free();
  if (e.type == "prescribed") {
    const Vec3 v = e.velocity, w = e.rotation_rate;
    return rod::EndCondition::make_prescribed([v](double) { return v; }, [w](double) { return w; });
  }
  throw std::logic_error("rod_end: unknown end condition " + e.type);
}

rod::StaticEnd static_end(const scene::EndSpec& e, double s_end) {
  rod::StaticEnd s;
  s.position = Vec3(0.0, 0.0, s_end);
  s.axis = e.axis;
  s.slide_axis = e.slide_axis;
  s.axial_force = e.axial_force;
  using T = rod::EndCondition::Type;
  if (e.type == "clamped" || e.type == "prescribed") s.type = T::clamped;  // prescribed motion starts from rest
  else if (e.type == "pinned") s.type = T::pinned;
  else if (e.type == "sliding") s.type = T::sliding;
  else if (e.type == "roller") s.type = T::roller;
  else if (e.type == "free") s.type = T::free;
  else throw std::logic_error("static_end: unknown end condition " + e.type);
  return s;
}

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

solver::ArchFormation form_arch(const scene::Scene& sc, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                const Teuchos::ParameterList& solver_params) {
  solver::ArchOptions o;
  o.length = sc.rod.length;
  o.num_cells = sc.mesh.nodes - 1;
  o.end_distance = sc.initial_state.end_to_end;
  o.gravity = sc.gravity;
  o.solver = solver_params;
  solver::ArchFormation arch = solver::form_arch(rod_properties(sc.rod), o, comm);
  if (!arch.ok) throw std::runtime_error("arch formation: " + arch.message);
  return arch;
}

std::string arch_summary(const solver::ArchFormation& arch) {
  std::ostringstream os;
  os << "arch formed: Euler load " << arch.euler_load << " N; end load " << arch.forming_load
     << " N when the ends passed " << arch.problem.value(rod::StaticParameter::end_position)
     << " m apart, pinned there; gravity raised to " << -arch.problem.gravity.y() << " m/s^2";
  return os.str();
}

rod::RodState static_start(const scene::Scene& sc, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                           const Teuchos::ParameterList& solver, std::string& description) {
  const rod::StaticProblem problem = static_problem(sc);
  if (sc.initial_state.type == "arch") {
    const solver::ArchFormation arch = form_arch(sc, comm, solver);
    description = arch_summary(arch);
    return rod::dynamic_state_from_static(arch.problem.model(), arch.state);
  }
  if (sc.initial_state.type == "file") {
    std::vector<rod::StaticNode> nodes;
    try {
      nodes = static_nodes(output::read_state(sc.initial_state.file, sc.initial_state.state), sc, "initial_state.file");
    } catch (const output::OutputError& e) {
      scene::fail_at(sc, "initial_state.file", "a continuation file with the state '" + sc.initial_state.state + "'",
                     e.what());
    }
    description = "state '" + sc.initial_state.state + "' of " + sc.initial_state.file + ", at rest";
    return rod::dynamic_state_from_static(problem.model(), nodes);
  }
  throw std::logic_error("static_start: initial state " + sc.initial_state.type);
}

std::vector<Vec3> point_force_vectors(const scene::Scene& sc) {
  std::vector<Vec3> v;
  for (const auto& l : sc.loads)
    if (!l.inertia) v.push_back(l.force);
  return v;
}

void precheck_planar(const scene::Scene& sc, const rod::RodModel& model) {
  if (sc.scheme.planar != "on") return;
  const rod::PlanarCheck c =
      rod::check_planar(model, rod::straight_rest_state(model.num_cells, model.length), point_force_vectors(sc));
  if (!c.planar)
    scene::fail_at(sc, "scheme.planar",
                   "a planar scene for 'on' (rod, loads, gravity and end conditions symmetric about one plane; "
                   "use auto or off)",
                   "a scene that is not planar: " + c.reason);
}

PathChoice choose_path(const scene::Scene& sc, const rod::RodModel& model, const rod::RodState& state, int stored,
                       MPI_Comm comm) {
  PathChoice out;
  const std::string& mode = sc.scheme.planar;
  if (mode == "off") {
    out.detail = "scheme.planar: off";
    return out;
  }
  rod::PlanarCheck c = rod::check_planar(model, state, point_force_vectors(sc));
  int mine = c.planar ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, comm);
  if (mine && !all) {
    c.planar = false;
    c.reason = "another rank found the state not planar";
  }
  if (mode == "on") {
    if (!c.planar)
      scene::fail_at(sc, "scheme.planar",
                     "a planar scene for 'on' (initial state, loads, gravity and end conditions symmetric about one "
                     "plane; use auto or off)",
                     "a scene whose initial state is not planar: " + c.reason);
    out.detail = "scheme.planar: on";
  } else if (mode == "auto") {
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
    throw std::logic_error("choose_path: scheme.planar " + mode);
  }
  out.planar = true;
  out.symmetry = c.symmetry;
  return out;
}

}  // namespace traverse::app


// The static problems of a continuation scene (statics_setup.hpp).
#include "traverse/setup/statics_setup.hpp"

#include <stdexcept>

#include "traverse/core/numerics_error.hpp"
#include "traverse/output/continuation_writer.hpp"
#include "traverse/output/output_error.hpp"
#include "traverse/setup/arch_start.hpp"
#include "traverse/setup/rod_quantities.hpp"
#include "traverse/setup/rod_setup.hpp"
#include "traverse/solver/solver_parameters.hpp"

namespace traverse::setup {

/// A scalar probe of a static state from its scene declaration (the quantity table of
/// rod_quantities.hpp, one component).
rod::StaticProbe make_probe(const scene::ContinuationProbeSpec& p) {
  switch (p.type) {
    case scene::ContinuationProbeType::end_compression: return rod::probe_end_compression(Vec3::UnitZ(), p.name);
    case scene::ContinuationProbeType::point: {
      rod::StaticProbe q;
      q.name = p.name;
      q.unit = quantity_unit(p.quantity);
      q.eval = [p](const rod::StaticModel& m, const std::vector<rod::StaticNode>& nodes) {
        auto view = [&](int j) { return node_view(nodes[static_cast<size_t>(j)]); };
        return quantity_at(p.quantity, p.at, m.ds(), m.num_cells, m.props, p.frame, view)(p.component);
      };
      return q;
    }
    default: throw std::logic_error("make_probe: unknown continuation probe type");
  }
}

// The solver's parameter of a scene's continuation parameter.
rod::StaticParameter static_parameter(scene::ContinuationParameter p) {
  using C = scene::ContinuationParameter;
  switch (p) {
    case C::end_load: return rod::StaticParameter::end_load;
    case C::end_position: return rod::StaticParameter::end_position;
    case C::gravity_factor: return rod::StaticParameter::gravity_factor;
    case C::load_position: return rod::StaticParameter::load_position;
    case C::load_magnitude: return rod::StaticParameter::load_magnitude;
    default: throw std::logic_error("static_parameter: unknown continuation parameter");
  }
}

// The solver parameters, validated here for the error message and handed on as given, so
// that the statics' own default for 2+ ranks (GMRES + ILUT, see StaticContext) applies when
// the scene names no preconditioner (validation would fill in the dynamic default, Schwarz).
Teuchos::ParameterList statics_solver_parameters(const scene::Scene& sc) {
  const Teuchos::ParameterList solver_params = sc.solver_parameters();
  try {
    (void)solver::checked_solver_parameters(solver_params);
  } catch (const std::invalid_argument& e) {
    scene::fail_at(sc, "solver", "valid solver parameters (see docs/solver.md)", e.what());
  }
  return solver_params;
}

// The starting state of the continuation, from the scene's initial state; an arch start
// replaces the problem's ends and position by the formed arch's (the scene's load on top).
std::vector<rod::StaticNode> statics_start(const scene::Scene& sc, const Teuchos::ParameterList& solver_params,
                                           const Teuchos::RCP<const Teuchos::Comm<int>>& tcomm,
                                           rod::StaticProblem& problem, std::string& description) {
  switch (sc.initial_state.type) {
    case scene::InitialStateType::arch: {
      solver::ArchFormation arch;
      try {
        arch = form_arch(sc, tcomm, solver_params);
      } catch (const std::runtime_error& e) {
        throw NumericsError(e.what());
      }
      description = arch_summary(arch);
      const auto values = problem.values;
      const bool load = problem.has_point_load;
      const Vec3 direction = problem.load_direction;
      problem = arch.problem;
      problem.has_point_load = load;
      problem.load_direction = direction;
      for (auto p : {rod::StaticParameter::load_position, rod::StaticParameter::load_magnitude})
        problem.value(p) = values[static_cast<size_t>(p)];
      return arch.state;
    }
    case scene::InitialStateType::file:
      try {
        return static_nodes(output::read_state(sc.initial_state.file, sc.initial_state.state), sc, "initial_state.file");
      } catch (const output::OutputError& e) {
        scene::fail_at(sc, "initial_state.file", "a continuation file with the state '" + sc.initial_state.state + "'",
                       e.what());
      }
    default: return rod::straight_static_state(problem.base);
  }
}

solver::ContinuationOptions continuation_options(const scene::ContinuationSpec& cs, rod::StaticParameter par, double start,
                                                 const Teuchos::ParameterList& solver_params) {
  solver::ContinuationOptions options;
  options.parameter = par;
  options.method = cs.method == scene::ContinuationMethod::natural ? "Natural" : "Arc Length";
  options.min_value = std::min(start, cs.stop);
  options.max_value = std::max(start, cs.stop);
  options.initial_step = cs.stop > start ? cs.step : -cs.step;
  options.min_step = cs.min_step;
  options.max_step = cs.max_step;
  options.max_steps = cs.max_steps;
  options.stability.enabled = cs.stability;
  options.stability.num_eigenvalues = cs.eigenvalues;
  options.detect_bifurcations = cs.stability;
  options.solver = solver_params;
  for (const auto& p : cs.probes) options.probes.push_back(make_probe(p));
  return options;
}

}  // namespace traverse::setup

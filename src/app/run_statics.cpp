// A rod scene with a `continuation` section: continuation of static states with stability,
// bifurcation detection and branch switching, written to a continuation file.
#include <mpi.h>

#include <Teuchos_DefaultMpiComm.hpp>

#include <cmath>
#include <sstream>

#include "arch_start.hpp"
#include "progress.hpp"
#include "rod_quantities.hpp"
#include "rod_setup.hpp"
#include "run.hpp"
#include "traverse/output/continuation_writer.hpp"
#include "traverse/output/output_error.hpp"
#include "traverse/solver/solver_parameters.hpp"
#include "traverse/solver/static_continuation.hpp"
#include "traverse/version.hpp"
#include "solver_access.hpp"

namespace traverse::app {

namespace {

using rod::StaticParameter;

// A scalar probe of a static state from its scene declaration (the quantity table of
// rod_quantities.hpp, one component).
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
StaticParameter static_parameter(scene::ContinuationParameter p) {
  using C = scene::ContinuationParameter;
  switch (p) {
    case C::end_load: return StaticParameter::end_load;
    case C::end_position: return StaticParameter::end_position;
    case C::gravity_factor: return StaticParameter::gravity_factor;
    case C::load_position: return StaticParameter::load_position;
    case C::load_magnitude: return StaticParameter::load_magnitude;
    default: throw std::logic_error("static_parameter: unknown continuation parameter");
  }
}

}  // namespace

namespace {

// The solver parameters, validated here for the error message and handed on as given, so
// that the statics' own default for 2+ ranks (GMRES + ILUT, see StaticContext) applies when
// the scene names no preconditioner (validation would fill in the dynamic default, Schwarz).
Teuchos::ParameterList statics_solver_parameters(const scene::Scene& sc) {
  const Teuchos::ParameterList solver_params = sc.solver_parameters();
  try {
    (void)solver::validated_solver_parameters(solver_params);
  } catch (const std::invalid_argument& e) {
    scene::fail_at(sc, "solver", "valid solver parameters (see docs/solver.md)", e.what());
  }
  return solver_params;
}

// The starting state of the continuation, from the scene's initial state; an arch start
// replaces the problem's ends and position by the formed arch's (the scene's load on top).
std::vector<rod::StaticNode> statics_start(const scene::Scene& sc, const Teuchos::ParameterList& solver_params,
                                           const Teuchos::RCP<const Teuchos::Comm<int>>& tcomm, bool report,
                                           rod::StaticProblem& problem) {
  switch (sc.initial_state.type) {
    case scene::InitialStateType::arch: {
      solver::ArchFormation arch;
      try {
        arch = form_arch(sc, tcomm, solver_params);
      } catch (const std::runtime_error& e) {
        throw NumericsError(e.what());
      }
      if (report) std::printf("%s\n", arch_summary(arch).c_str());
      const auto values = problem.values;
      const bool load = problem.has_point_load;
      const Vec3 direction = problem.load_direction;
      problem = arch.problem;
      problem.has_point_load = load;
      problem.load_direction = direction;
      for (auto p : {StaticParameter::load_position, StaticParameter::load_magnitude})
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

solver::ContinuationOptions continuation_options(const scene::ContinuationSpec& cs, StaticParameter par, double start,
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

output::ContinuationWriter continuation_writer(const scene::Scene& sc, const RunOptions& opt,
                                               const solver::ContinuationOptions& options, MPI_Comm comm) {
  std::vector<std::string> names, units;
  for (const auto& p : options.probes) {
    names.push_back(p.name);
    units.push_back(p.unit);
  }
  std::vector<double> s(static_cast<size_t>(sc.mesh.nodes));
  for (size_t j = 0; j < s.size(); ++j) s[j] = static_cast<double>(j) * sc.mesh.ds;
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "rod"};
  return output::ContinuationWriter(comm, opt.output, opt.overwrite, info, s, scene::name_of(sc.continuation.parameter),
                                    rod::parameter_unit(options.parameter), names, units);
}

void print_summary(const scene::Scene& sc, const RunOptions& opt, double start, long points, int branches,
                   const solver::ContinuationResult& primary) {
  const std::string& par = scene::name_of(sc.continuation.parameter);
  std::printf("continuation of '%s' in %s from %g to %g: %ld points on %d branch(es), %zu bifurcation(s) on the "
              "primary branch -> %s\n",
              sc.file.c_str(), par.c_str(), start, sc.continuation.stop, points, branches, primary.bifurcations.size(),
              opt.output.c_str());
  for (const auto& b : primary.bifurcations)
    std::printf("  %s at %s = %.10g (%s)\n", solver::to_string(b.type).c_str(), par.c_str(), b.parameter,
                b.located ? "located" : "bracketed");
}

}  // namespace

void run_statics(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  check_rod_run(sc, build_rod_model(sc).model, opt.limits, comm);  // memory, load ratio (run_limits.hpp)
  const TpetraScope tpetra(comm);  // Kokkos until finish_solver_runtime (run.hpp), Tpetra for this run
  auto tcomm = Teuchos::rcp(new Teuchos::MpiComm<int>(comm));
  const auto& cs = sc.continuation;

  const Teuchos::ParameterList solver_params = statics_solver_parameters(sc);
  rod::StaticProblem problem = static_problem(sc);
  const StaticParameter par = static_parameter(cs.parameter);
  const std::vector<rod::StaticNode> state = statics_start(sc, solver_params, tcomm, rank == 0 && !opt.quiet, problem);
  if (cs.start_given) problem.value(par) = cs.start;
  const double start = problem.value(par);
  if (start == cs.stop)
    scene::fail_at(sc, "continuation.stop", "a value different from the start value " + scene::format_number(start),
                   scene::format_number(cs.stop));
  const solver::ContinuationOptions options = continuation_options(cs, par, start, solver_params);
  output::ContinuationWriter writer = continuation_writer(sc, opt, options, comm);

  int branch = 0;
  long points = 0;
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), rod::parameter_name(par),
                    rod::parameter_unit(par), start, cs.stop, opt.progress_interval);
  const double lo = std::min(start, cs.stop), hi = std::max(start, cs.stop), slack = 1e-12 * (1.0 + hi - lo);
  auto on_point = [&](const solver::ContinuationPoint& p) {
    // The stepper shows the point that overshot a bound before landing on the bound: skip it.
    if (p.parameter < lo - slack || p.parameter > hi + slack) return;
    writer.add_point(branch, p.parameter, p.probes, p.unstable_modes, p.critical_eigenvalue);
    ++points;
    progress.update(p.parameter, points);
  };
  auto record = [&](const solver::ContinuationResult& r) {
    for (const auto& b : r.bifurcations)
      writer.add_bifurcation(solver::to_string(b.type), branch, b.located, b.parameter, b.probes, nodal_state(b.state));
    if (!r.completed) {
      progress.done();
      const std::string why = "continuation in " + scene::name_of(cs.parameter) + " stopped at " +
                              rod::parameter_name(par) + " = " +
                              (r.points.empty() ? std::string("its start") : scene::format_number(r.points.back().parameter)) +
                              ": " + r.message + "; try a smaller continuation.step or min_step";
      if (!r.points.empty()) writer.write_state("final", nodal_state(r.points.back().state));
      writer.fail(why);
      throw NumericsError(why);
    }
  };

  const solver::ContinuationResult primary = solver::continue_(problem, state, options, tcomm, on_point);
  record(primary);
  writer.write_state("final", nodal_state(primary.points.back().state));
  int switched = 0;
  if (cs.switch_branches) {
    for (const auto& b : primary.bifurcations) {
      if (b.type != solver::BifurcationType::pitchfork || !b.located) continue;
      branch = ++switched;
      const solver::ContinuationResult side = solver::switch_branch(problem, b, cs.branch_amplitude, options, tcomm, on_point);
      record(side);
      writer.write_state("branch_" + std::to_string(branch) + "_final", nodal_state(side.points.back().state));
    }
  }
  progress.done();
  writer.finish();
  if (rank == 0 && !opt.quiet) print_summary(sc, opt, start, points, switched + 1, primary);
}

}  // namespace traverse::app

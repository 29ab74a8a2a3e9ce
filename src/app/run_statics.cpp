// A rod scene with a `continuation` section: continuation of static states with stability,
// bifurcation detection and branch switching, written to a continuation file.
#include <mpi.h>

#include <Teuchos_DefaultMpiComm.hpp>

#include "progress.hpp"
#include "traverse/setup/rod_setup.hpp"
#include "run.hpp"
#include "traverse/output/continuation_writer.hpp"
#include "traverse/solver/static_continuation.hpp"
#include "traverse/version.hpp"
#include "traverse/setup/solver_access.hpp"
#include "traverse/setup/statics_setup.hpp"

namespace traverse::app {

namespace {

using rod::StaticParameter;

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
  setup::check_rod_run(sc, setup::build_rod_model(sc).model, opt.limits, comm);  // memory, load ratio (run_limits.hpp)
  const setup::TpetraScope tpetra(comm);  // Kokkos until setup::finish_solver_runtime, Tpetra for this run
  auto tcomm = Teuchos::rcp(new Teuchos::MpiComm<int>(comm));
  const auto& cs = sc.continuation;

  const Teuchos::ParameterList solver_params = setup::statics_solver_parameters(sc);
  rod::StaticProblem problem = setup::static_problem(sc);
  const StaticParameter par = setup::static_parameter(cs.parameter);
  std::string arch_text;
  const std::vector<rod::StaticNode> state = setup::statics_start(sc, solver_params, tcomm, problem, arch_text);
  if (rank == 0 && !opt.quiet && !arch_text.empty()) std::printf("%s\n", arch_text.c_str());
  if (cs.start_given) problem.value(par) = cs.start;
  const double start = problem.value(par);
  if (start == cs.stop)
    scene::fail_at(sc, "continuation.stop", "a value different from the start value " + scene::format_number(start),
                   scene::format_number(cs.stop));
  const solver::ContinuationOptions options = setup::continuation_options(cs, par, start, solver_params);
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
      writer.add_bifurcation(solver::to_string(b.type), branch, b.located, b.parameter, b.probes, setup::nodal_state(b.state));
    if (!r.completed) {
      progress.done();
      const std::string why = "continuation in " + scene::name_of(cs.parameter) + " stopped at " +
                              rod::parameter_name(par) + " = " +
                              (r.points.empty() ? std::string("its start") : scene::format_number(r.points.back().parameter)) +
                              ": " + r.message + "; try a smaller continuation.step or min_step";
      if (!r.points.empty()) writer.write_state("final", setup::nodal_state(r.points.back().state));
      writer.fail(why);
      throw NumericsError(why);
    }
  };

  const solver::ContinuationResult primary = solver::continue_(problem, state, options, tcomm, on_point);
  record(primary);
  writer.write_state("final", setup::nodal_state(primary.points.back().state));
  int switched = 0;
  if (cs.switch_branches) {
    for (const auto& b : primary.bifurcations) {
      if (b.type != solver::BifurcationType::pitchfork || !b.located) continue;
      branch = ++switched;
      const solver::ContinuationResult side = solver::switch_branch(problem, b, cs.branch_amplitude, options, tcomm, on_point);
      record(side);
      writer.write_state("branch_" + std::to_string(branch) + "_final", setup::nodal_state(side.points.back().state));
    }
  }
  progress.done();
  writer.finish();
  if (rank == 0 && !opt.quiet) print_summary(sc, opt, start, points, switched + 1, primary);
}

}  // namespace traverse::app

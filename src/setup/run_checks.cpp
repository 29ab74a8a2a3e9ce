// The up-front checks of each kind of run (run_checks.hpp).
#include "traverse/setup/run_checks.hpp"

#include "traverse/setup/memory_limit.hpp"
#include "traverse/setup/rod_setup.hpp"
#include "traverse/core/comm.hpp"

namespace traverse::setup {

namespace {

// Whether the planar path is expected: scheme.planar on, or auto and the scene planar (the
// rod, its loads, gravity and ends checked on a 2-cell copy of the model in the straight
// reference state: planarity does not depend on the mesh, and nothing of the rod's size is
// allocated before the memory check).
bool expect_planar(const scene::Scene& sc, const rod::RodModel& model) {
  if (sc.scheme.planar == scene::PlanarMode::off) return false;
  if (sc.scheme.planar == scene::PlanarMode::on) return true;
  return reference_state_planarity(sc, model).planar;
}

std::string summary(const scene::Scene& sc, const TimePlan* time, const MemoryPlan& memory,
                    const MemoryLimit& limit) {
  std::string s;
  if (time)
    s = std::to_string(time->grid.steps) + " time steps of dt = " + scene::format_number(time->grid.dt) + " s to t = " +
        scene::format_number(time->grid.t_end) + " s; ";
  s += "memory estimate " + format_bytes(memory.bytes) + " per rank (limit " +
       (limit.bytes > 0.0 ? format_bytes(limit.bytes) + ": " + limit.source : std::string("none known")) + ")";
  if (time)
    s += "; " + scene::format_number(time->output_steps()) + " output steps (" + time->every_text + "), output " +
         output_size(sc, *time).text();
  return s;
}

constexpr int kMaxCoupledNodes = 20001;  // the whole state is kept (and gathered each step) on every rank

}  // namespace

void check_coupled_rod(const scene::Scene& sc, const rod::RodModel& model) {
  const auto& a = model.alpha;
  for (double w : {a.as, a.bs, a.gs, a.at, a.bt, a.gt})
    if (w != 0.5)
      scene::fail_at(sc, "scheme.rho_inf", "rho_inf = rho_inf_space = 1 (all six parameters 1/2) with a coupled_mass or sprung_mass "
                     "(its midpoint rule is the box scheme's; other parameters are not yet supported)",
                     "parameters (" + scene::format_number(a.as) + ", " + scene::format_number(a.bs) + ", " +
                         scene::format_number(a.gs) + ", " + scene::format_number(a.at) + ", " +
                         scene::format_number(a.bt) + ", " + scene::format_number(a.gt) + ")");
  if (sc.mesh.nodes > kMaxCoupledNodes)
    scene::fail_at(sc, sc.has("mesh.ds") ? "mesh.ds" : "mesh.nodes",
                   "at most " + std::to_string(kMaxCoupledNodes) + " nodes with a coupled or sprung mass on the rod (its run "
                   "keeps the whole rod on every rank)", std::to_string(sc.mesh.nodes) + " nodes");
}

CheckedRun check_beam_run(const scene::Scene& sc, const RunLimits& limits, MPI_Comm comm) {
  CheckedRun out;
  check_properties(sc);
  check_load_ratio(sc);
  check_beam_static_deflection(sc);
  check_load_speeds(sc);
  const MemoryPlan memory = beam_memory(sc, par::size(comm));
  const MemoryLimit limit = memory_limit(limits, comm);
  check_memory(sc, memory, limit);
  TimePlan time = beam_time_plan(sc);
  check_time_plan(sc, time, limits.max_steps);
  out.grid = time.grid;
  out.output_every = time.every;
  out.summary = summary(sc, &time, memory, limit);
  return out;
}

CheckedRun check_rod_run(const scene::Scene& sc, const rod::RodModel& model, const RunLimits& limits, MPI_Comm comm) {
  CheckedRun out;
  check_properties(sc);
  check_load_ratio(sc);
  const RodPathGuess path{expect_planar(sc, model), par::size(comm)};
  const MemoryPlan memory = rod_memory(sc, path);
  const MemoryLimit limit = memory_limit(limits, comm);
  check_memory(sc, memory, limit);
  check_counters(sc, path);
  if (sc.continuation.enabled) {
    out.summary = summary(sc, nullptr, memory, limit);
    return out;
  }
  check_load_speeds(sc);
  TimePlan time = rod_time_plan(sc);
  check_time_plan(sc, time, limits.max_steps);
  out.grid = time.grid;
  out.summary = summary(sc, &time, memory, limit);
  return out;
}

std::string check_run(const scene::Scene& sc, const RunLimits& limits, MPI_Comm comm) {
  switch (sc.model) {
    case scene::Model::Beam: return check_beam_run(sc, limits, comm).summary;
    case scene::Model::Rod: return check_rod_run(sc, build_rod_model(sc).model, limits, comm).summary;
    default: throw std::logic_error("check_run: model not handled");
  }
}

}  // namespace traverse::setup

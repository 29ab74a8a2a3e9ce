#include "traverse/solver/arch_formation.hpp"

#include <cmath>

namespace traverse::solver {

std::vector<rod::StaticProbe> arch_probes(double length) {
  return {rod::probe_end_compression(Vec3::UnitZ(), "end_compression"), rod::probe_position(0.5 * length, 0, "mid_x"),
          rod::probe_position(0.5 * length, 1, "mid_y")};
}

ArchFormation form_arch(const rod::RodProperties& props, const ArchOptions& opt, const Comm& comm) {
  using P = rod::StaticParameter;
  ArchFormation out;
  const double L = opt.length;
  const rod::StaticProblem pr = rod::pinned_roller_problem(props, opt.num_cells, L, opt.gravity);
  const double PE = props.euler_load(L);
  // 1. Straight branch in the compressive end load: the Euler pitchfork.
  ContinuationOptions o;
  o.parameter = P::end_load;
  o.max_value = 1.1 * PE;
  o.initial_step = 0.2 * PE;
  o.max_step = 0.3 * PE;
  o.solver = opt.solver;
  o.verbose = opt.verbose;
  o.probes = {rod::probe_end_distance(), rod::probe_position(0.5 * L, 1, "mid_y")};
  out.buckling = continue_(pr, rod::straight_static_state(pr.base), o, comm);
  const Bifurcation* pf = nullptr;
  for (const auto& b : out.buckling.bifurcations)
    if (b.type == BifurcationType::pitchfork) pf = &b;
  if (!pf) {
    out.message = "arch formation: no Euler pitchfork found (" + out.buckling.message + ")";
    return out;
  }
  out.euler_load = pf->parameter;
  // 2. Upwards onto the buckled branch, continue until the ends are dz apart.
  const size_t mid = static_cast<size_t>(opt.num_cells / 2);
  const double up = pf->null_vector[mid](1) >= 0.0 ? 1.0 : -1.0;
  ContinuationOptions f = o;
  f.max_value = 1e3 * PE;
  f.min_value = 0.5 * PE;
  f.initial_step = 0.02 * PE;
  f.max_step = 0.1;
  f.max_steps = 500;
  f.stability.enabled = false;
  const double dz = opt.end_distance;
  f.stop = [dz](const ContinuationPoint& p) { return p.probes[0] <= dz; };
  out.forming = switch_branch(pr, *pf, up * 0.05 * L, f, comm);
  if (out.forming.points.empty() || out.forming.points.back().probes[0] > dz) {
    out.message = "arch formation: the buckled branch did not reach dz (" + out.forming.message + ")";
    return out;
  }
  out.forming_load = out.forming.points.back().parameter;
  // 3. Fix the right end (pinned) at dz: one Newton solve from the last point.
  const rod::StaticProblem arch = rod::pinned_arch_problem(out.forming.final_problem, dz);
  std::vector<rod::StaticNode> state = out.forming.points.back().state;
  const StaticSolveReport r = static_solve(arch, state, comm, opt.solver);
  if (!r.converged) {
    out.message = "arch formation: fixing the end at dz failed: " + r.message;
    return out;
  }
  // 4. Gravity 0 -> 1.
  ContinuationOptions g;
  g.parameter = P::gravity_factor;
  g.method = "Natural";
  g.max_value = 1.0;
  g.initial_step = 0.25;
  g.max_step = 0.5;
  g.stability.enabled = false;
  g.solver = opt.solver;
  g.verbose = opt.verbose;
  g.probes = arch_probes(L);
  out.loading = continue_(arch, state, g, comm);
  if (out.loading.points.empty() || std::abs(out.loading.points.back().parameter - 1.0) > 1e-12) {
    out.message = "arch formation: raising gravity failed (" + out.loading.message + ")";
    return out;
  }
  out.problem = arch;
  out.problem.value(P::gravity_factor) = 1.0;
  out.state = out.loading.points.back().state;
  out.ok = true;
  return out;
}

ContinuationResult sweep_load_position(const ArchFormation& arch, double F, double sigma_start, double sigma_end,
                                       const ContinuationOptions& base, const Comm& comm, const PointCallback& on_point) {
  using P = rod::StaticParameter;
  rod::StaticProblem pr = arch.problem;
  pr.has_point_load = true;
  pr.load_direction = -Vec3::UnitY();
  pr.value(P::load_magnitude) = F;
  pr.value(P::load_position) = sigma_start;
  ContinuationOptions o = base;
  o.parameter = P::load_position;
  o.min_value = std::min(sigma_start, sigma_end);
  o.max_value = std::max(sigma_start, sigma_end);
  o.initial_step = (sigma_end >= sigma_start ? 1.0 : -1.0) * std::abs(base.initial_step);
  o.probes = arch_probes(pr.base.length);
  return continue_(pr, arch.state, o, comm, on_point);
}

}  // namespace traverse::solver

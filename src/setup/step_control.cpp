// Where the adaptive steps of a rod run land besides the output times, and its error estimate
// (step_control.hpp).
#include "traverse/setup/step_control.hpp"

#include "traverse/solver/rod_time_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace traverse::setup {

double next_node_crossing(const std::vector<scene::MovingLoadSpec>& loads, double t, double ds, double length) {
  double next = std::numeric_limits<double>::infinity();
  const double eps = 1e-9;
  for (const auto& l : loads) {
    if (l.coupled) continue;
    if (t < l.entry_time) {  // not yet on its way: it appears at entry_time
      next = std::min(next, l.entry_time);
      continue;
    }
    const double pos = l.position(t), dir = l.direction();
    if (pos < -eps * ds || pos > length + eps * ds) continue;  // off the rod
    // The node ahead of the load (the one it sits on counts as passed).
    const double node = dir > 0 ? (std::floor(pos / ds + eps) + 1.0) * ds : (std::ceil(pos / ds - eps) - 1.0) * ds;
    if (node < -eps * ds || node > length * (1.0 + eps)) continue;
    const double tc = l.travel_time(dir * (std::clamp(node, 0.0, length) - l.start));
    if (tc > t) next = std::min(next, tc);
  }
  return next;
}

std::size_t rod_restart_components(const scene::Scene& sc) {
  return rod::kPackedNodeValues + (sc.time.adaptive.enabled ? solver::RodErrorEstimate::kPerNode : 0);
}

std::unique_ptr<solver::RodErrorEstimate> rod_error_estimate(const scene::Scene& sc, const rod::RodModel& model,
                                                             const solver::RodStepper& st,
                                                             const output::RestartPoint* point, MPI_Comm comm,
                                                             std::optional<time::ControllerState>& controller) {
  using solver::RodErrorEstimate;
  auto est = std::make_unique<RodErrorEstimate>(error_weights(sc.time.adaptive, model.length), model.alpha, comm);
  if (!point) {
    est->start(solver::owned_levels(st));
    return est;
  }
  const auto& x = point->extra;
  const std::size_t comps = rod_restart_components(sc), first = static_cast<std::size_t>(st.first_owned_node());
  std::vector<double> per_node(RodErrorEstimate::kPerNode * static_cast<std::size_t>(st.num_owned_nodes()));
  for (std::size_t k = 0; k < static_cast<std::size_t>(st.num_owned_nodes()); ++k)
    for (std::size_t i = 0; i < RodErrorEstimate::kPerNode; ++i)
      per_node[RodErrorEstimate::kPerNode * k + i] = point->state[comps * (first + k) + rod::kPackedNodeValues + i];
  controller = est->restore(solver::owned_levels(st), per_node,
                            std::vector<double>(x.begin() + std::min<std::size_t>(5, x.size()), x.end()));
  return est;
}

}  // namespace traverse::setup

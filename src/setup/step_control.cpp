// Where the adaptive steps of a rod run land besides the output times (step_control.hpp).
#include "traverse/setup/step_control.hpp"

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

}  // namespace traverse::setup

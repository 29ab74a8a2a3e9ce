#pragma once
// Where the adaptive steps of a rod run land besides the output times (time.adaptive.land_on_nodes).
#include <vector>

#include "traverse/scene/scene.hpp"

namespace traverse::app {

/// The first time after t at which one of the prescribed moving loads (not a coupled mass)
/// enters the rod or reaches one of its nodes (the multiples of ds in [0, length]): there the
/// hat weights that share its force between the nodes have a kink in time. +inf if none.
double next_node_crossing(const std::vector<scene::MovingLoadSpec>& loads, double t, double ds, double length);

}  // namespace traverse::app

#pragma once
// A rod's state after a time step as plain arrays, for a function the run calls every k-th
// step (the Python package's step callbacks). Free of Trilinos and MPI.
#include <functional>
#include <vector>

namespace traverse::setup {

/// The whole rod after time step `step` (node after node, 3 values per node and vector).
struct RodStepView {
  double t = 0.0;  ///< [s] the step's time
  long step = 0;   ///< the step's index (fixed steps: the grid index; adaptive: the accepted steps)
  int nodes = 0;
  std::vector<double> r;          ///< centreline [m], fixed components
  std::vector<double> directors;  ///< 9 per node: the rows d1, d2, d3, in fixed components
  std::vector<double> u, omega, kappa, n;  ///< body components, as the fields of the same names
};

/// What a rod run calls after every `every`-th time step (rank 0 only, with the whole rod; the
/// other ranks take part in gathering it): false stops the run at that step as SIGINT does
/// (a restart point, the output file marked interrupted; app::Interrupted). The answer of
/// rank 0 is that of every rank.
struct RodStepCallback {
  long every = 1;
  std::function<bool(const RodStepView&)> call;
  explicit operator bool() const { return static_cast<bool>(call); }
};

}  // namespace traverse::setup

#pragma once
// A rod's or a beam's state after a time step as plain arrays, for a function the run calls
// every k-th step (the Python package's step callbacks). Free of Trilinos and MPI.
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
  /// A coupled or sprung mass (runs with one): its position sigma along the rod [m] and
  /// sigma' [m/s]; a sprung mass's body displacement and velocity along up [m, m/s].
  bool has_mass = false, has_body = false;
  double sigma = 0.0, speed = 0.0, body = 0.0, body_speed = 0.0;
};

/// A beam after time step `step` (every beam run: moving loads, a coupled mass, vehicles):
/// its modal state and the deflection at the output's nodes (the field `deflection`).
struct BeamStepView {
  double t = 0.0;  ///< [s] the step's time
  long step = 0;   ///< the step's index (fixed steps: the grid index; adaptive: the accepted steps)
  std::vector<double> q, q_t;  ///< modal coordinates [m] and their rates [m/s], a value per mode
  std::vector<double> x, w;    ///< the output's nodes along the beam [m] and the deflection w there [m]
};

/// What a run calls after every `every`-th time step: `rod` in rod runs, `beam` in beam runs
/// (rank 0 only, with the whole structure; the other ranks take part in gathering it). False
/// stops the run at that step as SIGINT does (a restart point, the output file marked
/// interrupted; app::Interrupted). The answer of rank 0 is that of every rank.
struct StepCallback {
  long every = 1;
  std::function<bool(const RodStepView&)> rod;
  std::function<bool(const BeamStepView&)> beam;
  explicit operator bool() const { return rod || beam; }
};

}  // namespace traverse::setup

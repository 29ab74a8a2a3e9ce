#pragma once
// Adaptive time stepping of a rod run (time.adaptive; docs/adaptive.md): the controller's
// state over the ranks. Each rank keeps the accepted levels of its own nodes (rod::NodeLevel)
// and their displacements for the error estimate (rod/time_error.hpp); the error norm is reduced by max, so every rank
// takes the same decision and 1 and 2 ranks take the same steps.
#include <mpi.h>

#include <array>
#include <vector>

#include "step_control.hpp"
#include "traverse/core/step_controller.hpp"
#include "traverse/rod/time_error.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

class RodAdaptiveControl {
 public:
  /// `length`: the rod's (the position floor); `comm`: the ranks sharing the nodes (reduced by max).
  RodAdaptiveControl(const scene::AdaptiveSpec& spec, double first_dt, const rod::AlphaParameters& alpha,
                     double length, MPI_Comm comm);
  /// Whether the history has the three levels the extrapolation estimate needs.
  bool has_history() const { return history_.levels >= 3; }
  /// The weighted error norm (collective) of a step of length h that produced `y_new`.
  double extrapolation_error(const std::vector<rod::NodeLevel>& y_new, double h) const;
  /// The same for a doubled step: `full` one step of h, `mid` and `half` two steps of h / 2.
  double doubling_error(const std::vector<rod::NodeLevel>& full, const std::vector<rod::NodeLevel>& mid,
                        const std::vector<rod::NodeLevel>& half, double h) const;
  /// Record an accepted level y_new reached by a step of h.
  void accept(std::vector<rod::NodeLevel> y_new, double h);
  /// Record the current level as the first one (at the start of the run, or after a restart
  /// without the controller's state).
  void start(std::vector<rod::NodeLevel> y0) { history_.start(std::move(y0)); }

  StepController& controller() { return controller_; }
  StepControlTotals& totals() { return totals_; }
  const StepControlTotals& totals() const { return totals_; }
  double next_dt = 0.0;  ///< [s] the step the controller proposes next

  /// Restart: values per owned node appended to the node packing, and replicated values.
  static constexpr std::size_t kPerNode = 36;  ///< levels n-1 and n-2 (15 each), displacement, rotation
  void pack_node(int k, double* out) const;
  std::vector<double> pack_scalars() const;
  /// From a restart point: the owned nodes' values (count x kPerNode) and the scalars.
  void restore(const std::vector<rod::NodeLevel>& y0, const std::vector<double>& per_node,
               const std::vector<double>& scalars);

 private:
  double reduce(const rod::TimeErrorParts& local) const;
  scene::AdaptiveSpec spec_;
  StepController controller_;
  StepControlTotals totals_;
  rod::LevelHistory history_;
  rod::GroupValues peak_{};
  mutable rod::GroupValues last_sizes_{};  ///< sizes of the last estimate (reduced)
  double c_;
  double length_;
  MPI_Comm comm_;
};

/// The first time after t at which one of the prescribed moving loads (not a coupled mass)
/// enters the rod or reaches one of its nodes (the multiples of ds in [0, length]): there the
/// hat weights that share its force between the nodes have a kink in time. +inf if none.
double next_node_crossing(const std::vector<scene::MovingLoadSpec>& loads, double t, double ds, double length);

}  // namespace traverse::app

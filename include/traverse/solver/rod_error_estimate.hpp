#pragma once
// The adaptive steps' error estimate of a rod (time.adaptive; docs/adaptive.md) over the ranks.
// Each rank keeps the accepted levels of its own nodes (rod::LevelHistory) for the estimates
// of rod/time_error.hpp; the error norm is reduced by max, so every rank takes the same
// decision and 1 and 2 ranks take the same steps. The controller itself (step lengths,
// counters) is the time integrator's (time/time_integrator.hpp).
#include <mpi.h>

#include <vector>

#include "traverse/rod/time_error.hpp"
#include "traverse/time/time_integrator.hpp"

namespace traverse::solver {

class RodErrorEstimate {
 public:
  /// `weights`: the tolerances and controlled groups; `comm`: the ranks sharing the nodes
  /// (MPI_COMM_NULL: this rank holds them all).
  RodErrorEstimate(const rod::ErrorWeights& weights, const rod::AlphaParameters& alpha, MPI_Comm comm);
  /// Whether the history has the three levels the extrapolation estimate needs.
  bool has_history() const { return history_.levels >= 3; }
  /// The weighted error norm (collective) of a step of length h that produced `y_new`.
  double extrapolation_error(const std::vector<rod::NodeLevel>& y_new, double h) const;
  /// The same for a doubled step: `full` one step of h, `mid` and `half` two steps of h / 2.
  double doubling_error(const std::vector<rod::NodeLevel>& full, const std::vector<rod::NodeLevel>& mid,
                        const std::vector<rod::NodeLevel>& half, double h) const;
  /// Record an accepted level y_new reached by a step of h.
  void accept(std::vector<rod::NodeLevel> y_new, double h);
  /// Record the current level as the first one (at the start of a run).
  void start(std::vector<rod::NodeLevel> y0) { history_.start(std::move(y0)); }

  /// Restart points: values per node appended to the node's packing, and replicated values
  /// (the estimate's and the controller's).
  static constexpr std::size_t kPerNode = 36;  ///< levels n-1 and n-2 (15 each), displacement, rotation
  void pack_node(int k, double* out) const;
  std::vector<double> pack_scalars(const time::ControllerState& controller) const;
  /// From a restart point: the current level `y0`, the nodes' values (count x kPerNode) and
  /// the scalars; returns the controller's state.
  time::ControllerState restore(const std::vector<rod::NodeLevel>& y0, const std::vector<double>& per_node,
                                const std::vector<double>& scalars);

 private:
  double reduce(const rod::TimeErrorParts& local) const;
  rod::ErrorWeights weights_;
  rod::LevelHistory history_;
  rod::GroupValues peak_{};
  mutable rod::GroupValues last_sizes_{};  ///< sizes of the last estimate (reduced)
  double c_;
  MPI_Comm comm_;
};

}  // namespace traverse::solver

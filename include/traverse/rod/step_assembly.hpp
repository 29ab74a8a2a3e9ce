#pragma once
// The blocks of one rod time step on one rank's nodes, for the Thyra model evaluator over
// Tpetra that NOX solves (solver::RodStepModel, any rank count and linear solver).
// It holds the old level of the rank's ghosted nodes (its owned nodes plus one ghost on each
// side where there is one), their old-level fluxes (fixed during the step's Newton
// iterations) and, on the planar path, the reduction that maps the full node blocks to the
// in-plane ones. Eigen only.
#include <functional>
#include <memory>
#include <vector>

#include "traverse/rod/planar.hpp"
#include "traverse/rod/rod_kernels.hpp"

namespace traverse::rod {

/// Newton's initial guess of a time step (StepAssembly::initial_guess).
/// old_level: y; secant: y + dt yv; blend: y + dt yg (RodNode::yg).
enum class InitialGuess { old_level, secant, blend };

class StepAssembly {
 public:
  /// The rank's ghosted nodes first_ghosted .. first_ghosted + num_ghosted - 1 and its owned
  /// nodes first_owned .. first_owned + num_owned - 1. `planar` (may be null: 3D path) must
  /// belong to `model`'s layout.
  StepAssembly(std::shared_ptr<const RodModel> model, std::shared_ptr<const PlanarReduction> planar,
               int first_ghosted, int num_ghosted, int first_owned, int num_owned);

  const RodModel& model() const { return *model_; }
  const PlanarReduction* planar() const { return planar_.get(); }
  /// Unknowns per node of the system solved: the model's (12 or 24) or the planar layout's (6 or 12).
  int unknowns_per_node() const { return p_; }
  int first_ghosted_node() const { return g0_; }
  int num_ghosted_nodes() const { return ng_; }
  int first_owned_node() const { return o0_; }
  int num_owned_nodes() const { return no_; }

  /// The old level of the ghosted nodes and the step; computes their old-level fluxes.
  void set_old_level(std::vector<RodNode> ghosted_old_nodes, const StepTimes& step);
  const std::vector<RodNode>& old_nodes() const { return old_nodes_; }
  const StepTimes& step() const { return step_; }

  /// The Newton initial guess `g` of the owned nodes in the system's layout
  /// (unknowns_per_node() values per owned node): the old unknowns; with the secant guess the
  /// old unknowns with y extrapolated along the last step's secant, y + dt yv; with the blend
  /// y + dt yg, extrapolated only in the entries RodNode::yg keeps (yv = yg = 0 at a start: the
  /// old unknowns).
  void initial_guess(double* data, InitialGuess g) const;
  /// Ghosted system-layout unknowns (unknowns_per_node() per ghosted node) -> per ghosted node
  /// its full unknown block (model->unknowns_per_node() entries; planar: the in-plane ones
  /// embedded, zeros elsewhere).
  void full_unknowns(const double* ghosted, std::vector<VecX>& out) const;

  /// Every kernel block whose rows include owned rows, given the ghosted system-layout unknowns
  /// (unknowns_per_node() per ghosted node), handed to `visit` one at a time in row order (left
  /// end, cells, right end) and not kept (each row of the system belongs to exactly one block).
  /// Each node's new-level quantities are computed once and shared by its two cells through a
  /// two-node window. Planar path: the in-plane kernel (PlanarReduction::cell_block_into) and
  /// the restricted end and load blocks; returns the largest dropped (out-of-plane) residual of
  /// the blocks that have one (0 on the 3D path). `jacobian` false: the cells' residuals alone
  /// (the same bits; the cells' Jacobian blocks are left zero, the ends' are computed).
  double for_each_block(const double* ghosted, const std::function<void(const LocalBlock&)>& visit,
                        bool jacobian = true) const;

 private:
  std::shared_ptr<const RodModel> model_;
  std::shared_ptr<const PlanarReduction> planar_;
  int p_ = 12, g0_ = 0, ng_ = 0, o0_ = 0, no_ = 0;
  std::vector<RodNode> old_nodes_;
  StepTimes step_;
  std::vector<char> touched_;  ///< per ghosted node k: whether a load acts on cell (k-1, k) (set per step)
  bool touched(int j) const { return touched_[static_cast<size_t>(j - g0_)] != 0; }
  double blocks_3d(const double* ghosted, const std::function<void(const LocalBlock&)>& visit, bool jacobian) const;
  double blocks_planar(const double* ghosted, const std::function<void(const LocalBlock&)>& visit,
                       bool jacobian) const;

  std::vector<Vec12> F_old_;           ///< 3D: per ghosted node, the old-level flux (set per step)
  std::vector<PlanarReduction::OldNode> planar_old_;  ///< planar: per ghosted node (set per step)
  mutable std::vector<VecX> xg_;       ///< 3D: the ghosted unknown blocks (reused buffer)
  mutable VecX full_[2];               ///< planar: embedded blocks for end and load blocks
  mutable NodeLevels window_[2];       ///< 3D: new-level quantities of nodes j - 1 and j (j % 2)
  mutable PlanarReduction::NewLevels planar_window_[2];  ///< the same on the planar path
  mutable LocalBlock block_;           ///< the block being assembled (reused storage)
};

}  // namespace traverse::rod

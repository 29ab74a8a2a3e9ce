#include "traverse/rod/step_assembly.hpp"

#include <algorithm>
#include <stdexcept>

namespace traverse::rod {

StepAssembly::StepAssembly(std::shared_ptr<const RodModel> model, std::shared_ptr<const PlanarReduction> planar,
                           int first_ghosted, int num_ghosted, int first_owned, int num_owned)
    : model_(std::move(model)), planar_(std::move(planar)), g0_(first_ghosted), ng_(num_ghosted),
      o0_(first_owned), no_(num_owned) {
  if (!model_) throw std::invalid_argument("StepAssembly: null model");
  if (planar_ && planar_->full_unknowns_per_node() != model_->unknowns_per_node())
    throw std::invalid_argument("StepAssembly: the planar reduction belongs to another layout");
  if (g0_ < 0 || ng_ < 1 || g0_ + ng_ > model_->num_cells + 1 || o0_ < g0_ || o0_ + no_ > g0_ + ng_)
    throw std::invalid_argument("StepAssembly: the owned nodes must lie inside the ghosted nodes of the rod");
  p_ = planar_ ? planar_->unknowns_per_node() : model_->unknowns_per_node();
}

void StepAssembly::set_old_level(std::vector<RodNode> ghosted_old_nodes, const StepTimes& step) {
  if (static_cast<int>(ghosted_old_nodes.size()) != ng_)
    throw std::invalid_argument("StepAssembly::set_old_level: expected one node per ghosted node");
  old_nodes_ = std::move(ghosted_old_nodes);
  step_ = step;
  // The cells a load acts on depend on the step only: found once here, not per evaluation.
  touched_.assign(static_cast<size_t>(ng_), 0);
  for (int j : cells_touched_by_loads(*model_, step_, g0_ + 1, g0_ + ng_ - 1)) touched_[static_cast<size_t>(j - g0_)] = 1;
  // Old-level fluxes: fixed during the step's Newton iterations (the cells use F only).
  if (planar_) {
    planar_old_.resize(old_nodes_.size());
    for (size_t k = 0; k < old_nodes_.size(); ++k)
      planar_old_[k] = planar_->old_node(*model_, step_, g0_ + static_cast<int>(k), old_nodes_[k]);
    return;
  }
  F_old_.resize(old_nodes_.size());
  for (size_t k = 0; k < old_nodes_.size(); ++k)
    F_old_[k] = old_level_flux(*model_, step_, g0_ + static_cast<int>(k), old_nodes_[k]).F;
}

void StepAssembly::initial_guess(double* data, InitialGuess g) const {
  const int off = o0_ - g0_;
  for (int k = 0; k < no_; ++k) {
    RodNode guess = old_nodes_[static_cast<size_t>(off + k)];
    if (g == InitialGuess::secant) guess.y += step_.dt * guess.yv;
    if (g == InitialGuess::blend) guess.y += step_.dt * guess.yg;
    VecX u = node_unknowns(*model_, guess);
    if (planar_) u = planar_->restrict_unknowns(u);
    for (int c = 0; c < p_; ++c) data[static_cast<size_t>(k) * p_ + c] = u(c);
  }
}

void StepAssembly::full_unknowns(const double* ghosted, std::vector<VecX>& out) const {
  out.resize(static_cast<size_t>(ng_));
  for (size_t k = 0; k < out.size(); ++k) {
    if (planar_) {
      planar_->embed(&ghosted[k * p_], out[k]);
      continue;
    }
    out[k].resize(p_);
    for (int c = 0; c < p_; ++c) out[k](c) = ghosted[k * p_ + c];
  }
}

double StepAssembly::for_each_block(const double* ghosted, const std::function<void(const LocalBlock&)>& visit,
                                    bool jacobian) const {
  if (old_nodes_.empty()) throw std::logic_error("StepAssembly: evaluated before set_old_level");
  return planar_ ? blocks_planar(ghosted, visit, jacobian) : blocks_3d(ghosted, visit, jacobian);
}

double StepAssembly::blocks_3d(const double* ghosted, const std::function<void(const LocalBlock&)>& visit,
                               bool jacobian) const {
  full_unknowns(ghosted, xg_);
  const int N = model_->num_cells;
  const int first = o0_, last = o0_ + no_ - 1;
  auto O = [&](int j) -> const RodNode& { return old_nodes_[static_cast<size_t>(j - g0_)]; };
  auto X = [&](int j) -> const VecX& { return xg_[static_cast<size_t>(j - g0_)]; };
  // Rows of node k are [p k, p (k+1)): they come from the end blocks and cells k, k+1.
  const int c0 = std::max(1, first), c1 = std::min(N, last + 1);
  // Node j's new-level frame and flux (and its old-level flux), computed once and shared by
  // cells j and j + 1: a window of two nodes, node j in window_[j % 2]. Same arithmetic as
  // cell_block.
  auto levels = [&](int j) -> NodeLevels& {
    NodeLevels& L = window_[static_cast<size_t>(j & 1)];
    new_level_quantities(*model_, step_, j, O(j), X(j), L, jacobian);
    L.F_old.F = F_old_[static_cast<size_t>(j - g0_)];
    return L;
  };
  if (first == 0) visit(left_block(*model_, step_, O(0), X(0)));
  if (c0 <= c1) levels(c0 - 1);
  for (int j = c0; j <= c1; ++j) {
    const NodeLevels& cur = levels(j);
    cell_block_into(block_, *model_, step_, j, O(j - 1), O(j), X(j - 1), X(j),
                    window_[static_cast<size_t>((j - 1) & 1)], cur, touched(j), jacobian);
    visit(block_);
  }
  if (last == N) visit(right_block(*model_, step_, O(N), X(N)));
  return 0.0;
}

double StepAssembly::blocks_planar(const double* ghosted, const std::function<void(const LocalBlock&)>& visit,
                                   bool jacobian) const {
  // Planar layout (row r still belongs to node r / q).
  const int N = model_->num_cells;
  const int first = o0_, last = o0_ + no_ - 1;
  auto O = [&](int j) -> const RodNode& { return old_nodes_[static_cast<size_t>(j - g0_)]; };
  auto X = [&](int j) { return ghosted + static_cast<size_t>(j - g0_) * static_cast<size_t>(p_); };
  auto full = [&](int j, int slot) -> const VecX& {
    planar_->embed(X(j), full_[slot]);
    return full_[slot];
  };
  const int c0 = std::max(1, first), c1 = std::min(N, last + 1);
  auto levels = [&](int j) -> PlanarReduction::NewLevels& {
    PlanarReduction::NewLevels& L = planar_window_[static_cast<size_t>(j & 1)];
    planar_->new_levels(*model_, step_, planar_old_[static_cast<size_t>(j - g0_)], X(j), L);
    return L;
  };
  double dropped = 0.0;
  if (first == 0) {
    dropped = std::max(dropped, planar_->restrict_block(left_block(*model_, step_, O(0), full(0, 0)), block_));
    visit(block_);
  }
  if (c0 <= c1) levels(c0 - 1);
  for (int j = c0; j <= c1; ++j) {
    const PlanarReduction::NewLevels& cur = levels(j);
    const double own = planar_->cell_block_into(block_, *model_, step_, j, planar_old_[static_cast<size_t>(j - 1 - g0_)],
                             planar_old_[static_cast<size_t>(j - g0_)], X(j - 1), X(j),
                             planar_window_[static_cast<size_t>((j - 1) & 1)], cur, jacobian);
    dropped = std::max(dropped, own);
    if (touched(j))  // a point force or moving mass on this cell (rare)
      dropped = std::max(dropped, planar_->add_loads(block_, load_block(*model_, step_, j, O(j - 1), O(j),
                                                                        full(j - 1, 0), full(j, 1))));
    visit(block_);
  }
  if (last == N) {
    dropped = std::max(dropped, planar_->restrict_block(right_block(*model_, step_, O(N), full(N, 0)), block_));
    visit(block_);
  }
  return dropped;
}

}  // namespace traverse::rod

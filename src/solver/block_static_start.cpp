// The single-process static initial state on block storage (block_static_start.hpp).
#include "traverse/solver/block_static_start.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "block_system.hpp"
#include "traverse/rod/planar.hpp"
#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/solver/solver_parameters.hpp"

namespace traverse::solver {

namespace {

/// rod::StaticNewtonSystem on the whole rod in one process, the Jacobian in block storage.
/// The operations of the distributed system with the block LU (static_start.cpp), in the
/// same order: f and the blocks from the same kernel blocks, the LU's residual check, the
/// update of every node by static_update_node. With a planar split (rod::static_planar_split)
/// only the in-plane rows and unknowns: 6 x 6 blocks instead of 12 x 12, the out-of-plane
/// updates zero (exactly what the full system gives a symmetric state, to rounding); the
/// residual's maximum still covers the dropped rows, so a state that were not symmetric would
/// not converge.
class BlockStaticSystem : public rod::StaticNewtonSystem {
 public:
  BlockStaticSystem(const rod::StaticModel& m, double linear_tolerance,
                    const std::optional<rod::StaticPlanarSplit>& planar)
      : nodes_(rod::straight_static_nodes(m, 0, m.num_cells + 1)),
        sys_(m.num_cells + 1, planar ? 6 : 12),
        tol_(linear_tolerance),
        planar_(planar) {}

  bool assemble(const rod::StaticModel& m) override {
    fill(m);
    return std::isfinite(max_abs(sys_.f()));
  }
  bool factorize(std::string& why) override {
    try {
      sys_.factor();
      return true;
    } catch (const std::exception&) {
      why = "the linear solver failed on the static Jacobian (block-tridiagonal LU)";
      return false;
    }
  }
  double update(double length, double fscale) override {
    std::vector<double>& f = sys_.f();
    for (double& v : f) v = -v;
    const double worst = sys_.solve(dx_, max_abs(f), tol_);
    // As the direct solve over Tpetra is accepted: converged, or a tiny achieved tolerance.
    if (!(worst <= tol_ || worst <= 1e-9) || !std::isfinite(max_abs(dx_))) return std::numeric_limits<double>::infinity();
    double step = 0.0;
    for (size_t k = 0; k < nodes_.size(); ++k) {
      const double s = rod::static_update_node(nodes_[k], rod::static_node_update(planar_, dx_.data(), k), length, fscale);
      step = std::isfinite(s) ? std::max(step, s) : std::numeric_limits<double>::infinity();
    }
    return step;
  }
  double residual_max(const rod::StaticModel& m) override {
    fill(m);
    return std::max(max_abs_or_inf(sys_.f()), std::isnan(dropped_) ? std::numeric_limits<double>::infinity() : dropped_);
  }
  void rebase_all() override {
    for (auto& n : nodes_) n.rebase();
  }
  void start() override { saved_ = nodes_; }
  void restore() override { nodes_ = saved_; }
  const std::vector<rod::StaticNode>& nodes() const { return nodes_; }

 private:
  static double max_abs_or_inf(const std::vector<double>& v) {
    const double m = max_abs(v);
    return std::isnan(m) ? std::numeric_limits<double>::infinity() : m;
  }
  void fill(const rod::StaticModel& m) {
    sys_.clear();
    dropped_ = 0.0;
    add(m, rod::static_left_block(m, nodes_.front()));
    for (int j = 1; j <= m.num_cells; ++j)
      add(m, rod::static_cell_block(m, j, nodes_[static_cast<size_t>(j - 1)], nodes_[static_cast<size_t>(j)]));
    add(m, rod::static_right_block(m, nodes_.back()));
  }
  void add(const rod::StaticModel& m, const rod::LocalBlock& full) {
    if (!planar_) return sys_.add(full);
    const double d = rod::restrict_static_block(m, *planar_, full, in_plane_);
    dropped_ = std::isnan(d) || std::isnan(dropped_) ? std::numeric_limits<double>::quiet_NaN() : std::max(dropped_, d);
    sys_.add(in_plane_);
  }

  std::vector<rod::StaticNode> nodes_, saved_;
  BlockSystem sys_;
  double tol_;
  std::optional<rod::StaticPlanarSplit> planar_;
  rod::LocalBlock in_plane_;
  double dropped_ = 0.0;  ///< largest |residual| of the rows left out (planar)
  std::vector<double> dx_;
};

}  // namespace

StaticStart solve_static_start_in_one_process(const rod::StaticModel& m, bool planar) {
  StaticStart out;
  out.first_owned_node = 0;
  out.num_owned_nodes = m.num_cells + 1;
  // The block LU eliminates from the left end: well posed only when the left end is clamped
  // (static_start.cpp). The in-plane system first when the problem is symmetric about a plane,
  // the full one if that fails.
  if (m.left.type == rod::EndCondition::Type::clamped) {
    const LinearSolverChoice choice = LinearSolverChoice::resolve(validated_solver_parameters(ParamList()),
                                                                  1, LinearSolverChoice::Use::time_step);
    std::vector<std::optional<rod::StaticPlanarSplit>> tries;
    if (planar)
      if (std::optional<rod::StaticPlanarSplit> split = rod::static_planar_split(m)) tries.push_back(split);
    tries.push_back(std::nullopt);
    for (const std::optional<rod::StaticPlanarSplit>& split : tries) {
      BlockStaticSystem sys(m, choice.linear_tolerance, split);
      out.linear_solver = choice.resolved + (split ? " on the in-plane unknowns (6 per node)" : "");
      out.report = rod::StaticSolver().solve_with_load_steps(m, sys);
      if (out.report.converged) {
        out.nodes = sys.nodes();
        return out;
      }
      if (out.first_failure.empty()) out.first_failure = out.linear_solver + ": " + out.report.message;
    }
  }
  std::vector<rod::StaticNode> nodes = rod::straight_static_nodes(m, 0, m.num_cells + 1);
  out.linear_solver = "direct LU in one process (band storage; Eigen's SparseLU for a wide band)";
  out.report = rod::StaticSolver().solve_with_load_steps(m, nodes);
  if (out.report.converged) out.nodes = std::move(nodes);
  return out;
}

rod::RodState dynamic_state_piece(const rod::StaticModel& m, const StaticStart& start, int& first_node) {
  first_node = std::max(0, start.first_owned_node - 1);
  const int count = std::min(m.num_cells, start.first_owned_node + start.num_owned_nodes) - first_node + 1;
  rod::RodState piece;
  piece.ds = m.ds();
  piece.nodes = rod::dynamic_nodes_from_static(m, start.nodes, start.first_node, first_node, count);
  return piece;
}

}  // namespace traverse::solver

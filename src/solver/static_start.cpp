// The distributed static initial state (static_start.hpp).
#include "traverse/solver/static_start.hpp"
#include "thyra_tpetra.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "static_context.hpp"

namespace traverse::solver {

namespace {

using Vector = StaticRodModel::Vector;
using Matrix = StaticRodModel::Matrix;

/// rod::StaticNewtonSystem on the ranks: x on the mesh's dof map, the frames in the model,
/// the Jacobian in one CrsMatrix refilled in place.
class DistributedStaticSystem : public rod::StaticNewtonSystem {
 public:
  /// `solver` null: the block-tridiagonal LU.
  DistributedStaticSystem(const rod::StaticModel& m, const Comm& comm, const Teuchos::ParameterList* solver)
      : comm_(comm),
        linear_(solver ? StaticLinearSolver(*solver, comm) : StaticLinearSolver([this] { return version_; }, comm)) {
    mesh_ = Teuchos::rcp(new mesh::DistributedMesh(mesh::Mesh1D(m.length, m.num_cells + 1), comm, 12));
    rod::StaticProblem pb;  // its parameters are not used: fill_model takes the (scaled) model
    pb.base = m;
    model_ = Teuchos::rcp(new StaticRodModel(pb, mesh_));
    model_->set_local_state(rod::straight_static_nodes(m, mesh_->first_ghosted_node(), mesh_->num_ghosted_nodes()));
    x_ = Teuchos::rcp(new Vector(*model_->nominal_x(), Teuchos::Copy));
    f_ = Teuchos::rcp(new Vector(x_->getMap()));
    dx_ = Teuchos::rcp(new Vector(x_->getMap()));
    W_ = model_->jacobian_matrix();  // the model's own W: filled in place, no second matrix
  }

  bool assemble(const rod::StaticModel& m) override {
    model_->fill_model(*x_, m, f_.get(), W_.get());
    ++version_;
    return std::isfinite(max_all(local_max_abs(*f_)));
  }
  bool factorize(std::string& why) override {
    if (linear_.set_up(model_->get_x_space(), *W_)) return true;
    why = "the linear solver failed on the static Jacobian (" + linear_.choice().resolved + ")";
    return false;
  }
  double update(const rod::StaticModel& m, double fscale) override {
    f_->scale(-1.0);
    dx_->putScalar(0.0);
    if (!linear_.solve(*f_, *dx_)) return std::numeric_limits<double>::infinity();
    // Every rank updates its ghosts exactly as their owners do (same numbers, same rule).
    std::vector<rod::StaticNode> nodes = model_->ghosted_nodes(*x_);
    const std::vector<rod::StaticNode> d = model_->ghosted_nodes(*dx_);
    const size_t skip = static_cast<size_t>(mesh_->first_owned_node() - mesh_->first_ghosted_node());
    double step = 0.0;
    for (size_t k = 0; k < nodes.size(); ++k) {
      const double s = rod::static_update_node(nodes[k], d[k].x, m, fscale);
      if (k >= skip && k < skip + static_cast<size_t>(mesh_->num_owned_nodes()))
        step = std::isfinite(s) ? std::max(step, s) : std::numeric_limits<double>::infinity();
    }
    model_->store_ghosted_nodes(nodes, *x_);
    return max_all(step);
  }
  double residual_max(const rod::StaticModel& m) override {
    model_->fill_model(*x_, m, f_.get(), nullptr);
    return max_all(local_max_abs(*f_));
  }
  void rebase_all() override {
    std::vector<rod::StaticNode> nodes = model_->ghosted_nodes(*x_);
    for (auto& n : nodes) n.rebase();
    model_->store_ghosted_nodes(nodes, *x_);
  }
  void start() override { saved_ = model_->ghosted_nodes(*x_); }
  void restore() override { model_->store_ghosted_nodes(saved_, *x_); }

  /// This rank's nodes and up to `halo` more each side (the first returned).
  std::vector<rod::StaticNode> nodes_with_halo(int halo, int& first) const;
  const LinearSolverChoice& choice() const { return linear_.choice(); }
  const mesh::DistributedMesh& mesh() const { return *mesh_; }

 private:
  static double local_max_abs(const Vector& v) {
    double m = 0.0;
    for (double a : v.getData()) m = std::isfinite(a) ? std::max(m, std::abs(a)) : std::numeric_limits<double>::infinity();
    return m;
  }
  double max_all(double v) const {
    double g = 0.0;
    Teuchos::reduceAll<int, double>(*comm_, Teuchos::REDUCE_MAX, v, Teuchos::outArg(g));
    return g;
  }

  Comm comm_;
  long version_ = 0;  ///< of the assembled Jacobian
  StaticLinearSolver linear_;
  Teuchos::RCP<mesh::DistributedMesh> mesh_;
  Teuchos::RCP<StaticRodModel> model_;
  Teuchos::RCP<Vector> x_, f_, dx_;
  Teuchos::RCP<Matrix> W_;
  std::vector<rod::StaticNode> saved_;
};

std::vector<rod::StaticNode> DistributedStaticSystem::nodes_with_halo(int halo, int& first) const {
  constexpr int per = 21;  // 12 unknowns and the 9 entries of the frame
  const int N = mesh_->mesh().num_nodes() - 1;
  const int f0 = mesh_->first_owned_node(), n0 = mesh_->num_owned_nodes();
  first = std::max(0, f0 - halo);
  const int last = std::min(N, f0 + n0 - 1 + halo);
  std::vector<mesh::GO> gids;
  for (int j = first; j <= last; ++j) gids.push_back(j);
  using MV = Tpetra::MultiVector<double, tt::LO, tt::GO, tt::Node>;
  const auto& owned = mesh_->node_map();
  auto wide = Teuchos::rcp(new mesh::Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                         Teuchos::ArrayView<const mesh::GO>(gids), 0, comm_));
  MV mine(owned, per), all(wide, per);
  const std::vector<rod::StaticNode> held = model_->ghosted_nodes(*x_);
  const size_t skip = static_cast<size_t>(f0 - mesh_->first_ghosted_node());
  for (int k = 0; k < n0; ++k) {
    const rod::StaticNode& nd = held[skip + static_cast<size_t>(k)];
    for (int c = 0; c < 12; ++c) mine.replaceLocalValue(k, c, nd.x(c));
    for (int c = 0; c < 9; ++c) mine.replaceLocalValue(k, 12 + c, nd.Rbar.data()[c]);
  }
  all.doImport(mine, mesh::Import(owned, wide), Tpetra::INSERT);
  std::vector<rod::StaticNode> out(gids.size());
  for (size_t k = 0; k < out.size(); ++k) {
    for (int c = 0; c < 12; ++c) out[k].x(c) = all.getData(static_cast<size_t>(c))[k];
    for (int c = 0; c < 9; ++c) out[k].Rbar.data()[c] = all.getData(static_cast<size_t>(12 + c))[k];
  }
  return out;
}

}  // namespace

StaticStart solve_static_start(const rod::StaticModel& m, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                               const Teuchos::ParameterList& solver, int halo) {
  // The block LU eliminates from the left end; the pieces of the rod left of each node are
  // then cantilevers (their cut end is free), well posed only when the left end is clamped.
  const bool clamped = m.left.type == rod::EndCondition::Type::clamped;
  StaticStart out;
  for (int attempt = clamped ? 0 : 1; attempt < 2; ++attempt) {
    DistributedStaticSystem sys(m, comm, attempt == 0 ? nullptr : &solver);
    out.linear_solver = sys.choice().resolved;
    out.report = rod::StaticSolver().solve_with_load_steps(m, sys);
    if (out.report.converged) {
      out.nodes = sys.nodes_with_halo(halo, out.first_node);
      out.first_owned_node = sys.mesh().first_owned_node();
      out.num_owned_nodes = sys.mesh().num_owned_nodes();
      return out;
    }
    if (attempt == 0) out.first_failure = out.linear_solver + ": " + out.report.message;
  }
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

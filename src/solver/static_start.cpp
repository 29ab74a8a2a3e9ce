// The distributed static initial state (static_start.hpp).
#include "traverse/solver/static_start.hpp"
#include "thyra_tpetra.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_MultiVector.hpp>

#include <algorithm>
#include <cmath>

#include "static_newton.hpp"

namespace traverse::solver {

namespace {

using Vector = StaticRodModel::Vector;

/// One attempt at the static start with one linear solver: the static model over the ranks
/// (frames in the model, unknowns in x), solved at each load factor by NOX.
class LoadSteppedStart {
 public:
  /// `solver` null: the block-tridiagonal LU (the left end clamped and corrected when it is not
  /// clamped).
  LoadSteppedStart(const rod::StaticModel& m, const Comm& comm, const Teuchos::ParameterList* solver)
      : comm_(comm),
        linear_(solver ? StaticLinearSolver(*solver, comm)
                       : StaticLinearSolver(std::function<long()>(), comm,
                                            m.left.type != rod::EndCondition::Type::clamped)) {
    mesh_ = Teuchos::rcp(new mesh::DistributedMesh(mesh::Mesh1D(m.length, m.num_cells + 1), comm, 12));
    rod::StaticProblem pb;  // its parameters are not used: each solve fixes the (scaled) model
    pb.base = m;
    model_ = Teuchos::rcp(new StaticRodModel(pb, mesh_));
    model_->set_local_state(rod::straight_static_nodes(m, mesh_->first_ghosted_node(), mesh_->num_ghosted_nodes()));
    model_->set_W_factory(linear_.factory());
    x_ = Teuchos::rcp(new Vector(*model_->nominal_x(), Teuchos::Copy));
  }

  /// NOX at the loads of `scaled` from the current state, with the static start's tests:
  /// max |f| <= ftol * force scale and the scaled update <= rtol. Converged: the state moves
  /// there with its frames rebased; failed: the state stays.
  rod::StaticReport newton(const rod::StaticModel& scaled) {
    const rod::StaticTolerances tol;
    const double fscale = rod::static_force_scale(scaled);
    StaticNewtonTests tests;
    tests.residual = tol.ftol * fscale;
    tests.update = tol.rtol;
    tests.scales = rod::static_update_scales(scaled.length, fscale);
    tests.compliance = scaled.props.C;
    tests.max_iterations = tol.max_iterations;
    // A solve that has run away (a load step too large for the state it starts from: a rope
    // pinned straight has almost no transverse stiffness) fails once its residual has grown
    // 1e4-fold, and the load step is halved, instead of spending all its iterations.
    tests.divergence = 1e4;
    model_->set_fixed_model(scaled);
    Vector x(*x_, Teuchos::Copy);
    const StaticSolveReport s = nox_static_solve(model_, x, tests);
    rod::StaticReport r;
    r.converged = s.converged;
    r.iterations = s.iterations;
    r.residual_norm = s.residual_norm;
    r.load_scale = fscale;
    r.message = s.message;
    if (s.converged) {
      Tpetra::deep_copy(*x_, x);
      std::vector<rod::StaticNode> nodes = model_->ghosted_nodes(*x_);
      for (auto& n : nodes) n.rebase();  // every rank rebases its ghosts as their owners do
      model_->store_ghosted_nodes(nodes, *x_);
    }
    return r;
  }

  /// This rank's nodes and up to `halo` more each side (the first returned).
  std::vector<rod::StaticNode> nodes_with_halo(int halo, int& first) const;
  const LinearSolverChoice& choice() const { return linear_.choice(); }
  const mesh::DistributedMesh& mesh() const { return *mesh_; }

 private:
  Comm comm_;
  StaticLinearSolver linear_;
  Teuchos::RCP<mesh::DistributedMesh> mesh_;
  Teuchos::RCP<StaticRodModel> model_;
  Teuchos::RCP<Vector> x_;
};

std::vector<rod::StaticNode> LoadSteppedStart::nodes_with_halo(int halo, int& first) const {
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
  // The block LU first (it eliminates from the left end; with a left end that is not clamped
  // it factorises the rod clamped there and corrects each solve for the end's rows), then the
  // scene's solver when it fails.
  StaticStart out;
  for (int attempt = 0; attempt < 2; ++attempt) {
    LoadSteppedStart sys(m, comm, attempt == 0 ? nullptr : &solver);
    out.linear_solver = sys.choice().resolved;
    out.report = rod::solve_with_load_steps(m, [&sys](const rod::StaticModel& s) { return sys.newton(s); });
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

double static_start_bytes_per_node() { return 13000.0; }

}  // namespace traverse::solver

#include "traverse/solver/static_rod_model.hpp"
#include "thyra_tpetra.hpp"

#include <Thyra_DefaultLinearOpSource.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <algorithm>
#include <stdexcept>

namespace traverse::solver {

namespace {
using namespace tt;  // MEB, LO, GO, Node, Extract
using Params = std::array<double, rod::num_static_parameters>;
}  // namespace

StaticRodModel::StaticRodModel(const rod::StaticProblem& problem, Teuchos::RCP<const mesh::DistributedMesh> mesh)
    : BlockAssemblyModel(std::move(mesh), 12, "traverse static rod"), problem_(problem) {
  if (mesh_->unknowns_per_node() != 12 || mesh_->mesh().num_nodes() != problem_.base.num_cells + 1)
    throw std::invalid_argument("StaticRodModel: the mesh must have num_cells + 1 nodes and 12 unknowns per node");
  const auto comm = mesh_->dof_map()->getComm();
  auto pmap = Teuchos::rcp(new mesh::Map(rod::num_static_parameters, 0, comm, Tpetra::LocallyReplicated));
  p_space_ = Thyra::createVectorSpace<double, LO, GO, Node>(pmap);
  auto names = Teuchos::rcp(new Teuchos::Array<std::string>);
  for (int i = 0; i < rod::num_static_parameters; ++i)
    names->push_back(rod::parameter_name(static_cast<rod::StaticParameter>(i)));
  p_names_ = names;
  const GO n = 12 * static_cast<GO>(problem_.base.num_cells + 1);
  full_map_ = Teuchos::rcp(new mesh::Map(n, 0, comm, Tpetra::LocallyReplicated));
  full_import_ = Teuchos::rcp(new mesh::Import(mesh_->dof_map(), full_map_));
  x0_ = Teuchos::rcp(new Vector(mesh_->dof_map()));
  x0_thyra_ = Thyra::createVector(x0_, x_space_);
  p0_thyra_ = Thyra::createMember(p_space_);
  Rbar_.assign(static_cast<size_t>(mesh_->num_ghosted_nodes()), Mat3::Identity());
  set_problem(problem_);
}

void StaticRodModel::set_problem(const rod::StaticProblem& problem) {
  if (problem.base.num_cells != problem_.base.num_cells)
    throw std::invalid_argument("StaticRodModel::set_problem: the number of cells cannot change");
  problem_ = problem;
  auto p = Extract::getTpetraVector(p0_thyra_);
  auto d = p->getDataNonConst();
  for (int i = 0; i < rod::num_static_parameters; ++i) d[i] = problem_.values[static_cast<size_t>(i)];
}

void StaticRodModel::set_state(const std::vector<rod::StaticNode>& nodes) {
  if (static_cast<int>(nodes.size()) != problem_.base.num_cells + 1)
    throw std::invalid_argument("StaticRodModel::set_state: expected num_cells + 1 nodes");
  const size_t g0 = static_cast<size_t>(mesh_->first_ghosted_node());
  for (size_t k = 0; k < Rbar_.size(); ++k) Rbar_[k] = nodes[g0 + k].Rbar;
  scatter(nodes, *x0_);
}

void StaticRodModel::set_local_state(const std::vector<rod::StaticNode>& ghosted) {
  if (ghosted.size() != Rbar_.size())
    throw std::invalid_argument("StaticRodModel::set_local_state: expected the " + std::to_string(Rbar_.size()) +
                                " ghosted nodes of this rank");
  store_ghosted_nodes(ghosted, *x0_);
}

void StaticRodModel::store_ghosted_nodes(const std::vector<rod::StaticNode>& ghosted, Vector& x) {
  for (size_t k = 0; k < Rbar_.size(); ++k) Rbar_[k] = ghosted[k].Rbar;
  auto d = x.getDataNonConst();
  const size_t skip = static_cast<size_t>(mesh_->first_owned_node() - mesh_->first_ghosted_node());
  for (int k = 0; k < mesh_->num_owned_nodes(); ++k)
    for (int c = 0; c < 12; ++c) d[static_cast<size_t>(12 * k + c)] = ghosted[skip + static_cast<size_t>(k)].x(c);
}

void StaticRodModel::scatter(const std::vector<rod::StaticNode>& nodes, Vector& x) const {
  auto d = x.getDataNonConst();
  const int first = mesh_->first_owned_node();
  for (int k = 0; k < mesh_->num_owned_nodes(); ++k)
    for (int c = 0; c < 12; ++c) d[static_cast<size_t>(12 * k + c)] = nodes[static_cast<size_t>(first + k)].x(c);
}

std::vector<rod::StaticNode> StaticRodModel::gather(const Vector& x) const {
  Vector full(full_map_);
  full.doImport(x, *full_import_, Tpetra::INSERT);
  auto d = full.getData();
  // The frames: each node's from its owner (one sum-reduction of 9 numbers per node).
  const size_t nodes = static_cast<size_t>(problem_.base.num_cells + 1);
  std::vector<double> mine(9 * nodes, 0.0), all(9 * nodes);
  const int first = mesh_->first_owned_node(), skip = first - mesh_->first_ghosted_node();
  for (int k = 0; k < mesh_->num_owned_nodes(); ++k) {
    Eigen::Map<Mat3> frame(&mine[9 * static_cast<size_t>(first + k)]);
    frame = Rbar_[static_cast<size_t>(skip + k)];
  }
  Teuchos::reduceAll<int, double>(*mesh_->dof_map()->getComm(), Teuchos::REDUCE_SUM, static_cast<int>(mine.size()),
                                  mine.data(), all.data());
  std::vector<rod::StaticNode> out(nodes);
  for (size_t j = 0; j < out.size(); ++j) {
    out[j].Rbar = Eigen::Map<const Mat3>(&all[9 * j]);
    for (int c = 0; c < 12; ++c) out[j].x(c) = d[12 * j + static_cast<size_t>(c)];
  }
  return out;
}

std::vector<rod::StaticNode> StaticRodModel::ghosted_nodes(const Vector& x) const {
  auto data = ghosted(x).getData();
  std::vector<rod::StaticNode> nd(static_cast<size_t>(mesh_->num_ghosted_nodes()));
  for (size_t k = 0; k < nd.size(); ++k) {
    nd[k].Rbar = Rbar_[k];
    for (int c = 0; c < 12; ++c) nd[k].x(c) = data[12 * k + static_cast<size_t>(c)];
  }
  return nd;
}

void StaticRodModel::fill(const Vector& x, const rod::StaticModel& m, Kind kind, Vector* f, Matrix* W) const {
  // Each block goes into f and W as it is computed (none is kept: the static start of a long
  // rod would otherwise hold every cell's blocks at once).
  const std::vector<rod::StaticNode> nd = ghosted_nodes(x);
  const int g0 = mesh_->first_ghosted_node();
  auto X = [&](int j) -> const rod::StaticNode& { return nd[static_cast<size_t>(j - g0)]; };
  const int N = m.num_cells;
  const int first = mesh_->first_owned_node(), last = first + mesh_->num_owned_nodes() - 1;
  Scatter scatter(*this, f, W);
  if (kind == Kind::residual_jacobian && first == 0) scatter.add(rod::static_left_block(m, X(0)));
  for (int j = std::max(1, first); j <= std::min(N, last + 1); ++j)
    scatter.add(kind == Kind::mass ? rod::static_mass_block(m, j, X(j - 1), X(j))
                                   : rod::static_cell_block(m, j, X(j - 1), X(j)));
  if (kind == Kind::residual_jacobian && last == N) scatter.add(rod::static_right_block(m, X(N)));
  scatter.finish();
}

void StaticRodModel::fill_model(const Vector& x, const rod::StaticModel& m, Vector* f, Matrix* W) const {
  fill(x, m, Kind::residual_jacobian, f, W);
}

void StaticRodModel::set_fixed_model(const rod::StaticModel& m) {
  if (m.num_cells != problem_.base.num_cells)
    throw std::invalid_argument("StaticRodModel::set_fixed_model: the number of cells cannot change");
  fixed_ = m;
}

void StaticRodModel::fill_jacobian(const Vector& x, const Params& p, Matrix& W) const {
  fill(x, problem_.model(p), Kind::residual_jacobian, nullptr, &W);
}

void StaticRodModel::fill_residual(const Vector& x, const Params& p, Vector& f) const {
  fill(x, problem_.model(p), Kind::residual_jacobian, &f, nullptr);
}

void StaticRodModel::fill_dfdp(const Vector& x, const Params& p, rod::StaticParameter ip, Vector& dfdp) const {
  const std::vector<rod::StaticNode> nd = ghosted_nodes(x);
  const int g0 = mesh_->first_ghosted_node();
  auto X = [&](int j) -> const rod::StaticNode& { return nd[static_cast<size_t>(j - g0)]; };
  const int N = problem_.base.num_cells;
  const int first = mesh_->first_owned_node(), last = first + mesh_->num_owned_nodes() - 1;
  Scatter scatter(*this, &dfdp, nullptr);
  rod::LocalBlock b;
  for (int j = std::max(1, first); j <= std::min(N, last + 1); ++j) {
    b.row = 6 + 12 * static_cast<Eigen::Index>(j - 1);
    b.residual = rod::static_cell_dfdp(problem_, p, ip, j, X(j - 1), X(j));
    scatter.add(b);
  }
  if (first == 0) {
    b.row = 0;
    b.residual = rod::static_end_dfdp(problem_, p, ip, X(0), false);
    scatter.add(b);
  }
  if (last == N) {
    b.row = 12 * static_cast<Eigen::Index>(N) + 6;
    b.residual = rod::static_end_dfdp(problem_, p, ip, X(N), true);
    scatter.add(b);
  }
  scatter.finish();
}

void StaticRodModel::fill_mass(const Vector& x, Matrix& M) const {
  const rod::StaticModel m = problem_.model();
  fill(x, m, Kind::mass, nullptr, &M);
}

Teuchos::RCP<const Thyra::VectorSpaceBase<double>> StaticRodModel::get_p_space(int l) const {
  if (l != 0) throw std::out_of_range("StaticRodModel: only parameter vector 0 exists");
  return p_space_;
}
Teuchos::RCP<const Teuchos::Array<std::string>> StaticRodModel::get_p_names(int l) const {
  if (l != 0) throw std::out_of_range("StaticRodModel: only parameter vector 0 exists");
  return p_names_;
}

Thyra::ModelEvaluatorBase::InArgs<double> StaticRodModel::getNominalValues() const {
  MEB::InArgs<double> in = createInArgs();
  in.set_x(x0_thyra_);
  in.set_p(0, p0_thyra_);
  return in;
}

Thyra::ModelEvaluatorBase::InArgs<double> StaticRodModel::createInArgs() const {
  MEB::InArgsSetup<double> in;
  in.setModelEvalDescription("traverse static rod");
  in.setSupports(MEB::IN_ARG_x);
  in.set_Np(1);
  return std::move(in);
}

Thyra::ModelEvaluatorBase::OutArgs<double> StaticRodModel::createOutArgsImpl() const {
  MEB::OutArgsSetup<double> out = out_args_setup(1);
  out.setSupports(MEB::OUT_ARG_DfDp, 0, MEB::DerivativeSupport(MEB::DERIV_MV_BY_COL));
  return std::move(out);
}

void StaticRodModel::evalModelImpl(const Thyra::ModelEvaluatorBase::InArgs<double>& in,
                                   const Thyra::ModelEvaluatorBase::OutArgs<double>& out) const {
  const Request req = request(in, out);
  Params p = problem_.values;
  if (!in.get_p(0).is_null()) {
    auto pv = Extract::getConstTpetraVector(in.get_p(0));
    auto d = pv->getData();
    for (int i = 0; i < rod::num_static_parameters; ++i) p[static_cast<size_t>(i)] = d[i];
  }
  Matrix* W = req.W_other ? req.W_other : req.W_own || req.want_prec ? W_.get() : nullptr;
  if (req.f || W) fill(*req.x, fixed_ ? *fixed_ : problem_.model(p), Kind::residual_jacobian, req.f.get(), W);
  if (req.want_prec) initialize_prec(out);
  // dF/dp by columns, one per parameter (LOCA::Thyra::Group with implement_dfdp asks for it).
  const Teuchos::RCP<Thyra::MultiVectorBase<double>> dfdp = out.get_DfDp(0).getMultiVector();
  if (!dfdp.is_null()) {
    for (int i = 0; i < static_cast<int>(dfdp->domain()->dim()); ++i)
      fill_dfdp(*req.x, p, static_cast<rod::StaticParameter>(i), *Extract::getTpetraVector(dfdp->col(i)));
  }
}

}  // namespace traverse::solver
